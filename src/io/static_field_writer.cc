#include <base/input_error.h>
#include <fem/solid_stress.h>
#include <io/static_field_writer.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/numerics/data_out.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace flextrack::io
{
using namespace dealii;

namespace
{
/// Writes @p out as NAME into @p folder (staged), InputError if the write fails.
template <int dim>
void write_vtu(OutputFolder &folder, DataOut<dim, 3> &out, const std::string &name, const double step)
{
  DataOutBase::VtkFlags flags(step, static_cast<unsigned int>(step));
  flags.compression_level = DataOutBase::VtkFlags::best_speed;
  out.set_flags(flags);
  errno = 0;
  std::ofstream file(folder.add_file(name));
  try
    {
      out.write_vtu(file); // deal.II throws its own exception when the stream fails
    }
  catch (const ExceptionBase &)
    {
      file.setstate(std::ios::failbit);
    }
  file.close();
  if (!file)
    throw InputError("-o / Output/Directory", "cannot write '" + folder.path() + "/" + name + "': " +
                                                (errno ? std::strerror(errno) : "write error") +
                                                " (is the disk full or the folder read-only?)");
}

void write_series(OutputFolder &folder, const std::vector<std::string> &names)
{
  std::vector<std::pair<double, std::string>> series;
  for (std::size_t k = 0; k < names.size(); ++k) series.emplace_back(static_cast<double>(k + 1), "static_" + names[k] + ".vtu");
  errno = 0;
  std::ofstream file(folder.add_file("static.pvd"));
  try
    {
      DataOutBase::write_pvd_record(file, series);
    }
  catch (const ExceptionBase &)
    {
      file.setstate(std::ios::failbit);
    }
  file.close();
  if (!file) throw InputError("-o / Output/Directory", "cannot write '" + folder.path() + "/static.pvd'");
}
} // namespace

void remove_static_fields(const std::string &folder)
{
  std::error_code ec;
  for (const auto &entry : std::filesystem::directory_iterator(folder, ec))
    {
      const std::string name = entry.path().filename().string();
      const bool vtu = name.rfind("static_", 0) == 0 && name.size() > 4 && name.substr(name.size() - 4) == ".vtu";
      if (vtu || name == "static.pvd" || name == "section_forces.csv") std::filesystem::remove(entry.path(), ec);
    }
}

void write_static_fields(OutputFolder &folder, const fem::CurvedBeamModel &model, const std::vector<std::string> &names,
                         const std::vector<Vector<double>> &u, const unsigned int subdivisions)
{
  std::vector<std::string> fields(3, "displacement");
  fields.insert(fields.end(), 3, "rotation");
  std::vector<DataComponentInterpretation::DataComponentInterpretation> kinds(
    6, DataComponentInterpretation::component_is_part_of_vector);
  const std::vector<std::string> forces = {"N", "Q_y", "Q_z", "T", "M_y", "M_z"};
  const std::vector<DataComponentInterpretation::DataComponentInterpretation> scalars(
    6, DataComponentInterpretation::component_is_scalar);
  for (std::size_t k = 0; k < names.size(); ++k)
    {
      const Vector<double> section = model.section_force_field(u[k]);
      DataOut<1, 3> out;
      out.attach_dof_handler(model.dof_handler());
      out.add_data_vector(u[k], fields, DataOut<1, 3>::type_dof_data, kinds);
      out.add_data_vector(section, forces, DataOut<1, 3>::type_dof_data, scalars);
      out.build_patches(model.mapping(), subdivisions, DataOut<1, 3>::curved_inner_cells);
      write_vtu(folder, out, "static_" + names[k] + ".vtu", static_cast<double>(k + 1));
    }
  write_series(folder, names);
}

void write_static_fields(OutputFolder &folder, const fem::SolidModel &model, const fem::Material &material,
                         const std::vector<std::string> &names, const std::vector<Vector<double>> &u,
                         const unsigned int subdivisions)
{
  const fem::StressPostprocessor stresses(material);
  const std::vector<std::string> fields(3, "displacement");
  const std::vector<DataComponentInterpretation::DataComponentInterpretation> kinds(
    3, DataComponentInterpretation::component_is_part_of_vector);
  for (std::size_t k = 0; k < names.size(); ++k)
    {
      DataOut<3> out;
      out.attach_dof_handler(model.dof_handler());
      out.add_data_vector(u[k], fields, DataOut<3>::type_dof_data, kinds);
      out.add_data_vector(u[k], stresses);
      out.build_patches(model.mapping(), subdivisions, DataOut<3>::curved_inner_cells);
      write_vtu(folder, out, "static_" + names[k] + ".vtu", static_cast<double>(k + 1));
    }
  write_series(folder, names);
}
} // namespace flextrack::io
