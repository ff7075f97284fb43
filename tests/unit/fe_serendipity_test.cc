// The 20-node serendipity hexahedron: interpolation properties and conformity.
#include <fem/fe_serendipity.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <gtest/gtest.h>

using namespace dealii;
using flextrack::fem::FE_Serendipity;
using flextrack::fem::SerendipityPolynomials;

namespace
{
// Points spread over the unit cube, including its corners and faces.
std::vector<Point<3>> sample_points()
{
  std::vector<Point<3>> p;
  for (double x : {0.0, 0.13, 0.5, 0.77, 1.0})
    for (double y : {0.0, 0.31, 0.66, 1.0})
      for (double z : {0.0, 0.2, 0.9, 1.0}) p.emplace_back(x, y, z);
  return p;
}
} // namespace

TEST(FE_Serendipity, shape_functions_form_a_partition_of_unity)
{
  // Exact property of the serendipity basis (sum N_i = 1): 1e-14.
  const FE_Serendipity<3> fe;
  for (const auto &p : sample_points())
    {
      double sum = 0;
      Tensor<1, 3> grad;
      for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
        {
          sum += fe.shape_value(i, p);
          grad += fe.shape_grad(i, p);
        }
      EXPECT_NEAR(sum, 1.0, 1e-14);
      EXPECT_NEAR(grad.norm(), 0.0, 1e-13);
    }
}

TEST(FE_Serendipity, shape_functions_are_one_at_their_node_and_zero_at_the_others)
{
  // Kronecker property N_i(x_j) = delta_ij at the 20 nodes (8 vertices, 12 mid-edges): 1e-15.
  const FE_Serendipity<3> fe;
  ASSERT_EQ(fe.n_dofs_per_cell(), 20u);
  ASSERT_EQ(fe.n_dofs_per_vertex(), 1u);
  ASSERT_EQ(fe.n_dofs_per_line(), 1u);
  ASSERT_EQ(fe.n_dofs_per_quad(0), 0u);
  const auto nodes = SerendipityPolynomials::nodes();
  for (unsigned int i = 0; i < 20; ++i)
    for (unsigned int j = 0; j < 20; ++j)
      EXPECT_NEAR(fe.shape_value(i, nodes[j]), i == j ? 1.0 : 0.0, 1e-15) << "N_" << i << "(x_" << j << ")";
}

TEST(FE_Serendipity, interpolation_reproduces_the_serendipity_space)
{
  // The 20-node space (Zienkiewicz & Taylor, The FEM vol. 1, sec. 6.7) contains every
  // quadratic, the cubics x^2 y-type and xyz, and x^2 yz-type quartics: their nodal interpolants
  // are exact (1e-13), values and gradients. x^2 y^2 is not in the space: it must not be.
  const FE_Serendipity<3> fe;
  const auto nodes = SerendipityPolynomials::nodes();
  using F = std::function<double(const Point<3> &)>;
  const std::vector<std::pair<std::string, F>> in_space = {
    {"1 + 2x - y + 3z", [](const Point<3> &p) { return 1 + 2 * p[0] - p[1] + 3 * p[2]; }},
    {"x^2 - 3 y z + z^2 + x y", [](const Point<3> &p) { return p[0] * p[0] - 3 * p[1] * p[2] + p[2] * p[2] + p[0] * p[1]; }},
    {"x^2 y + y^2 z - z^2 x", [](const Point<3> &p) { return p[0] * p[0] * p[1] + p[1] * p[1] * p[2] - p[2] * p[2] * p[0]; }},
    {"x y z", [](const Point<3> &p) { return p[0] * p[1] * p[2]; }},
    {"x^2 y z", [](const Point<3> &p) { return p[0] * p[0] * p[1] * p[2]; }}};
  for (const auto &[name, f] : in_space)
    for (const auto &p : sample_points())
      {
        double v = 0;
        for (unsigned int i = 0; i < 20; ++i) v += f(nodes[i]) * fe.shape_value(i, p);
        EXPECT_NEAR(v, f(p), 1e-13) << name << " at " << p;
      }
  const Point<3> centre(0.5, 0.5, 0.5);
  double v = 0;
  for (unsigned int i = 0; i < 20; ++i) v += std::pow(nodes[i][0] * nodes[i][1], 2) * fe.shape_value(i, centre);
  EXPECT_GT(std::abs(v - std::pow(0.25, 2)), 1e-3) << "x^2 y^2 is not a serendipity function";
}

TEST(FE_Serendipity, interpolated_fields_are_continuous_across_faces_in_any_orientation)
{
  // A Moebius band of hexahedra: at its seam the shared faces have non-standard orientations.
  // Interpolate a field outside the space; its traces from both sides must coincide on every
  // interior face (H1 conformity), to 1e-13.
  Triangulation<3> tria;
  GridGenerator::moebius(tria, 8, 1, 2.0, 0.5); // a twisted ring: faces meet in many orientations
  DoFHandler<3> dofs(tria);
  FESystem<3> fe(FE_Serendipity<3>(), 1);
  dofs.distribute_dofs(fe);
  Vector<double> u(dofs.n_dofs());
  const MappingQ<3> mapping(1);
  VectorTools::interpolate(mapping, dofs, ScalarFunctionFromFunctionObject<3>([](const Point<3> &p) {
                             return std::sin(p[0]) * std::exp(p[1]) + p[2] * p[2] * p[0] * p[1];
                           }),
                           u);
  const QGauss<2> face_rule(4);
  FEFaceValues<3> here(mapping, fe, face_rule, update_values | update_quadrature_points);
  FEFaceValues<3> there(mapping, fe, face_rule, update_values | update_quadrature_points);
  unsigned int checked = 0;
  for (const auto &cell : dofs.active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (!cell->at_boundary(f))
        {
          const auto neighbor = cell->neighbor(f);
          const unsigned int nf = cell->neighbor_of_neighbor(f);
          here.reinit(cell, f);
          there.reinit(neighbor, nf);
          std::vector<double> a(face_rule.size()), b(face_rule.size());
          here.get_function_values(u, a);
          there.get_function_values(u, b);
          for (unsigned int q = 0; q < face_rule.size(); ++q)
            {
              // Match quadrature points by position (orientations may differ).
              unsigned int r = 0;
              while (r < face_rule.size() && here.quadrature_point(q).distance(there.quadrature_point(r)) > 1e-10) ++r;
              ASSERT_LT(r, face_rule.size()) << "face points do not match";
              EXPECT_NEAR(a[q], b[r], 1e-13);
            }
          ++checked;
        }
  EXPECT_GT(checked, 0u);
}
