// Rigid-body inertia of FE models against closed forms (first check of issue 4).
#include <fem/solid_mesh.h>
#include <io/arm_scene.h>
#include <reduction/rigid_body_inertia.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace flextrack;

TEST(RigidBodyInertia, box_matches_the_closed_form)
{
  // Homogeneous box a x b x c, density rho: m = rho a b c, centre at the middle,
  // J = m/12 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2) (any dynamics text). hex20, 4 x 3 x 2 cells:
  // the consistent mass integrates the rigid motions exactly: 1e-10 relative (issue 4).
  const double a = 1.2, b = 0.5, c = 0.3, rho = 7850, m = rho * a * b * c;
  fem::Solid box;
  box.mesh = fem::generate_box(dealii::Point<3>(a, b, c), {{4, 3, 2}});
  box.material.density = rho;
  const auto I = reduction::rigid_body_inertia(box);
  EXPECT_NEAR(I.mass, m, 1e-10 * m);
  EXPECT_NEAR(I.centre_of_mass.distance(dealii::Point<3>(a / 2, b / 2, c / 2)), 0.0, 1e-10 * a);
  const double J[3] = {m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12};
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      EXPECT_NEAR(I.inertia_about_centre[i][j], i == j ? J[i] : 0.0, 1e-10 * J[0]) << i << j;
}

TEST(RigidBodyInertia, straight_arm_matches_the_closed_form)
{
  // Straight rod along x, length L, square section h x h: the beam's mass rho A L and its
  // inertia about the centre m L^2 / 12 (bending axes) plus the section's rho I L; about the axis
  // rho Ip L. Equal to the solid cuboid's m (L^2 + h^2) / 12 and m h^2 / 6: 1e-12 relative.
  const double L = 2, h = 0.05, rho = 7850, m = rho * h * h * L;
  dealii::ParameterHandler prm;
  io::declare_arm_scene(prm);
  const auto scene = io::read_arm_scene_from_string(
    "subsection Arm\n subsection Curve\n  set Kind = line\n  subsection Line\n   set Start point = 1, 2, 3\n"
    "   set End point = 3, 2, 3\n  end\n end\n subsection Cross section\n  set Shape = rectangle\n"
    "  set Width = 0.05\n  set Height = 0.05\n end\n subsection Mesh\n  set Number of elements = 4\n end\nend\n",
    prm);
  const auto I = reduction::rigid_body_inertia(scene.arm);
  EXPECT_NEAR(I.mass, m, 1e-12 * m);
  EXPECT_NEAR(I.centre_of_mass.distance(dealii::Point<3>(2, 2, 3)), 0.0, 1e-12);
  EXPECT_NEAR(I.inertia_about_centre[0][0], m * h * h / 6, 1e-12 * m * h * h);
  EXPECT_NEAR(I.inertia_about_centre[1][1], m * (L * L + h * h) / 12, 1e-12 * m * L * L);
  EXPECT_NEAR(I.inertia_about_centre[2][2], m * (L * L + h * h) / 12, 1e-12 * m * L * L);
  EXPECT_NEAR(I.inertia_about_centre[0][1], 0.0, 1e-12 * m * L * L);
}

TEST(RigidBodyInertia, thin_ring_converges_to_the_closed_form)
{
  // Thin circular ring, radius R, in the plane z = 0: m = 2 pi R rho A, centre at the origin,
  // J_zz = m R^2, J_xx = J_yy = m R^2 / 2, plus the sections' own rotary inertia: about z every
  // section turns about its bending axis (rho I per length), about x half of them about the
  // tangent (rho I_p = 2 rho I) and half about the bending axis, rho (I + I_p) / 2 on average.
  // Curved arms carry the interpolation error of the rigid rotation: 64 cubic elements, 1e-8.
  const double R = 1, d = 0.01, rho = 7850, A = M_PI * d * d / 4, I = M_PI * std::pow(d, 4) / 64;
  const double m = 2 * M_PI * R * rho * A;
  dealii::ParameterHandler prm;
  io::declare_arm_scene(prm);
  const auto scene = io::read_arm_scene_from_string(
    "subsection Arm\n subsection Curve\n  set Kind = arc\n  subsection Arc\n   set Radius = 1\n"
    "   set Angle = 6.283185307179586\n  end\n end\n subsection Cross section\n  set Shape = circle\n"
    "  set Diameter = 0.01\n end\n subsection Mesh\n  set Number of elements = 64\n  set Element degree = 3\n"
    " end\nend\n",
    prm);
  const auto J = reduction::rigid_body_inertia(scene.arm);
  EXPECT_NEAR(J.mass, m, 1e-12 * m);
  EXPECT_NEAR(J.centre_of_mass.norm(), 0.0, 1e-10);
  // J_zz = m R^2 + rho 2 pi R I_p (the section turns about its own y/z axes around z).
  EXPECT_NEAR(J.inertia_about_centre[2][2], m * R * R + rho * 2 * M_PI * R * I, 1e-8 * m * R * R);
  EXPECT_NEAR(J.inertia_about_centre[0][0], m * R * R / 2 + rho * 2 * M_PI * R * (I + 2 * I) / 2, 1e-8 * m * R * R);
}
