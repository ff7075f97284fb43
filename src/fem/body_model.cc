#include <fem/body_model.h>
#include <geometry/rotation.h>
#include <fem/csr_matrix.h>
#include <base/input_error.h>
#include <base/memory.h>
#include <base/mpi_session.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/affine_constraints.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>
#include <Epetra_MultiVector.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <sstream>

namespace flextrack::fem
{
using namespace dealii;

namespace
{
/// Coefficients of theta_b in (theta x r)_c, i.e. the matrix -[r x] = -r~.
Tensor<2, 3> cross_matrix_of_rotation(const Tensor<1, 3> &r) { return -geometry::skew(r); }

std::string point_text(const Point<3> &p)
{
  std::ostringstream s;
  s << "(" << p[0] << ", " << p[1] << ", " << p[2] << ") m";
  return s.str();
}
/// y_(g - first) += (A x)_g for this process' rows g of the distributed matrix @p A and @p m
/// vectors: x is whole, indexed by A's column numbers; column k of x at x + k ld_x, of y at
/// y + k ld_y.
void own_rows_multiply(const Epetra_CrsMatrix &A, const double *x, const std::size_t ld_x, const unsigned int m,
                       double *y, const std::size_t ld_y, const std::size_t first = 0)
{
  const int *column_gid = A.ColMap().MyGlobalElements();
  for (int r = 0; r < A.NumMyRows(); ++r)
    {
      int n, *idx;
      double *v;
      A.ExtractMyRowView(r, n, v, idx);
      const std::size_t row = A.RowMap().GID(r) - first;
      for (unsigned int k = 0; k < m; ++k)
        {
          const double *xk = x + k * ld_x;
          double sum = 0;
          for (int e = 0; e < n; ++e) sum += v[e] * xk[column_gid[idx[e]]];
          y[k * ld_y + row] += sum;
        }
    }
}

/// Sends @p outgoing[p] to process p (for every p; emptied here) and returns what the others
/// sent here, one after the other in the order of their ranks. Collective over @p comm.
std::vector<double> send_to_owners(std::vector<std::vector<double>> &outgoing, const MPI_Comm comm)
{
  const std::size_t n = outgoing.size();
  constexpr std::size_t limit = std::numeric_limits<int>::max();
  std::vector<int> send_counts(n), receive_counts(n), send_offsets(n, 0), receive_offsets(n, 0);
  std::size_t send_total = 0;
  for (std::size_t p = 0; p < n; ++p) send_total += outgoing[p].size();
  // Decided on every process alike, so that none throws while the others wait in a collective.
  const auto too_many = [&](const std::size_t here) {
    AssertThrow(Utilities::MPI::max(static_cast<double>(here), comm) < static_cast<double>(limit),
                ExcMessage("the tie regions of this body send too many entries between processes for one MPI "
                           "message; run with fewer processes"));
  };
  too_many(send_total);
  std::vector<double> send;
  send.reserve(send_total);
  for (std::size_t p = 0; p < n; ++p)
    {
      send_counts[p] = static_cast<int>(outgoing[p].size());
      send_offsets[p] = static_cast<int>(send.size());
      send.insert(send.end(), outgoing[p].begin(), outgoing[p].end());
      std::vector<double>().swap(outgoing[p]);
    }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm);
  std::size_t total = 0;
  for (std::size_t p = 0; p < n; ++p)
    {
      receive_offsets[p] = static_cast<int>(std::min(total, limit));
      total += receive_counts[p];
    }
  too_many(total);
  std::vector<double> received(total);
  MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), MPI_DOUBLE, received.data(),
                receive_counts.data(), receive_offsets.data(), MPI_DOUBLE, comm);
  return received;
}
} // namespace

BodyModel::~BodyModel() = default;

BodyModel::BodyModel(const Body &body, const MPI_Comm communicator)
  : description(body), comm(communicator), rank(Utilities::MPI::this_mpi_process(communicator))
{
  // Each arm gets a mesh node at every interface on it; supports stay out of the matrices and
  // are applied with the ties.
  for (unsigned int a = 0; a < body.arms.size(); ++a)
    {
      arms.push_back(std::make_unique<Arm>(body.arms[a]));
      for (const auto *points : {&body.interfaces, &body.output_points})
        for (const auto &p : *points)
          if (p.arm == body.arm_names[a]) arms.back()->supports.push_back({p.s, SupportKind::free});
    }
  unsigned int offset = 0;
  if (body.solid)
    {
      check_memory_for_solid(*body.solid, communicator);
      solid = std::make_unique<SolidModel>(*body.solid, 0, false, true, communicator);
      offset = solid->n_dofs();
    }
  for (const auto &arm : arms)
    {
      arm_models.push_back(std::make_unique<CurvedBeamModel>(*arm, 0, false));
      arm_offsets.push_back(offset);
      offset += arm_models.back()->n_dofs();
    }
  n_full = offset;
  collect_nodes();
  build_constraints();
  distribute_rows();
  condense_matrices();
}

