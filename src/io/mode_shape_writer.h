// Mode shapes of an arm as VTU files (one per mode) plus a PVD index that ParaView opens as a
// series: step k is mode k; mass-normalised fields.
#pragma once

#include <io/output_folder.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace flextrack::io
{
/// Writes mode_shapes.pvd and, per mode, mode_shapes_NNN.vtu (arms, dim = 1: fields
/// "displacement" and "rotation") or mode_shapes_NNN.pvtu with one piece per process (solids,
/// dim = 3: "displacement"; a collective call under MPI) into @p folder. The arms' files and the
/// .pvd are staged in @p folder (renamed at its commit()); the pieces of a distributed solid are
/// written in place by deal.II. A write error is an InputError naming the file; the pieces
/// already written are then removed. Returns the .pvd path.
template <int dim>
std::string write_mode_shapes(OutputFolder &folder, const dealii::DoFHandler<dim, 3> &dofs,
                              const dealii::Mapping<dim, 3> &mapping,
                              const std::vector<dealii::Vector<double>> &shapes, unsigned int subdivisions);

/// Removes the mode-shape files (mode_shapes*) from @p folder: those of an earlier run, which may
/// have had more modes than this one (first process only).
void remove_mode_shapes(const std::string &folder);
} // namespace flextrack::io
