#include <base/input_error.h>
#include <io/mode_shape_writer.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/mpi.h>
#include <deal.II/numerics/data_out.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace flextrack::io
{
using namespace dealii;

namespace
{
/// Runs @p write on @p file; deal.II throws its own exception when the stream fails (a full disk:
/// "modes" ended as an internal error with deal.II's three paragraphs): the stream is marked
/// failed instead, for check_written.
template <typename Write>
void write_or_mark_failed(std::ofstream &file, const Write &write)
{
  try
    {
      write();
    }
  catch (const ExceptionBase &)
    {
      file.setstate(std::ios::failbit);
    }
}

/// Throws the InputError of OutputFolder's write errors for @p name if @p file failed.
void check_written(const std::ofstream &file, const std::string &name)
{
  if (!file)
    throw InputError("-o / Output/Directory", "cannot write '" + name + "': " +
                                                (errno ? std::strerror(errno) : "write error") +
                                                " (is the disk full or the folder read-only?)");
}
} // namespace

template <int dim>
std::string write_mode_shapes(OutputFolder &folder, const DoFHandler<dim, 3> &dofs,
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
          errno = 0;
          std::ofstream file(folder.add_file(name.str()));
          write_or_mark_failed(file, [&] { out.write_vtu(file); });
          file.close();
          check_written(file, folder.path() + "/" + name.str());
          series.emplace_back(static_cast<double>(k + 1), name.str());
        }
      else
        {
          // Solids may be distributed: every process writes the piece of its cells, and a .pvtu
          // per mode (mode_shapes_NNN.pvtu) collects them. Collective call.
          folder.create();
          try
            {
              series.emplace_back(static_cast<double>(k + 1),
                                  out.write_vtu_with_pvtu_record(folder.path() + "/", "mode_shapes", k + 1,
                                                                 dofs.get_triangulation().get_communicator(), 3));
            }
          catch (const ExceptionBase &)
            {
              remove_mode_shapes(folder.path());
              throw InputError("-o / Output/Directory", "cannot write the mode shapes of mode " + std::to_string(k + 1) +
                                                          " into '" + folder.path() +
                                                          "' (is the disk full or the folder read-only?)");
            }
        }
    }
  const std::string pvd = folder.path() + "/mode_shapes.pvd";
  if (Utilities::MPI::this_mpi_process(dofs.get_triangulation().get_communicator()) == 0)
    {
      errno = 0;
      std::ofstream file(folder.add_file("mode_shapes.pvd"));
      write_or_mark_failed(file, [&] { DataOutBase::write_pvd_record(file, series); });
      file.close();
      check_written(file, pvd);
    }
  return pvd;
}

void remove_mode_shapes(const std::string &folder)
{
  if (!is_first_process()) return;
  std::error_code ec;
  for (const auto &entry : std::filesystem::directory_iterator(folder, ec))
    if (entry.path().filename().string().rfind("mode_shapes", 0) == 0) std::filesystem::remove(entry.path(), ec);
}

template std::string write_mode_shapes<1>(OutputFolder &, const DoFHandler<1, 3> &, const Mapping<1, 3> &,
                                          const std::vector<Vector<double>> &, unsigned int);
template std::string write_mode_shapes<3>(OutputFolder &, const DoFHandler<3, 3> &, const Mapping<3, 3> &,
                                          const std::vector<Vector<double>> &, unsigned int);
} // namespace flextrack::io