void BodyModel::distribute_rows()
{
  const unsigned int n_processes = Utilities::MPI::n_mpi_processes(comm);
  if (n_processes == 1)
    {
      first_rows = {0, n_body_dofs};
      own_begin = 0;
      own_end = n_body_dofs;
      return;
    }
  first_rows.assign(n_processes + 1, 0);
  if (!solid)
    {
      // Arms only (a small model): equal blocks of rows. The last process condenses the arms and
      // sends the other processes their rows.
      for (unsigned int p = 0; p <= n_processes; ++p)
        first_rows[p] = static_cast<unsigned int>(static_cast<std::uint64_t>(n_body_dofs) * p / n_processes);
      own_begin = first_rows[rank];
      own_end = first_rows[rank + 1];
      return;
    }
  // The solid's own dofs: a contiguous block, the blocks in rank order (the shared
  // triangulation numbers them so). The last process' block of full dofs runs to the end: the
  // arms and the interface and output points.
  const IndexSet &owned = solid->dof_handler().locally_owned_dofs();
  const unsigned int n_own_solid = owned.n_elements();
  const unsigned int first_own_solid = n_own_solid > 0 ? owned.nth_index_in_set(0) : 0;
  AssertThrow(n_own_solid == 0 || owned.is_contiguous(), ExcMessage("the solid's own dofs on a process are not one block"));
  const auto counts = Utilities::MPI::all_gather(comm, n_own_solid);
  const auto firsts = Utilities::MPI::all_gather(comm, first_own_solid);
  std::vector<unsigned int> first_full(n_processes + 1, 0);
  for (unsigned int p = 0; p < n_processes; ++p)
    {
      AssertThrow(counts[p] == 0 || firsts[p] == first_full[p],
                  ExcMessage("the solid's blocks of dofs do not follow the ranks"));
      first_full[p + 1] = first_full[p] + counts[p];
    }
  first_full[n_processes] = n_full;
  // Body dofs keep the order of the full dofs they are: a block of full dofs is a block of rows.
  for (unsigned int p = 0; p <= n_processes; ++p)
    first_rows[p] = std::lower_bound(full_of_column.begin(), full_of_column.end(), first_full[p]) - full_of_column.begin();
  own_begin = first_rows[rank];
  own_end = first_rows[rank + 1];
}

void BodyModel::check_memory_for_solid(const Solid &solid, const MPI_Comm communicator)
{
  // What the model of a solid holds until the factorisation, per solid dof (hex20 links of
  // 8 x 8 x N cells, tests/bench/distributed_reduction.py): the solid's M, the condensed K and
  // M and their clamped copies (each pair on one graph), nodes and constraints, and the
  // workspace of the factor's fill-reducing ordering, which comes first and is the peak.
  // Measured 2026-12-02 (FLEXTRACK_MEMORY_PROBE, "fill-reducing ordering done", less the
  // program's 0.18 GB): 10.25 kB per dof for the 2.4e5-dof body; 7.7 kB once the ordering's
  // workspace is given back (the log's "held then"). Rounded up. The processes of a distributed
  // model share the matrices; each holds the mesh, the nodes and T whole, taken as 1 kB per dof.
  // Other elements couple more or fewer dofs per row: scaled by their typical row length, about
  // 81 entries for hex8, 160 for hex20 (the link above) and 300 for hex27.
  constexpr double bytes_per_hex20_dof = 11000;
  const double bytes_per_dof = bytes_per_hex20_dof * (solid.element == SolidElement::hex8    ? 81.0 / 160
                                                      : solid.element == SolidElement::hex27 ? 300.0 / 160
                                                                                             : 1.0);
  const auto &tria = solid.mesh->triangulation;
  double nodes = tria.n_vertices();
  if (solid.element != SolidElement::hex8) nodes += tria.n_lines();
  if (solid.element == SolidElement::hex27) nodes += tria.n_quads() + tria.n_hexs();
  const double dofs = 3 * nodes;
  const unsigned int n_processes = Utilities::MPI::n_mpi_processes(communicator);
  constexpr double replicated_bytes_per_dof = 1000;
  std::ostringstream what;
  what << "assembling the body model (" << static_cast<std::uint64_t>(dofs) << " solid dofs)";
  if (n_processes == 1)
    base::check_memory_for(what.str(), bytes_per_dof * dofs, nullptr, base::MemoryUse::replicated);
  else
    base::check_memory_for(what.str(), (bytes_per_dof / n_processes + replicated_bytes_per_dof) * dofs, &communicator,
                           base::MemoryUse::shared_factor);
}

