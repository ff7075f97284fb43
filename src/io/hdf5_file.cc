#include <io/hdf5_file.h>

#include <sys/resource.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace flextrack::io
{
namespace
{
std::string shape_text(const std::vector<hsize_t> &shape)
{
  std::ostringstream s;
  s << "[";
  for (unsigned int i = 0; i < shape.size(); ++i) s << (i ? ", " : "") << shape[i];
  s << "]";
  return s.str();
}

/// Closes an HDF5 handle when it goes out of scope.
struct Handle
{
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle()
  {
    if (id >= 0) close(id);
  }
};
} // namespace

Hdf5File::Hdf5File(const std::string &name, const Mode open_mode) : file_name(name), mode(open_mode)
{
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // errors are reported by exceptions
  if (mode == Mode::create)
    {
      // The file is built in memory (HDF5's core driver, no backing store) and written to disk by
      // close() with ordinary, checked writes: a full disk then never reaches HDF5, whose library
      // keeps a file that failed to flush open and crashes on it at exit (HDF5 1.10).
      Handle fapl{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
      if (fapl.id < 0 || H5Pset_fapl_core(fapl.id, 1 << 20, false) < 0)
        throw std::runtime_error("cannot set up an HDF5 file in memory");
      file = H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.id);
      if (file < 0) throw std::runtime_error("cannot create the HDF5 file");
    }
  else if (mode == Mode::create_on_disk)
    {
      // The 1.8 file format at least: its dense attribute storage holds attributes beyond the
      // 64 KiB of an object header (the column names of a scene with hundreds of joints).
      Handle fapl{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
      if (fapl.id < 0 || H5Pset_libver_bounds(fapl.id, H5F_LIBVER_V18, H5F_LIBVER_LATEST) < 0)
        throw std::runtime_error("cannot set up the HDF5 file");
      file = H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.id);
      if (file < 0) throw std::runtime_error("cannot create the HDF5 file");
    }
  else
    {
      if (H5Fis_hdf5(name.c_str()) <= 0) throw std::runtime_error("not an HDF5 file (or a damaged one)");
      file = H5Fopen(name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      if (file < 0) throw std::runtime_error("the HDF5 file cannot be opened (damaged or truncated)");
    }
}

Hdf5File::~Hdf5File()
{
  if (file >= 0) H5Fclose(file);
}

void Hdf5File::close()
{
  if (file < 0) return;
  if (mode == Mode::create_on_disk)
    {
      require_free_space(1 << 20); // HDF5's metadata, written by the flush
      const bool flushed = H5Fflush(file, H5F_SCOPE_GLOBAL) >= 0;
      const bool closed = H5Fclose(file) >= 0;
      file = -1;
      if (!flushed || !closed) throw std::runtime_error("writing '" + file_name + "' failed (is the disk full?)");
      return;
    }
  // The image of the in-memory file, then one checked write of it (see the constructor).
  const bool flushed = H5Fflush(file, H5F_SCOPE_GLOBAL) >= 0;
  const ssize_t size = flushed ? H5Fget_file_image(file, nullptr, 0) : -1;
  std::vector<char> image(size > 0 ? static_cast<std::size_t>(size) : 0);
  const bool copied = size > 0 && H5Fget_file_image(file, image.data(), image.size()) == size;
  H5Fclose(file);
  file = -1;
  if (!copied) throw std::runtime_error("HDF5 could not finish the file '" + file_name + "' in memory");
  errno = 0;
  std::ofstream out(file_name, std::ios::binary | std::ios::trunc);
  out.write(image.data(), static_cast<std::streamsize>(image.size()));
  out.close();
  if (!out)
    throw std::runtime_error("writing '" + file_name + "' failed: " + std::strerror(errno ? errno : EIO) +
                             " (is the disk full?)");
}

void Hdf5File::require_free_space(const std::uintmax_t bytes) const
{
  // Twice the bytes and 16 MiB to spare: chunks, their index and the metadata HDF5 adds.
  const std::uintmax_t needed = 2 * bytes + (std::uintmax_t(16) << 20);
  std::error_code error;
  const auto space = std::filesystem::space(std::filesystem::path(file_name).parent_path().empty()
                                              ? std::filesystem::path(".")
                                              : std::filesystem::path(file_name).parent_path(),
                                            error);
  if (!error && space.available < needed)
    throw std::runtime_error("writing '" + file_name + "' stopped: " + std::to_string(space.available >> 20) +
                             " MiB left on its disk (is the disk full?)");
  // A file size limit (ulimit -f) is met like a full disk.
  rlimit limit{};
  if (getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    {
      std::error_code size_error;
      const auto size = std::filesystem::file_size(file_name, size_error);
      if (!size_error && size + needed > limit.rlim_cur)
        throw std::runtime_error("writing '" + file_name + "' stopped: the file would exceed the file size limit of " +
                                 std::to_string(limit.rlim_cur) + " bytes (ulimit -f)");
    }
}

void Hdf5File::create_growing(const std::string &path, const hsize_t columns, const hsize_t expected_rows)
{
  const int rank = columns == 0 ? 1 : 2;
  const hsize_t dims[2] = {0, columns}, max_dims[2] = {H5S_UNLIMITED, columns};
  const hsize_t rows = std::clamp<hsize_t>(std::min<hsize_t>(expected_rows, 8192 / std::max<hsize_t>(1, columns)), 1, 8192);
  const hsize_t chunk[2] = {rows, std::max<hsize_t>(1, columns)};
  Handle space{H5Screate_simple(rank, dims, max_dims), H5Sclose};
  Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  H5Pset_obj_track_times(dcpl.id, false);
  if (H5Pset_chunk(dcpl.id, rank, chunk) < 0 || (mode == Mode::create_on_disk && H5Pset_attr_phase_change(dcpl.id, 0, 0) < 0))
    throw std::runtime_error("cannot set up dataset '" + path + "'");
  Handle set{H5Dcreate2(file, path.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT), H5Dclose};
  if (set.id < 0) throw std::runtime_error("cannot create dataset '" + path + "'");
}

void Hdf5File::append_rows(const std::string &path, const hsize_t n_rows, const double *data)
{
  if (n_rows == 0) return;
  Handle set{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  if (set.id < 0) throw std::runtime_error("there is no dataset '" + path + "'");
  Handle old_space{H5Dget_space(set.id), H5Sclose};
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_ndims(old_space.id);
  if (rank < 1 || rank > 2) throw std::runtime_error("dataset '" + path + "' does not grow by rows");
  H5Sget_simple_extent_dims(old_space.id, dims, nullptr);
  const hsize_t columns = rank == 2 ? dims[1] : 1;
  if (mode == Mode::create_on_disk) require_free_space(n_rows * columns * sizeof(double));
  const hsize_t start[2] = {dims[0], 0}, count[2] = {n_rows, columns};
  dims[0] += n_rows;
  if (H5Dset_extent(set.id, dims) < 0) throw std::runtime_error("cannot extend dataset '" + path + "'");
  Handle file_space{H5Dget_space(set.id), H5Sclose};
  Handle memory_space{H5Screate_simple(rank, count, nullptr), H5Sclose};
  if (H5Sselect_hyperslab(file_space.id, H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 ||
      H5Dwrite(set.id, H5T_NATIVE_DOUBLE, memory_space.id, file_space.id, H5P_DEFAULT, data) < 0)
    throw std::runtime_error("cannot write dataset '" + path + "'");
}

void Hdf5File::create_group(const std::string &path)
{
  Handle gcpl{H5Pcreate(H5P_GROUP_CREATE), H5Pclose};
  H5Pset_obj_track_times(gcpl.id, false);
  Handle g{H5Gcreate2(file, path.c_str(), H5P_DEFAULT, gcpl.id, H5P_DEFAULT), H5Gclose};
  if (g.id < 0) throw std::runtime_error("cannot create group '" + path + "'");
}

void Hdf5File::write_raw(const std::string &path, const std::vector<hsize_t> &shape, const hid_t file_type,
                         const hid_t memory_type, const void *data)
{
  Handle space{H5Screate_simple(shape.size(), shape.data(), nullptr), H5Sclose};
  Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  H5Pset_obj_track_times(dcpl.id, false);
  Handle set{H5Dcreate2(file, path.c_str(), file_type, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT), H5Dclose};
  if (set.id < 0) throw std::runtime_error("cannot create dataset '" + path + "'");
  hsize_t size = 1;
  for (const auto s : shape) size *= s;
  if (size > 0 && H5Dwrite(set.id, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error("cannot write dataset '" + path + "'");
}

void Hdf5File::write(const std::string &path, const std::vector<hsize_t> &shape, const double *data)
{
  write_raw(path, shape, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data);
}

void Hdf5File::write(const std::string &path, const std::vector<hsize_t> &shape, const unsigned int *data)
{
  write_raw(path, shape, H5T_STD_U32LE, H5T_NATIVE_UINT, data);
}

void Hdf5File::set_attribute(const std::string &object, const std::string &name, const std::string &value)
{
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, std::max<size_t>(1, value.size()));
  H5Tset_strpad(type.id, H5T_STR_NULLPAD);
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle a{H5Acreate_by_name(file, object.c_str(), name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  const std::string padded = value.empty() ? std::string(1, '\0') : value;
  if (a.id < 0 || H5Awrite(a.id, type.id, padded.data()) < 0)
    throw std::runtime_error("cannot write attribute '" + name + "' of '" + object + "'");
}

void Hdf5File::set_attribute(const std::string &object, const std::string &name, const std::vector<std::string> &values)
{
  std::size_t width = 1;
  for (const auto &v : values) width = std::max(width, v.size());
  std::string packed(width * values.size(), '\0');
  for (std::size_t i = 0; i < values.size(); ++i) packed.replace(i * width, values[i].size(), values[i]);
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, width);
  H5Tset_strpad(type.id, H5T_STR_NULLPAD);
  const hsize_t n = values.size();
  Handle space{H5Screate_simple(1, &n, nullptr), H5Sclose};
  Handle a{H5Acreate_by_name(file, object.c_str(), name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  if (a.id < 0 || (n > 0 && H5Awrite(a.id, type.id, packed.data()) < 0))
    throw std::runtime_error("cannot write attribute '" + name + "' of '" + object + "'");
}

void Hdf5File::set_attribute(const std::string &object, const std::string &name, const long long value)
{
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle a{H5Acreate_by_name(file, object.c_str(), name.c_str(), H5T_STD_I64LE, space.id, H5P_DEFAULT, H5P_DEFAULT,
                             H5P_DEFAULT),
           H5Aclose};
  if (a.id < 0 || H5Awrite(a.id, H5T_NATIVE_LLONG, &value) < 0)
    throw std::runtime_error("cannot write attribute '" + name + "' of '" + object + "'");
}

void Hdf5File::write_text(const std::string &path, const std::string &text)
{
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, std::max<size_t>(1, text.size()));
  H5Tset_strpad(type.id, H5T_STR_NULLPAD);
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  H5Pset_obj_track_times(dcpl.id, false);
  Handle set{H5Dcreate2(file, path.c_str(), type.id, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT), H5Dclose};
  const std::string padded = text.empty() ? std::string(1, '\0') : text;
  if (set.id < 0 || H5Dwrite(set.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()) < 0)
    throw std::runtime_error("cannot write dataset '" + path + "'");
}

bool Hdf5File::exists(const std::string &path) const
{
  // Check each level, as H5Lexists fails on a missing intermediate group.
  std::string partial;
  std::istringstream parts(path);
  for (std::string part; std::getline(parts, part, '/');)
    {
      if (part.empty()) continue;
      partial += "/" + part;
      if (H5Lexists(file, partial.c_str(), H5P_DEFAULT) <= 0) return false;
    }
  return true;
}

std::vector<std::string> Hdf5File::members(const std::string &group) const
{
  if (!exists(group)) throw std::runtime_error("group '" + group + "' is missing");
  std::vector<std::string> names;
  auto collect = [](hid_t, const char *name, const H5L_info_t *, void *data) -> herr_t {
    static_cast<std::vector<std::string> *>(data)->push_back(name);
    return 0;
  };
  if (H5Literate_by_name(file, group.c_str(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names, H5P_DEFAULT) < 0)
    throw std::runtime_error("cannot list group '" + group + "'");
  return names;
}

std::vector<hsize_t> Hdf5File::shape(const std::string &path) const
{
  if (!exists(path)) throw std::runtime_error("dataset '" + path + "' is missing");
  Handle set{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  if (set.id < 0) throw std::runtime_error("'" + path + "' is not a dataset");
  Handle space{H5Dget_space(set.id), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank < 0) throw std::runtime_error("dataset '" + path + "' has no simple shape");
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
  return dims;
}

namespace
{
/// The number of elements of a dataset or attribute space, or -1 if it is not a simple space.
long long element_count(const hid_t space)
{
  const H5S_class_t kind = H5Sget_simple_extent_type(space);
  if (kind == H5S_SCALAR) return 1;
  if (kind != H5S_SIMPLE) return -1;
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  return n < 0 ? -1 : static_cast<long long>(n);
}

/// The largest dataset this reader allocates: 2^28 values (2 GiB of doubles). A reduced body of
/// 1000 modes has a largest dataset (Q, n x n x 3 x 3) of 9e6 values.
constexpr hsize_t max_dataset_values = hsize_t(1) << 28;

/// Opens attribute @p name of @p object, checks that it holds exactly one value of class
/// @p expected (a file may hold an array, or another type, under a known name).
hid_t open_single_attribute(const hid_t file, const std::string &object, const std::string &name,
                            const H5T_class_t expected, const char *expected_text)
{
  if (H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT) <= 0)
    throw std::runtime_error("attribute '" + name + "' of '" + object + "' is missing");
  const hid_t a = H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) throw std::runtime_error("attribute '" + name + "' of '" + object + "' cannot be opened");
  Handle space{H5Aget_space(a), H5Sclose};
  Handle type{H5Aget_type(a), H5Tclose};
  if (space.id < 0 || type.id < 0 || element_count(space.id) != 1 || H5Tget_class(type.id) != expected)
    {
      H5Aclose(a);
      throw std::runtime_error("attribute '" + name + "' of '" + object + "' is not a single " + expected_text);
    }
  return a;
}
} // namespace

std::vector<hsize_t> Hdf5File::checked_shape(const std::string &path, const H5T_class_t expected_class) const
{
  const auto dims = shape(path);
  Handle set{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  Handle type{H5Dget_type(set.id), H5Tclose};
  if (type.id < 0 || H5Tget_class(type.id) != expected_class)
    throw std::runtime_error("dataset '" + path + "' has the wrong type (expected " +
                             (expected_class == H5T_FLOAT ? "floating-point numbers" : "integers") + ")");
  hsize_t size = 1;
  for (const auto s : dims)
    {
      if (s > 0 && size > max_dataset_values / s)
        throw std::runtime_error("dataset '" + path + "' of shape " + shape_text(dims) + " is too large (at most " +
                                 std::to_string(max_dataset_values) + " values)");
      size *= s;
    }
  return dims;
}

void Hdf5File::read_raw(const std::string &path, const std::vector<hsize_t> &expected_shape, const hid_t memory_type,
                        void *data) const
{
  Handle set{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  hsize_t size = 1;
  for (const auto s : expected_shape) size *= s;
  if (size > 0 && H5Dread(set.id, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error("cannot read dataset '" + path + "' (damaged file?)");
}

template <typename Number>
std::vector<Number> Hdf5File::read_checked(const std::string &path, const std::vector<hsize_t> &expected_shape,
                                           const H5T_class_t file_class, const hid_t memory_type) const
{
  // The shape and type are checked before anything is allocated: the expected shape may come
  // from a count in the same (possibly hostile) file.
  const auto dims = checked_shape(path, file_class);
  if (dims != expected_shape)
    throw std::runtime_error("dataset '" + path + "' has shape " + shape_text(dims) + ", expected " +
                             shape_text(expected_shape));
  hsize_t size = 1;
  for (const auto s : dims) size *= s;
  std::vector<Number> v(size);
  read_raw(path, dims, memory_type, v.data());
  return v;
}

std::vector<double> Hdf5File::read_doubles(const std::string &path, const std::vector<hsize_t> &expected_shape) const
{
  auto v = read_checked<double>(path, expected_shape, H5T_FLOAT, H5T_NATIVE_DOUBLE);
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw std::runtime_error("dataset '" + path + "' holds a non-finite value (" + std::to_string(v[i]) +
                               ") at position " + std::to_string(i));
  return v;
}

std::vector<unsigned int> Hdf5File::read_unsigned(const std::string &path, const std::vector<hsize_t> &expected_shape) const
{
  return read_checked<unsigned int>(path, expected_shape, H5T_INTEGER, H5T_NATIVE_UINT);
}

std::string Hdf5File::string_attribute(const std::string &object, const std::string &name) const
{
  Handle a{open_single_attribute(file, object, name, H5T_STRING, "fixed-length string"), H5Aclose};
  Handle type{H5Aget_type(a.id), H5Tclose};
  const size_t size = H5Tget_size(type.id);
  if (H5Tis_variable_str(type.id) != 0 || size == 0 || size > max_string_length)
    throw std::runtime_error("attribute '" + name + "' of '" + object + "' is not a fixed-length string of at most " +
                             std::to_string(max_string_length) + " characters");
  // Read through a memory type of exactly this size: one element, so the buffer fits.
  Handle memory{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(memory.id, size);
  H5Tset_strpad(memory.id, H5T_STR_NULLPAD);
  std::string value(size, '\0');
  if (H5Aread(a.id, memory.id, value.data()) < 0) throw std::runtime_error("cannot read attribute '" + name + "'");
  value.erase(value.find_last_not_of('\0') + 1);
  return value;
}

std::string Hdf5File::read_text(const std::string &path, const std::size_t max_length) const
{
  if (!exists(path)) throw std::runtime_error("dataset '" + path + "' is missing");
  Handle set{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  if (set.id < 0) throw std::runtime_error("'" + path + "' is not a dataset");
  Handle space{H5Dget_space(set.id), H5Sclose};
  Handle type{H5Dget_type(set.id), H5Tclose};
  if (space.id < 0 || type.id < 0 || element_count(space.id) != 1 || H5Tget_class(type.id) != H5T_STRING ||
      H5Tis_variable_str(type.id) != 0)
    throw std::runtime_error("dataset '" + path + "' is not a single fixed-length string");
  const size_t size = H5Tget_size(type.id);
  if (size == 0 || size > max_length)
    throw std::runtime_error("dataset '" + path + "' is a string of " + std::to_string(size) + " characters; at most " +
                             std::to_string(max_length) + " are allowed");
  Handle memory{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(memory.id, size);
  H5Tset_strpad(memory.id, H5T_STR_NULLPAD);
  std::string value(size, '\0');
  if (H5Dread(set.id, memory.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, value.data()) < 0)
    throw std::runtime_error("cannot read dataset '" + path + "' (damaged file?)");
  value.erase(value.find_last_not_of('\0') + 1);
  return value;
}

long long Hdf5File::integer_attribute(const std::string &object, const std::string &name) const
{
  Handle a{open_single_attribute(file, object, name, H5T_INTEGER, "integer"), H5Aclose};
  long long value = 0;
  if (H5Aread(a.id, H5T_NATIVE_LLONG, &value) < 0) throw std::runtime_error("cannot read attribute '" + name + "'");
  return value;
}
} // namespace flextrack::io
