#include "hdf5_mutator.h"

#include <hdf5.h>

#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <sstream>
#include <vector>

namespace flextrack::fuzz
{
namespace
{
/// Closes an HDF5 handle when it goes out of scope.
struct Handle
{
  hid_t id;
  herr_t (*close)(hid_t);
  Handle(hid_t id, herr_t (*close)(hid_t)) : id(id), close(close) {}
  Handle(const Handle &) = delete;
  ~Handle() { reset(); }
  /// Closes now (the object is about to be deleted or replaced).
  void reset()
  {
    if (id >= 0) close(id);
    id = -1;
  }
};

/// Values of no dataset or attribute are read beyond this many elements (memory of the fuzzer).
constexpr hsize_t max_elements = 1u << 22;

/// Every object and attribute of a file, by path.
struct Inventory
{
  std::vector<std::string> datasets, groups{"/"};
  std::vector<std::pair<std::string, std::string>> attributes; ///< (object, name)
};

herr_t collect_link(hid_t, const char *name, const H5L_info_t *, void *data)
{
  static_cast<std::vector<std::string> *>(data)->push_back(std::string("/") + name);
  return 0;
}

herr_t collect_attribute(hid_t, const char *name, const H5A_info_t *, void *data)
{
  static_cast<std::vector<std::string> *>(data)->push_back(name);
  return 0;
}

Inventory inventory(const hid_t file)
{
  std::vector<std::string> links;
  H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, collect_link, &links);
  Inventory inv;
  for (const auto &l : links)
    {
      Handle object(H5Oopen(file, l.c_str(), H5P_DEFAULT), H5Oclose);
      if (object.id < 0) continue;
      const H5I_type_t type = H5Iget_type(object.id);
      if (type == H5I_DATASET) inv.datasets.push_back(l);
      else if (type == H5I_GROUP) inv.groups.push_back(l);
    }
  for (const auto &group : {inv.groups, inv.datasets})
    for (const auto &object : group)
      {
        std::vector<std::string> names;
        Handle o(H5Oopen(file, object.c_str(), H5P_DEFAULT), H5Oclose);
        if (o.id < 0) continue;
        H5Aiterate2(o.id, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_attribute, &names);
        for (const auto &n : names) inv.attributes.emplace_back(object, n);
      }
  return inv;
}

double hostile_double(Rng &rng)
{
  const double values[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(), 1e308, -1e308, 0.0, -0.0, -1.0, 1e-320, 1e30,
                           9007199254740993.0};
  return values[rng.below(std::size(values))];
}

long long hostile_integer(Rng &rng, const long long current)
{
  const long long values[] = {0, -1, 1, current + 1, current - 1, 2 * current, 100000, INT_MAX, 1LL << 31, 1LL << 32,
                              1LL << 62, LLONG_MAX, LLONG_MIN};
  return values[rng.below(std::size(values))];
}

std::vector<hsize_t> shape_of(const hid_t set)
{
  Handle space(H5Dget_space(set), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.id);
  std::vector<hsize_t> dims(rank > 0 ? rank : 0);
  if (rank > 0) H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
  return dims;
}

hsize_t elements(const std::vector<hsize_t> &dims)
{
  hsize_t n = 1;
  for (const auto d : dims) n = d != 0 && n > std::numeric_limits<hsize_t>::max() / d ? max_elements + 1 : n * d;
  return n;
}

H5T_class_t class_of_dataset(const hid_t set)
{
  Handle type(H5Dget_type(set), H5Tclose);
  return H5Tget_class(type.id);
}

/// The fixed-length string of a scalar or one-element string object (dataset or attribute).
std::string read_fixed_string(const hid_t type, const std::function<herr_t(hid_t, void *)> &read)
{
  if (H5Tis_variable_str(type) > 0) return "";
  const std::size_t size = H5Tget_size(type);
  if (size == 0 || size > (1u << 20)) return "";
  std::string s(size, '\0');
  Handle memory(H5Tcopy(type), H5Tclose);
  if (read(memory.id, s.data()) < 0) return "";
  return s.substr(0, s.find('\0'));
}

hid_t string_type(const std::string &s)
{
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, std::max<std::size_t>(1, s.size()));
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  return type;
}