void BodyModel::collect_nodes()
{
  if (solid)
    {
      const auto points = solid->support_points();
      const auto &fe = solid->dof_handler().get_fe();
      const unsigned int n_base = fe.base_element(0).n_dofs_per_cell();
      node_of_solid_dof.assign(solid->n_dofs(), -1);
      std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
      for (const auto &cell : solid->dof_handler().active_cell_iterators())
        {
          cell->get_dof_indices(local);
          for (unsigned int k = 0; k < n_base; ++k)
            {
              const auto x_dof = local[fe.component_to_system_index(0, k)];
              if (node_of_solid_dof[x_dof] >= 0) continue;
              Node n;
              n.x = points[x_dof];
              for (unsigned int c = 0; c < 3; ++c)
                {
                  n.u[c] = local[fe.component_to_system_index(c, k)];
                  node_of_solid_dof[n.u[c]] = nodes.size();
                }
              nodes.push_back(n);
            }
        }
    }
  for (unsigned int a = 0; a < arm_models.size(); ++a)
    {
      const auto &model = *arm_models[a];
      const auto &fe = model.dof_handler().get_fe();
      const auto &base = fe.base_element(0);
      std::vector<bool> seen(model.n_dofs(), false);
      std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
      for (const auto &cell : model.dof_handler().active_cell_iterators())
        {
          cell->get_dof_indices(local);
          const auto [s0, s1] = model.mesh_of_arm().cell_arc_lengths(cell);
          for (unsigned int k = 0; k < base.n_dofs_per_cell(); ++k)
            {
              const auto x_dof = local[fe.component_to_system_index(0, k)];
              if (seen[x_dof]) continue;
              seen[x_dof] = true;
              // Exact position on the curve, as the element's geometry is exact.
              double s = s0 + base.get_unit_support_points()[k][0] * (s1 - s0);
              s = std::min(s, model.arm().curve->length());
              Node n;
              n.x = model.arm().curve->position(s);
              for (unsigned int c = 0; c < 3; ++c)
                {
                  n.u[c] = arm_offsets[a] + local[fe.component_to_system_index(c, k)];
                  n.theta[c] = arm_offsets[a] + local[fe.component_to_system_index(3 + c, k)];
                }
              nodes.push_back(n);
            }
        }
    }
}

std::array<unsigned int, 6> BodyModel::arm_node_dofs(const unsigned int a, const double s) const
{
  const auto &model = *arm_models[a];
  const unsigned int vertex = model.mesh_of_arm().vertex_at(s);
  for (const auto &cell : model.dof_handler().active_cell_iterators())
    for (unsigned int v = 0; v < 2; ++v)
      if (cell->vertex_index(v) == vertex)
        {
          std::array<unsigned int, 6> d;
          for (unsigned int c = 0; c < 6; ++c) d[c] = arm_offsets[a] + cell->vertex_dof_index(v, c);
          return d;
        }
  throw std::logic_error("arm vertex not found");
}

std::vector<unsigned int> BodyModel::region_nodes(const NodeRegion &region, const Point<3> &centre,
                                                  const std::string &entry, const std::string &what) const
{
  std::vector<unsigned int> found;
  if (!region.node_set.empty())
    {
      for (const auto &node : description.solid->mesh->node_sets.at(region.node_set))
        {
          const auto d = solid->node_dofs(node);
          if (!d.empty()) found.push_back(node_of_solid_dof[d[0]]);
        }
      std::sort(found.begin(), found.end());
      found.erase(std::unique(found.begin(), found.end()), found.end());
      if (found.empty())
        throw InputError(entry, what + ": node set '" + region.node_set + "' has no node with degrees of freedom");
      check_spread(found, entry, what);
      return found;
    }
  double nearest = std::numeric_limits<double>::max();
  for (unsigned int n = 0; n < nodes.size(); ++n)
    {
      if (nodes[n].theta[0] >= 0) continue; // solid nodes only
      const double d = nodes[n].x.distance(centre);
      nearest = std::min(nearest, d);
      if (d <= region.radius) found.push_back(n);
    }
  if (found.empty())
    {
      std::ostringstream m;
      m << what << ": no node of the solid lies within " << region.radius << " m of " << point_text(centre)
        << " (the nearest is " << nearest << " m away); move the point onto the solid or increase the radius";
      throw InputError(entry, m.str());
    }
  check_spread(found, entry, what);
  return found;
}

