// Mode shapes of an arm as VTU files (one per mode) plus a PVD index that ParaView opens as a
// series: step k is mode k; mass-normalised fields.
#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace flextrack::io
{
/// Writes DIR/mode_shapes.pvd and, per mode, DIR/mode_shapes_NNN.vtu (arms, dim = 1: fields
/// "displacement" and "rotation") or DIR/mode_shapes_NNN.pvtu with one piece per process
/// (solids, dim = 3: "displacement"; a collective call under MPI). Returns the .pvd path.
template <int dim>
std::string write_mode_shapes(const std::string &directory, const dealii::DoFHandler<dim, 3> &dofs,
                              const dealii::Mapping<dim, 3> &mapping,
                              const std::vector<dealii::Vector<double>> &shapes, unsigned int subdivisions);
} // namespace flextrack::io
