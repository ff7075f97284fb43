#include <io/mode_shape_writer.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/mpi.h>
#include <deal.II/numerics/data_out.h>

#include <fstream>
#include <iomanip>
#include <sstream>

namespace flextrack::io
{
using namespace dealii;

template <int dim>
std::string write_mode_shapes(const std::string &directory, const DoFHandler<dim, 3> &dofs,
                              const Mapping<dim, 3> &mapping, const std::vector<Vector<double>> &shapes,
                              const unsigned int subdivisions)
{
  std::vector<std::pair<double, std::string>> series;
  std::vector<std::string> names(3, "displacement");
  if (dim == 1) names.insert(names.end(), 3, "rotation");
  const std::vector<DataComponentInterpretation::DataComponentInterpretation> kinds(
    names.size(), DataComponentInterpretation::component_is_part_of_vector);
  for (std::size_t k = 0; k < shapes.size(); ++k)
    {
      DataOut<dim, 3> out;
      out.attach_dof_handler(dofs);
      out.add_data_vector(shapes[k], names, DataOut<dim, 3>::type_dof_data, kinds);
      out.build_patches(mapping, subdivisions, DataOut<dim, 3>::curved_inner_cells);
      DataOutBase::VtkFlags flags(static_cast<double>(k + 1), static_cast<unsigned int>(k + 1));
      flags.compression_level = DataOutBase::VtkFlags::best_speed;
      out.set_flags(flags);
      if (dim == 1)
        {
          // Arms are computed on one process: one .vtu per mode.
          std::ostringstream name;
          name << "mode_shapes_" << std::setw(3) << std::setfill('0') << k + 1 << ".vtu";
          std::ofstream file(directory + "/" + name.str());
          out.write_vtu(file);
          series.emplace_back(static_cast<double>(k + 1), name.str());
        }
      else
        // Solids may be distributed: every process writes the piece of its cells, and a .pvtu
        // per mode (mode_shapes_NNN.pvtu) collects them. Collective call.
        series.emplace_back(static_cast<double>(k + 1),
                            out.write_vtu_with_pvtu_record(directory + "/", "mode_shapes", k + 1,
                                                           dofs.get_triangulation().get_communicator(), 3));
    }
  const std::string pvd = directory + "/mode_shapes.pvd";
  if (Utilities::MPI::this_mpi_process(dofs.get_triangulation().get_communicator()) == 0)
    {
      std::ofstream file(pvd);
      DataOutBase::write_pvd_record(file, series);
    }
  return pvd;
}

template std::string write_mode_shapes<1>(const std::string &, const DoFHandler<1, 3> &, const Mapping<1, 3> &,
                                          const std::vector<Vector<double>> &, unsigned int);
template std::string write_mode_shapes<3>(const std::string &, const DoFHandler<3, 3> &, const Mapping<3, 3> &,
                                          const std::vector<Vector<double>> &, unsigned int);
} // namespace flextrack::io