void BodyModel::check_spread(const std::vector<unsigned int> &region, const std::string &entry,
                             const std::string &what) const
{
  // Three displacements cannot carry a rotation unless the nodes span a plane: the second
  // moment tensor of their positions about the centroid must be regular.
  Point<3> centre;
  for (const auto n : region) centre += nodes[n].x / static_cast<double>(region.size());
  Tensor<2, 3> A;
  double scale = 0;
  for (const auto n : region)
    {
      const Tensor<1, 3> r = nodes[n].x - centre;
      A += (r * r) * unit_symmetric_tensor<3>() - outer_product(r, r);
      scale = std::max(scale, r.norm_square());
    }
  if (!(std::abs(determinant(A)) > 1e-10 * std::pow(region.size() * scale, 3)))
    throw InputError(entry, what + ": the region holds " + std::to_string(region.size()) +
                              " node(s), all on one line, so it cannot carry a rotation; enlarge the region");
}

namespace
{
/// Rigid spider: every region node's displacement follows the master's rigid motion,
/// u_n = u_m + theta_m x (x_n - x_m). A support (or an earlier tie) of a node wins.
void add_rigid_spider(AffineConstraints<double> &c, const std::vector<BodyModel::Node> &nodes,
                      const std::vector<unsigned int> &region, const std::array<unsigned int, 6> &master,
                      const Point<3> &master_x)
{
  for (const auto n : region)
    {
      const Tensor<2, 3> C = cross_matrix_of_rotation(nodes[n].x - master_x);
      for (unsigned int d = 0; d < 3; ++d)
        {
          const unsigned int slave = nodes[n].u[d];
          if (c.is_constrained(slave)) continue;
          c.add_line(slave);
          c.add_entry(slave, master[d], 1.0);
          for (unsigned int b = 0; b < 3; ++b)
            if (C[d][b] != 0) c.add_entry(slave, master[3 + b], C[d][b]);
        }
    }
}

/// Distributing coupling (RBE3-like): the 6 dofs of a point follow the region,
/// u = mean(u_n) + theta x (x - x_c), theta = A^{-1} sum_n w (r_n x u_n),
/// A = sum_n w (|r_n|^2 1 - r_n r_n^T), r_n = x_n - x_c. Adds no stiffness.
void add_distributing_coupling(AffineConstraints<double> &c, const std::vector<BodyModel::Node> &nodes,
                               const std::vector<unsigned int> &region, const std::array<unsigned int, 6> &point,
                               const Point<3> &x_point)
{
  const double w = 1.0 / region.size();
  Point<3> x_c;
  for (const auto n : region) x_c += w * nodes[n].x;
  Tensor<2, 3> A;
  for (const auto n : region)
    {
      const Tensor<1, 3> r = nodes[n].x - x_c;
      A += w * ((r * r) * unit_symmetric_tensor<3>() - outer_product(r, r));
    }
  const Tensor<2, 3> A_inv = invert(A);
  const Tensor<2, 3> D = cross_matrix_of_rotation(x_point - x_c);
  std::array<std::map<unsigned int, double>, 6> coefficient; // a dof can appear in several terms
  for (const auto n : region)
    {
      // d theta / d u_n = w A^{-1} [r_n x]
      const Tensor<1, 3> r = nodes[n].x - x_c;
      const Tensor<2, 3> G = w * A_inv * (-cross_matrix_of_rotation(r));
      for (unsigned int k = 0; k < 3; ++k) // component k of u_n
        {
          const unsigned int dof = nodes[n].u[k];
          coefficient[k][dof] += w;
          for (unsigned int b = 0; b < 3; ++b)
            {
              coefficient[3 + b][dof] += G[b][k];
              for (unsigned int d = 0; d < 3; ++d) // (theta x (x_point - x_c))_d
                coefficient[d][dof] += D[d][b] * G[b][k];
            }
        }
    }
  for (unsigned int d = 0; d < 6; ++d)
    {
      c.add_line(point[d]);
      for (const auto &[dof, v] : coefficient[d])
        if (v != 0) c.add_entry(point[d], dof, v);
    }
}
} // namespace

std::vector<unsigned int> BodyModel::number_reference_nodes(const std::vector<InterfacePoint> &points)
{
  // Points on the solid get 6 dofs of their own after the solid's and the arms'.
  std::vector<unsigned int> first_dof(points.size(), 0);
  for (unsigned int i = 0; i < points.size(); ++i)
    if (points[i].arm.empty())
      {
        first_dof[i] = n_full;
        n_full += 6;
      }
  return first_dof;
}