/// Replaces the dataset at @p path by one of @p dims holding @p values (doubles, or unsigned
/// integers if @p integers), or by the fixed-length string @p text if @p dims is empty.
void recreate_dataset(const hid_t file, const std::string &path, const std::vector<hsize_t> &dims,
                      std::vector<double> values, const bool integers, const std::string &text = "")
{
  H5Ldelete(file, path.c_str(), H5P_DEFAULT);
  if (dims.empty())
    {
      Handle type(string_type(text), H5Tclose);
      Handle space(H5Screate(H5S_SCALAR), H5Sclose);
      Handle set(H5Dcreate2(file, path.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
      const std::string padded = text.empty() ? std::string(1, '\0') : text;
      if (set.id >= 0) H5Dwrite(set.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data());
      return;
    }
  const hsize_t n = elements(dims);
  Handle space(H5Screate_simple(dims.size(), dims.data(), nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (n > max_elements)
    {
      // A huge shape with no data: chunked, so that nothing is allocated on disk.
      std::vector<hsize_t> chunk(dims.size(), 1);
      H5Pset_chunk(dcpl.id, chunk.size(), chunk.data());
    }
  Handle set(H5Dcreate2(file, path.c_str(), integers ? H5T_STD_U32LE : H5T_IEEE_F64LE, space.id, H5P_DEFAULT, dcpl.id,
                        H5P_DEFAULT),
             H5Dclose);
  if (set.id < 0 || n > max_elements || n == 0) return;
  values.resize(n, 1.0);
  if (integers)
    {
      std::vector<unsigned int> u(n);
      for (hsize_t i = 0; i < n; ++i)
        u[i] = std::isfinite(values[i]) && values[i] >= 0 && values[i] < 4e9 ? static_cast<unsigned int>(values[i]) : UINT_MAX;
      H5Dwrite(set.id, H5T_NATIVE_UINT, H5S_ALL, H5S_ALL, H5P_DEFAULT, u.data());
    }
  else
    H5Dwrite(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
}

/// The numeric values of a dataset as doubles (empty if not numeric or too large).
std::vector<double> numeric_values(const hid_t set)
{
  const H5T_class_t c = class_of_dataset(set);
  const hsize_t n = elements(shape_of(set));
  if ((c != H5T_FLOAT && c != H5T_INTEGER) || n > max_elements) return {};
  std::vector<double> v(n);
  if (n > 0 && H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) return {};
  return v;
}

std::string change_values(const hid_t file, const std::string &path, Rng &rng)
{
  Handle set(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (set.id < 0) return "";
  const H5T_class_t c = class_of_dataset(set.id);
  if (c == H5T_STRING)
    {
      if (elements(shape_of(set.id)) != 1) return "";
      Handle type(H5Dget_type(set.id), H5Tclose);
      const std::string text = read_fixed_string(
        type.id, [&](hid_t memory, void *buffer) { return H5Dread(set.id, memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer); });
      const std::string changed = mutate_text(text, {}, rng, 1u << 16);
      set.reset();
      recreate_dataset(file, path, {}, {}, false, changed);
      return "text of " + path + " mutated";
    }
  auto v = numeric_values(set.id);
  if (v.empty()) return "";
  const bool all = rng.one_in(8);
  for (std::size_t k = all ? v.size() : 1 + rng.below(4); k > 0; --k)
    {
      const std::size_t i = all ? k - 1 : rng.below(v.size());
      v[i] = c == H5T_INTEGER ? static_cast<double>(hostile_integer(rng, static_cast<long long>(v[i]))) : hostile_double(rng);
    }
  // Integers are written back as doubles' nearest unsigned values; LLONG_MIN etc. clamp to UINT_MAX.
  const bool integers = c == H5T_INTEGER;
  const auto dims = shape_of(set.id);
  set.reset();
  recreate_dataset(file, path, dims, v, integers);
  return std::string(all ? "every value" : "values") + " of " + path + " replaced";
}

std::string change_shape(const hid_t file, const std::string &path, Rng &rng)
{
  Handle set(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (set.id < 0) return "";
  const bool integers = class_of_dataset(set.id) == H5T_INTEGER;
  auto dims = shape_of(set.id);
  const auto v = numeric_values(set.id);
  std::ostringstream what;
  what << "shape of " << path << " changed to [";
  switch (rng.below(6))
    {
      case 0:
        if (!dims.empty()) dims[rng.below(dims.size())] += 1;
        break;
      case 1:
        if (!dims.empty())
          {
            auto &d = dims[rng.below(dims.size())];
            d = d > 0 ? d - 1 : 0;
          }
        break;
      case 2:
        if (!dims.empty()) dims[rng.below(dims.size())] = 0;
        break;
      case 3:
        if (!dims.empty()) dims.pop_back();
        break;
      case 4: dims.push_back(rng.one_in(2) ? 1 : 3); break;
      default:
        if (!dims.empty()) dims[rng.below(dims.size())] = hsize_t(1) << (20 + rng.below(20));
    }
  for (std::size_t i = 0; i < dims.size(); ++i) what << (i ? ", " : "") << dims[i];
  what << "]";
  set.reset();
  recreate_dataset(file, path, dims, v, integers, "1");
  return what.str();
}

std::string change_type(const hid_t file, const std::string &path, Rng &rng)
{
  Handle set(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (set.id < 0) return "";
  const H5T_class_t c = class_of_dataset(set.id);
  const auto dims = shape_of(set.id);
  const auto v = numeric_values(set.id);
  set.reset();
  if (c == H5T_STRING || rng.one_in(3))
    {
      recreate_dataset(file, path, {3}, {1.0, 2.0, 3.0}, rng.one_in(2));
      return "type of " + path + " changed to numbers";
    }
  if (rng.one_in(2))
    {
      recreate_dataset(file, path, {}, {}, false, "1.5");
      return "type of " + path + " changed to a string";
    }
  recreate_dataset(file, path, dims, v, c != H5T_INTEGER);
  return "type of " + path + (c == H5T_INTEGER ? " changed to doubles" : " changed to integers");
}

std::string copy_object(const hid_t file, const Inventory &inv, Rng &rng)
{
  const std::vector<std::string> &from = rng.one_in(2) ? inv.groups : inv.datasets;
  if (from.empty()) return "";
  const std::string source = from[rng.below(from.size())];
  const std::string names[] = {"copy", "tip", "a b", "x/y", std::string(300, 'z'), "\xff\xfe"};
  const std::string target = inv.groups[rng.below(inv.groups.size())];
  const std::string destination = (target == "/" ? "" : target) + "/" + names[rng.below(std::size(names))];
  if (H5Ocopy(file, source.c_str(), file, destination.c_str(), H5P_DEFAULT, H5P_DEFAULT) < 0) return "";
  return source + " copied to " + destination;
}

std::string change_attribute(const hid_t file, const std::string &object, const std::string &name, Rng &rng)
{
  Handle a(H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (a.id < 0) return "";
  Handle type(H5Aget_type(a.id), H5Tclose);
  const H5T_class_t c = H5Tget_class(type.id);
  long long current = 0;
  std::string text;
  // Only a single value is read back (an earlier mutation may have made it an array).
  Handle old_space(H5Aget_space(a.id), H5Sclose);
  const bool single = H5Sget_simple_extent_npoints(old_space.id) == 1;
  if (single && c == H5T_INTEGER) H5Aread(a.id, H5T_NATIVE_LLONG, &current);
  if (single && c == H5T_STRING)
    text = read_fixed_string(type.id, [&](hid_t memory, void *buffer) { return H5Aread(a.id, memory, buffer); });
  a.reset();
  H5Adelete_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT);
  const std::string where = "attribute '" + name + "' of " + object;
  if (rng.one_in(6)) return where + " deleted";
  const int kind = rng.one_in(4) ? static_cast<int>(rng.below(3)) : c == H5T_STRING ? 1 : 0;
  const hsize_t length = rng.one_in(4) ? 1 + rng.below(5000) : 0; // 0: a scalar
  Handle space(length ? H5Screate_simple(1, &length, nullptr) : H5Screate(H5S_SCALAR), H5Sclose);
  if (kind == 1)
    {
      const std::string changed = mutate_text(text.empty() ? "47" : text, {}, rng, 1u << 16);
      Handle s(string_type(changed), H5Tclose);
      Handle b(H5Acreate_by_name(file, object.c_str(), name.c_str(), s.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
               H5Aclose);
      std::string padded = changed.empty() ? std::string(1, '\0') : changed;
      padded.resize(H5Tget_size(s.id) * std::max<hsize_t>(1, length), '\0');
      if (b.id >= 0) H5Awrite(b.id, s.id, padded.data());
      return where + " set to a string";
    }
  Handle b(H5Acreate_by_name(file, object.c_str(), name.c_str(), kind == 0 ? H5T_STD_I64LE : H5T_IEEE_F64LE, space.id,
                             H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose);
  std::vector<long long> integers(std::max<hsize_t>(1, length), hostile_integer(rng, current));
  std::vector<double> doubles(std::max<hsize_t>(1, length), hostile_double(rng));
  if (b.id >= 0)
    kind == 0 ? H5Awrite(b.id, H5T_NATIVE_LLONG, integers.data()) : H5Awrite(b.id, H5T_NATIVE_DOUBLE, doubles.data());
  return where + (kind == 0 ? " set to " + std::to_string(integers[0]) : " set to a double") +
         (length ? " (an array of " + std::to_string(length) + ")" : "");
}

std::string structural_mutation(const hid_t file, Rng &rng)
{
  const Inventory inv = inventory(file);
  const auto pick = [&](const std::vector<std::string> &v) { return v.empty() ? std::string() : v[rng.below(v.size())]; };
  switch (rng.below(8))
    {
      case 0:
      case 1: return inv.datasets.empty() ? "" : change_values(file, pick(inv.datasets), rng);
      case 2: return inv.datasets.empty() ? "" : change_shape(file, pick(inv.datasets), rng);
      case 3: return inv.datasets.empty() ? "" : change_type(file, pick(inv.datasets), rng);
      case 4:
      case 5:
        {
          if (inv.attributes.empty()) return "";
          const auto &[object, name] = inv.attributes[rng.below(inv.attributes.size())];
          return change_attribute(file, object, name, rng);
        }
      case 6:
        {
          const std::string victim = rng.one_in(2) ? pick(inv.datasets) : pick(inv.groups);
          if (victim.empty() || victim == "/" || H5Ldelete(file, victim.c_str(), H5P_DEFAULT) < 0) return "";
          return victim + " deleted";
        }
      default: return copy_object(file, inv, rng);
    }
}

std::string byte_mutation(std::string &bytes, Rng &rng)
{
  if (bytes.empty()) return "";
  std::ostringstream what;
  switch (rng.below(3))
    {
      case 0:
        {
          const std::size_t n = 1 + rng.below(16);
          for (std::size_t k = 0; k < n; ++k) bytes[rng.below(bytes.size())] ^= static_cast<char>(1u << rng.below(8));
          what << n << " bits flipped";
          break;
        }
      case 1:
        {
          const std::size_t at = rng.below(bytes.size()), n = std::min<std::size_t>(1 + rng.below(64), bytes.size() - at);
          const int fill = rng.one_in(2) ? 0xff : 0x00;
          for (std::size_t k = 0; k < n; ++k) bytes[at + k] = static_cast<char>(fill);
          what << n << " bytes at " << at << " set to " << fill;
          break;
        }
      default:
        {
          const std::size_t size = rng.below(bytes.size());
          bytes.resize(size);
          what << "truncated to " << size << " bytes";
        }
    }
  return what.str();
}
} // namespace

std::string mutate_hdf5(const std::string &seed, const std::string &mutant, Rng &rng)
{
  namespace fs = std::filesystem;
  fs::copy_file(seed, mutant, fs::copy_options::overwrite_existing);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  std::ostringstream what;
  if (rng.one_in(4))
    {
      std::ifstream in(mutant, std::ios::binary);
      std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      in.close();
      for (std::size_t k = 1 + rng.below(3); k > 0; --k) what << byte_mutation(bytes, rng) << "; ";
      std::ofstream(mutant, std::ios::binary | std::ios::trunc) << bytes;
      return what.str();
    }
  Handle file(H5Fopen(mutant.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  if (file.id < 0) return "seed is not an HDF5 file; unchanged";
  for (std::size_t k = 1 + rng.below(3); k > 0; --k) what << structural_mutation(file.id, rng) << "; ";
  return what.str();
}
} // namespace flextrack::fuzz
