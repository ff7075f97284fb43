// The static solutions of 'flextrack static' as VTU files, one per load case, plus static.pvd
// listing them (ParaView opens it as a series: step k is load case k; apply "Warp By Vector" on
// "displacement" to see the deformed shape).
//   arm:   displacement [m], rotation [rad] and the section forces N, Q_y, Q_z [N], T, M_y, M_z
//          [N m] (section frame; nodal values, averaged where cells meet);
//   solid: displacement [m] and the stresses of fem/solid_stress.h [Pa] (per cell, not averaged).
#pragma once

#include <fem/curved_beam_model.h>
#include <fem/material.h>
#include <fem/solid_model.h>
#include <io/output_folder.h>

#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace flextrack::io
{
/// Removes the static fields of an earlier run (static_*.vtu, static.pvd, section_forces.csv)
/// from @p folder, whose load cases may have had other names.
void remove_static_fields(const std::string &folder);
/// static_NAME.vtu per load case @p names[k] with solution @p u[k], and static.pvd (staged in
/// @p folder). Write errors: InputError naming the file.
void write_static_fields(OutputFolder &folder, const fem::CurvedBeamModel &model, const std::vector<std::string> &names,
                         const std::vector<dealii::Vector<double>> &u, unsigned int subdivisions);
void write_static_fields(OutputFolder &folder, const fem::SolidModel &model, const fem::Material &material,
                         const std::vector<std::string> &names, const std::vector<dealii::Vector<double>> &u,
                         unsigned int subdivisions);
} // namespace flextrack::io