void BodyModel::add_supports(AffineConstraints<double> &c) const
{
  auto fix = [&](const unsigned int dof) {
    if (!c.is_constrained(dof)) c.add_line(dof);
  };
  if (solid)
    for (const auto &line : solid->constraints().get_lines()) fix(line.index);
  for (unsigned int a = 0; a < arm_models.size(); ++a)
    for (const auto &line : arm_models[a]->constraints().get_lines()) fix(arm_offsets[a] + line.index);
}

void BodyModel::add_ties(AffineConstraints<double> &c) const
{
  for (const auto &tie : description.ties)
    {
      const unsigned int a = description.arm_index(tie.arm);
      const auto root = arm_node_dofs(a, 0.0);
      const Point<3> x_root = arm_models[a]->arm().curve->position(0.0);
      const std::string what = "tie of arm '" + tie.arm + "' (root at " + point_text(x_root) + ")";
      const auto region = region_nodes(tie.region, x_root, "Body/Ties", what);
      if (tie.kind == TieKind::rigid)
        {
          add_rigid_spider(c, nodes, region, root, x_root);
          continue;
        }
      for (unsigned int d = 0; d < 6; ++d)
        if (c.is_constrained(root[d]))
          throw InputError("Body/Ties", what + ": the arm root is supported; a distributing tie needs it free");
      add_distributing_coupling(c, nodes, region, root, x_root);
    }
}

void BodyModel::add_interfaces(AffineConstraints<double> &c, const std::vector<unsigned int> &first_dof)
{
  for (unsigned int i = 0; i < description.interfaces.size(); ++i)
    {
      const auto &p = description.interfaces[i];
      std::array<unsigned int, 6> dofs;
      Point<3> x;
      if (!p.arm.empty())
        {
          const unsigned int a = description.arm_index(p.arm);
          dofs = arm_node_dofs(a, p.s);
          x = arm_models[a]->arm().curve->position(p.s);
        }
      else
        {
          for (unsigned int d = 0; d < 6; ++d) dofs[d] = first_dof[i] + d;
          x = p.position;
          const std::string what = "interface '" + p.name + "' at " + point_text(x);
          add_rigid_spider(c, nodes, region_nodes(p.region, x, "Body/Interfaces", what), dofs, x);
          Node n;
          n.x = x;
          for (unsigned int d = 0; d < 3; ++d)
            {
              n.u[d] = dofs[d];
              n.theta[d] = dofs[3 + d];
            }
          nodes.push_back(n);
        }
      for (unsigned int d = 0; d < 6; ++d)
        if (c.is_constrained(dofs[d]))
          {
            // Name the support that holds it: a joint at an interface already holds the body
            // there, so the usual fix is to drop the support, not to move the interface.
            std::string fix = "move it, or free what holds it";
            if (!p.arm.empty())
              {
                const auto &arm = description.arms[description.arm_index(p.arm)];
                const double L = arm.curve->length();
                for (std::size_t k = 0; k < arm.supports.size(); ++k)
                  if (arm.supports[k].kind != SupportKind::free && std::abs(arm.supports[k].s - p.s) <= 1e-9 * std::max(L, 1.0))
                    fix = "it is held by the support '" + arm.section_name + "/Supports/" +
                          (k == 0 ? "Start" : k == 1 ? "End" : "Intermediate") +
                          "'. A joint at an interface holds the body there already: set that support to 'free' "
                          "(the default), or move the interface";
              }
            throw InputError("Body/Interfaces", "interface '" + p.name + "' at " + point_text(x) +
                                                  " lies on a support or at the root of a distributing tie, so its "
                                                  "dofs are not free; " + fix);
          }
      interface_full_dofs.push_back(dofs);
      interface_list.push_back({p.name, x, {}});
    }
}

void BodyModel::add_output_points(AffineConstraints<double> &c, const std::vector<unsigned int> &first_dof)
{
  for (unsigned int i = 0; i < description.output_points.size(); ++i)
    {
      const auto &p = description.output_points[i];
      OutputPoint o{p.name, p.position, {}};
      if (!p.arm.empty())
        {
          const unsigned int a = description.arm_index(p.arm);
          o.full_dofs = arm_node_dofs(a, p.s);
          o.position = arm_models[a]->arm().curve->position(p.s);
        }
      else
        {
          for (unsigned int d = 0; d < 6; ++d) o.full_dofs[d] = first_dof[i] + d;
          add_distributing_coupling(c, nodes,
                                    region_nodes(p.region, p.position, "Body/Output points",
                                                 "output point '" + p.name + "' at " + point_text(p.position)),
                                    o.full_dofs, p.position);
        }
      output_list.push_back(o);
    }
}

