// A small, strict wrapper of the HDF5 C library (Debian's libhdf5, via deal.II): datasets of
// doubles and unsigned integers with their shapes, string and integer attributes, groups.
// Every failure throws std::runtime_error naming the object, and HDF5's own error printing is
// switched off, so that callers can turn it into one clear message.
// Datasets and groups are written without modification times, so that the same data give the
// same bytes.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace flextrack::io
{
class Hdf5File
{
public:
  enum class Mode { create, create_on_disk, read };
  /// create: a new file, built in memory and written (an existing one replaced) by close() only;
  /// create_on_disk: a new file written to disk as it grows (results too large to hold in memory:
  /// a run's results.h5), each write checked against the free space first (see append_rows);
  /// read: must be an HDF5 file.
  Hdf5File(const std::string &name, Mode mode);
  ~Hdf5File();
  /// Writes a created file to disk and closes it; throws std::runtime_error if the data did not
  /// reach the disk (a full disk). A created file destroyed without close() is not written.
  void close();
  Hdf5File(const Hdf5File &) = delete;
  Hdf5File &operator=(const Hdf5File &) = delete;

  void create_group(const std::string &path);
  void write(const std::string &path, const std::vector<hsize_t> &shape, const double *data);
  void write(const std::string &path, const std::vector<hsize_t> &shape, const unsigned int *data);
  void set_attribute(const std::string &object, const std::string &name, const std::string &value);
  /// A text as a scalar dataset of one fixed-length string (an attribute holds at most 64 KiB).
  void write_text(const std::string &path, const std::string &text);
  void set_attribute(const std::string &object, const std::string &name, long long value);
  /// A 1-D attribute of fixed-length strings (one per column of a dataset: its names).
  void set_attribute(const std::string &object, const std::string &name, const std::vector<std::string> &values);
  /// A dataset of doubles that grows by rows: [0 x columns] at first ([0] for columns = 0),
  /// stored in chunks of about 64 KiB, or of @p expected_rows rows when that is less.
  void create_growing(const std::string &path, hsize_t columns, hsize_t expected_rows);
  /// Appends @p n_rows rows (row-major, columns values each) to a dataset of create_growing.
  /// On a file on disk the free space of its folder is checked first: a disk that would fill
  /// throws std::runtime_error before HDF5 writes (HDF5 1.10 crashes at exit on a file whose
  /// write failed).
  void append_rows(const std::string &path, hsize_t n_rows, const double *data);

  bool exists(const std::string &path) const;
  /// Names of the members of a group.
  std::vector<std::string> members(const std::string &group) const;
  std::vector<hsize_t> shape(const std::string &path) const;
  /// The longest string attribute read [characters]; longer ones are refused.
  static constexpr std::size_t max_string_length = 4096;
  /// The dataset at @p path, which must have exactly @p expected_shape, the right type class,
  /// and (doubles) only finite values. Nothing is allocated before the shape is checked.
  std::vector<double> read_doubles(const std::string &path, const std::vector<hsize_t> &expected_shape) const;
  std::vector<unsigned int> read_unsigned(const std::string &path, const std::vector<hsize_t> &expected_shape) const;
  /// Attributes must hold exactly one value of the right class (a scalar or a 1-element array).
  std::string string_attribute(const std::string &object, const std::string &name) const;
  long long integer_attribute(const std::string &object, const std::string &name) const;
  /// The text dataset at @p path: one fixed-length string (scalar or 1 element) of at most
  /// @p max_length characters, checked before anything is allocated.
  std::string read_text(const std::string &path, std::size_t max_length) const;

private:
  void write_raw(const std::string &path, const std::vector<hsize_t> &shape, hid_t file_type, hid_t memory_type,
                 const void *data);
  /// The shape of the dataset at @p path, checked to be of type class @p expected_class and of
  /// at most max_dataset_values values.
  std::vector<hsize_t> checked_shape(const std::string &path, H5T_class_t expected_class) const;
  template <typename Number>
  std::vector<Number> read_checked(const std::string &path, const std::vector<hsize_t> &expected_shape,
                                   H5T_class_t file_class, hid_t memory_type) const;
  void read_raw(const std::string &path, const std::vector<hsize_t> &expected_shape, hid_t memory_type, void *data) const;
  /// Throws if @p bytes more would not fit on the file's disk or under its file size limit.
  void require_free_space(std::uintmax_t bytes) const;
  std::string file_name;
  Mode mode;
  hid_t file = -1;
};
} // namespace flextrack::io
