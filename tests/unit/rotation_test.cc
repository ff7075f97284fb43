// The rotation toolbox (geometry/rotation.h) against closed forms.
#include <geometry/rotation.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace flextrack::geometry;

namespace
{
double distance(const Matrix3 &A, const Matrix3 &B) { return (A - B).norm(); }

Matrix3 about_z(const double angle) // the textbook rotation about z
{
  Matrix3 A;
  A[0][0] = std::cos(angle);
  A[0][1] = -std::sin(angle);
  A[1][0] = std::sin(angle);
  A[1][1] = std::cos(angle);
  A[2][2] = 1;
  return A;
}
} // namespace

TEST(Rotation, skew_matrix_is_the_cross_product)
{
  const Vector3 a({0.3, -1.2, 2.5}), b({-0.7, 0.4, 1.1});
  // Reference: a x b written out component by component (exact in floating point to 1e-15).
  const Vector3 cross({a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]});
  EXPECT_LT((skew(a) * b - cross).norm(), 1e-15);
  EXPECT_LT((axial(skew(a)) - a).norm(), 1e-15);
  EXPECT_EQ(levi_civita(0, 1, 2), 1);
  EXPECT_EQ(levi_civita(1, 0, 2), -1);
  EXPECT_EQ(levi_civita(0, 0, 2), 0);
}

TEST(Rotation, euler_parameters_of_an_axis_angle_give_the_textbook_matrix)
{
  for (const double angle : {0.0, 0.4, 2.0, M_PI, 5.5})
    {
      const auto p = euler_parameters_from_axis_angle(Vector3({0, 0, 2}), angle);
      // Reference: the rotation matrix about z in closed form; tolerance: round-off, 1e-14.
      EXPECT_LT(distance(rotation_matrix(p), about_z(angle)), 1e-14) << "angle " << angle;
      EXPECT_NEAR(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3], 1.0, 1e-15);
    }
  const auto p = euler_parameters_from_rotation_vector(Vector3({0, 0, 0.4}));
  EXPECT_LT(distance(rotation_matrix(p), about_z(0.4)), 1e-14);
}

TEST(Rotation, matrix_to_euler_parameters_round_trip_including_half_turns)
{
  // Axes and angles that exercise every branch of Shepperd's method (half turns about x, y, z
  // and a general axis); A(p(A)) must return A to round-off.
  const Vector3 axes[] = {Vector3({1, 0, 0}), Vector3({0, 1, 0}), Vector3({0, 0, 1}), Vector3({1, -2, 0.5})};
  for (const auto &axis : axes)
    for (const double angle : {0.1, 1.7, M_PI, 4.0})
      {
        const Matrix3 A = rotation_matrix(euler_parameters_from_axis_angle(axis, angle));
        const auto p = euler_parameters_from_matrix(A);
        EXPECT_LT(distance(rotation_matrix(p), A), 1e-14) << "angle " << angle;
        EXPECT_GE(p[0], 0.0);
      }
}

TEST(Rotation, body_angular_velocity_is_twice_G_times_p_dot)
{
  // p(t) = rotation by w t about a fixed axis n: the body angular velocity is w n (closed form).
  // omega = 2 G p' must give it to round-off; and A^T A' = skew(omega) by central differences
  // (h = 1e-6: truncation error ~ h^2 w^3 = 1e-11).
  const Vector3 n = Vector3({1, 2, -2}) / 3.0;
  const double w = 1.3, t = 0.7, h = 1e-6;
  auto p_of = [&](const double time) { return euler_parameters_from_axis_angle(n, w * time); };
  const auto p = p_of(t);
  std::array<double, 4> p_dot;
  for (unsigned int i = 0; i < 4; ++i) p_dot[i] = (p_of(t + h)[i] - p_of(t - h)[i]) / (2 * h);
  const auto G = body_velocity_matrix(p);
  Vector3 omega;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 4; ++j) omega[i] += 2 * G[i][j] * p_dot[j];
  EXPECT_LT((omega - w * n).norm(), 1e-9);
  const Matrix3 A_dot = (rotation_matrix(p_of(t + h)) - rotation_matrix(p_of(t - h))) / (2 * h);
  EXPECT_LT(distance(transpose(rotation_matrix(p)) * A_dot, skew(w * n)), 1e-9);
  // G p = 0: the normalisation has no velocity-level counterpart.
  for (unsigned int i = 0; i < 3; ++i)
    EXPECT_NEAR(G[i][0] * p[0] + G[i][1] * p[1] + G[i][2] * p[2] + G[i][3] * p[3], 0.0, 1e-16);
}