void BodyModel::add_point_masses()
{
  for (const auto &m : description.point_masses)
    {
      const auto &dofs = interface_full_dofs[description.interface_index(m.interface)];
      for (unsigned int d = 0; d < 3; ++d)
        {
          point_mass_entries.push_back({{{dofs[d], dofs[d]}}, m.mass});
          for (unsigned int e = 0; e < 3; ++e)
            if (m.inertia[d][e] != 0) point_mass_entries.push_back({{{dofs[3 + d], dofs[3 + e]}}, m.inertia[d][e]});
        }
    }
}

void BodyModel::build_transformation(const AffineConstraints<double> &c)
{
  // T: the independent dofs, numbered in order, and every full dof as their combination.
  std::vector<int> column(n_full, -1);
  for (unsigned int i = 0; i < n_full; ++i)
    if (!c.is_constrained(i))
      {
        column[i] = n_body_dofs++;
        full_of_column.push_back(i);
      }
  t_start.assign(1, 0);
  for (unsigned int i = 0; i < n_full; ++i)
    {
      if (column[i] >= 0)
        t_entries.push_back({static_cast<unsigned int>(column[i]), 1.0});
      else if (const auto *line = c.get_constraint_entries(i))
        for (const auto &[j, v] : *line)
          if (v != 0) t_entries.push_back({static_cast<unsigned int>(column[j]), v});
      t_start.push_back(t_entries.size());
    }
  for (unsigned int i = 0; i < interface_list.size(); ++i)
    for (unsigned int d = 0; d < 6; ++d) interface_list[i].dofs[d] = column[interface_full_dofs[i][d]];
}

void BodyModel::build_constraints()
{
  // Full dof numbering: solid, arms, then 6 dofs per interface point and output point on the solid.
  const auto interface_dofs = number_reference_nodes(description.interfaces);
  const auto output_dofs = number_reference_nodes(description.output_points);
  AffineConstraints<double> c;
  add_supports(c);
  supported = c.n_constraints() > 0;
  add_ties(c);
  add_interfaces(c, interface_dofs);
  add_output_points(c, output_dofs);
  add_point_masses();
  c.close();
  build_transformation(c);
}

void BodyModel::condense_matrices()
{
  // T^T A T entry by entry: row i of a part, column j, value v adds v T(i,a) T(j,b) at (a, b).
  // Two passes over the same contributions: the pattern of every condensed row, then the values.
  // K and M share the pattern (point masses add explicit zeros to K).
  // Distributed: each process visits its own rows of the parts and keeps what falls into its
  // own condensed rows; what falls into another process' rows (tie regions, arm roots) is sent
  // there after the first pass, with its values, as (row, column, K, M).
  const unsigned int n_own = own_end - own_begin, n_processes = first_rows.size() - 1;
  std::vector<std::vector<int>> rows(n_own);
  std::vector<std::vector<double>> outgoing(n_processes);
  CsrMatrix K, M;
  bool values_pass = false;
  auto add_row = [&](const unsigned int i, const unsigned int n, const int *cols, const double *kv, const double *mv) {
    for (unsigned int a = t_start[i]; a < t_start[i + 1]; ++a)
      {
        const unsigned int row = t_entries[a].column;
        const bool own = row >= own_begin && row < own_end;
        if (!own && values_pass) continue;
        std::vector<double> *remote = nullptr;
        if (!own)
          remote = &outgoing[std::upper_bound(first_rows.begin(), first_rows.end(), row) - first_rows.begin() - 1];
        for (unsigned int e = 0; e < n; ++e)
          for (unsigned int b = t_start[cols[e]]; b < t_start[cols[e] + 1]; ++b)
            {
              const int col = t_entries[b].column;
              const double t = t_entries[a].value * t_entries[b].value;
              if (remote)
                remote->insert(remote->end(), {double(row), double(col), kv[e] * t, mv[e] * t});
              else if (!values_pass)
                rows[row - own_begin].push_back(col);
              else
                {
                  K.add(row - own_begin, col, kv[e] * t);
                  M.add(row - own_begin, col, mv[e] * t);
                }
            }
      }
  };
  std::vector<double> incoming; // (row, column, K, M) sent here by the other processes
  auto add_part = [&](const TrilinosWrappers::SparseMatrix &Kp, const TrilinosWrappers::SparseMatrix &Mp,
                      const unsigned int offset) {
    const Epetra_CrsMatrix &k = Kp.trilinos_matrix(), &m = Mp.trilinos_matrix();
    std::vector<int> cols;
    std::vector<double> mv;
    for (int r = 0; r < k.NumMyRows(); ++r)
      {
        int nk, nm, *ik, *im;
        double *vk, *vm;
        k.ExtractMyRowView(r, nk, vk, ik);
        m.ExtractMyRowView(r, nm, vm, im);
        // K and M come from one pattern; match M's entries to K's columns all the same.
        cols.resize(nk);
        mv.assign(nk, 0.0);
        for (int e = 0; e < nk; ++e) cols[e] = k.ColMap().GID(ik[e]) + offset;
        for (int e = 0, f = 0; e < nm; ++e)
          {
            while (f < nk && ik[f] != im[e]) ++f;
            AssertThrow(f < nk, ExcMessage("K and M of a part have different sparsity patterns"));
            mv[f] = vm[e];
          }
        add_row(k.RowMap().GID(r) + offset, nk, cols.data(), vk, mv.data());
      }
  };
  for (int pass = 0; pass < 2; ++pass)
    {
      if (solid) add_part(solid->stiffness_matrix(), solid->mass_matrix(), 0);
      if (holds_arms())
        {
          for (unsigned int a = 0; a < arm_models.size(); ++a)
            add_part(arm_models[a]->stiffness_matrix(), arm_models[a]->mass_matrix(), arm_offsets[a]);
          for (const auto &[ij, value] : point_mass_entries)
            {
              const int col = ij[1];
              const double zero = 0.0;
              add_row(ij[0], 1, &col, &zero, &value);
            }
        }
      if (pass == 0)
        {
          if (n_processes > 1) incoming = send_to_owners(outgoing, comm);
          for (std::size_t e = 0; e < incoming.size(); e += 4)
            rows[static_cast<unsigned int>(incoming[e]) - own_begin].push_back(static_cast<int>(incoming[e + 1]));
          K = CsrMatrix(std::move(rows));
          M = K;
          values_pass = true;
        }
    }
  for (std::size_t e = 0; e < incoming.size(); e += 4)
    {
      const unsigned int row = static_cast<unsigned int>(incoming[e]) - own_begin;
      K.add(row, static_cast<int>(incoming[e + 1]), incoming[e + 2]);
      M.add(row, static_cast<int>(incoming[e + 1]), incoming[e + 3]);
    }
  // The solid's K is not needed any more (its M is: full_mass_multiply); M keeps the graph they
  // share. One copy at a time: a large body's matrices are most of its memory.
  if (solid) solid->release_stiffness();
  if (n_processes > 1)
    K.to_trilinos(stiffness, own_begin, n_body_dofs, comm);
  else
    K.to_trilinos(stiffness);
  K = CsrMatrix();
  M.to_trilinos_on_graph_of(stiffness, mass, own_begin);
  M = CsrMatrix();
  // Distributed: the passes' work space back to the system before the factorisation (one
  // process reuses it for the clamped copies, and pays for fresh pages otherwise).
  if (n_processes > 1) base::release_free_heap();
  base::probe_memory("body K and M condensed");
}

void BodyModel::body_vmult(const TrilinosWrappers::SparseMatrix &A, Vector<double> &dst, const Vector<double> &src) const
{
  dst.reinit(n_body_dofs);
  if (!distributed())
    {
      A.vmult(dst, src);
      return;
    }
  const Epetra_CrsMatrix &a = A.trilinos_matrix();
  std::vector<double> own(own_end - own_begin, 0.0);
  own_rows_multiply(a, src.begin(), src.size(), 1, own.data(), own.size(), own_begin);
  std::vector<int> counts(first_rows.size() - 1), offsets(first_rows.size() - 1);
  for (std::size_t p = 0; p + 1 < first_rows.size(); ++p)
    {
      counts[p] = static_cast<int>(first_rows[p + 1] - first_rows[p]);
      offsets[p] = static_cast<int>(first_rows[p]);
    }
  MPI_Allgatherv(own.data(), static_cast<int>(own.size()), MPI_DOUBLE, dst.begin(), counts.data(), offsets.data(),
                 MPI_DOUBLE, comm);
}

void BodyModel::stiffness_vmult(Vector<double> &dst, const Vector<double> &src) const { body_vmult(stiffness, dst, src); }

void BodyModel::mass_vmult(Vector<double> &dst, const Vector<double> &src) const { body_vmult(mass, dst, src); }

Vector<double> BodyModel::expand(const Vector<double> &y) const
{
  Vector<double> x(n_full);
  for (unsigned int i = 0; i < n_full; ++i)
    for (unsigned int a = t_start[i]; a < t_start[i + 1]; ++a) x[i] += t_entries[a].value * y[t_entries[a].column];
  return x;
}

Vector<double> BodyModel::condense(const Vector<double> &f) const
{
  Vector<double> g(n_body_dofs);
  for (unsigned int i = 0; i < n_full; ++i)
    if (f[i] != 0)
      for (unsigned int a = t_start[i]; a < t_start[i + 1]; ++a) g[t_entries[a].column] += t_entries[a].value * f[i];
  return g;
}

void BodyModel::full_mass_vmult(Vector<double> &dst, const Vector<double> &src) const
{
  dst.reinit(n_full);
  full_mass_multiply(src.begin(), 1, dst.begin());
}

void BodyModel::full_mass_multiply(const double *X, const unsigned int m, double *Y) const
{
  const std::size_t size = static_cast<std::size_t>(n_full) * m;
  std::fill(Y, Y + size, 0.0);
  auto part = [&](const TrilinosWrappers::SparseMatrix &M, const unsigned int offset) {
    const Epetra_CrsMatrix &A = M.trilinos_matrix();
    // Views of the part's rows of X and Y (leading dimension n_full).
    Epetra_MultiVector x(View, A.DomainMap(), const_cast<double *>(X) + offset, n_full, m);
    Epetra_MultiVector y(View, A.RangeMap(), Y + offset, n_full, m);
    AssertThrow(A.Multiply(false, x, y) == 0, ExcMessage("Epetra multiply failed"));
  };
  // Distributed: each process computes the solid's rows it owns, the last one also the arms and
  // point masses; every row is computed once, so a sum over the processes gathers them.
  if (solid)
    {
      if (distributed())
        own_rows_multiply(solid->mass_matrix().trilinos_matrix(), X, n_full, m, Y, n_full);
      else
        part(solid->mass_matrix(), 0);
    }
  if (holds_arms())
    {
      for (unsigned int a = 0; a < arm_models.size(); ++a) part(arm_models[a]->mass_matrix(), arm_offsets[a]);
      add_point_masses_product(X, m, Y);
    }
  if (distributed())
    for (std::size_t begin = 0; begin < size; begin += 1u << 28)
      MPI_Allreduce(MPI_IN_PLACE, Y + begin, static_cast<int>(std::min<std::size_t>(size - begin, 1u << 28)),
                    MPI_DOUBLE, MPI_SUM, comm);
}

void BodyModel::add_point_masses_product(const double *X, const unsigned int m, double *Y) const
{
  for (unsigned int k = 0; k < m; ++k)
    for (const auto &[ij, value] : point_mass_entries)
      Y[static_cast<std::size_t>(k) * n_full + ij[0]] += value * X[static_cast<std::size_t>(k) * n_full + ij[1]];
}

std::array<Vector<double>, 6> BodyModel::rigid_body_modes() const
{
  // Rigid motions satisfy every constraint, so their values at the independent dofs define
  // them: set them on the full nodes and keep the independent entries.
  std::array<Vector<double>, 6> r;
  for (unsigned int k = 0; k < 6; ++k)
    {
      Vector<double> x(n_full);
      for (const auto &n : nodes)
        {
          Tensor<1, 3> u;
          if (k < 3)
            u[k] = 1;
          else
            u = cross_product_3d(Tensor<1, 3>(Point<3>::unit_vector(k - 3)), Tensor<1, 3>(n.x));
          for (unsigned int d = 0; d < 3; ++d)
            {
              x[n.u[d]] = u[d];
              if (n.theta[d] >= 0) x[n.theta[d]] = k >= 3 && d == k - 3;
            }
        }
      r[k].reinit(n_body_dofs);
      for (unsigned int j = 0; j < n_body_dofs; ++j) r[k][j] = x[full_of_column[j]];
    }
  return r;
}

Vector<double> BodyModel::arm_point_load(const unsigned int a, const double s, const Tensor<1, 3> &F) const
{
  const Vector<double> f_arm = arm_models[a]->point_load(s, F);
  Vector<double> f(n_full);
  for (unsigned int i = 0; i < f_arm.size(); ++i) f[arm_offsets[a] + i] = f_arm[i];
  return condense(f);
}

Tensor<1, 3> BodyModel::arm_displacement(const unsigned int a, const double s, const Vector<double> &y) const
{
  const Vector<double> x = expand(y);
  Vector<double> u(arm_models[a]->n_dofs());
  for (unsigned int i = 0; i < u.size(); ++i) u[i] = x[arm_offsets[a] + i];
  return arm_models[a]->displacement_at(s, u);
}
} // namespace flextrack::fem
