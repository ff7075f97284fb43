// An HDF5 file that sums what passes through it: the content checksum of the reduced body file
// (doc/reduced_body_file.md, "Content checksum"; issue 23, item 4). The writer adds every
// dataset and attribute it writes and stores the checksum last; the reader adds every item it
// reads, so that after reading the whole file the sum can be compared with the stored one.
//
// The checksum is a 64-bit FNV-1a hash of every attribute and dataset of the file but the
// checksum itself. Each item is hashed on its own - its values as stored: doubles as IEEE 754
// binary64 little-endian, unsigned integers as 32-bit and integer attributes as 64-bit
// little-endian, strings and texts as their characters without trailing zero bytes - then the
// items' keys (a dataset's path; an attribute's object path, '@', its name) in byte order, each
// followed by a zero byte and the item's hash (8 bytes, little-endian), are hashed together.
// Sorting makes the sum independent of the order in which writer and reader visit the items,
// and the keys make a value moved to another item a change. It detects damage (flipped bits, an
// edited number, a partial copy), not intent: anyone can recompute it, which is why the reader
// also checks the physics (reduction/plausibility.h).
#pragma once

#include <io/hdf5_file.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace flextrack::io
{
class ContentChecksum
{
public:
  /// The item @p key holds the @p bytes bytes at @p data.
  void add(const std::string &key, const void *data, std::size_t bytes);
  /// A string item: its characters without trailing zero bytes (as HDF5 reads them back).
  void add(const std::string &key, const std::string &text);
  void add(const std::string &key, long long value);
  /// The checksum of all items added: 16 lower-case hex digits.
  std::string hex() const;

private:
  std::map<std::string, std::uint64_t> items;
};

/// Hdf5File's writing calls, each item also added to the checksum; close() stores the checksum
/// as the root attribute "content_checksum" and writes the file.
class ChecksummedWriter
{
public:
  explicit ChecksummedWriter(const std::string &name);
  void create_group(const std::string &path);
  void write(const std::string &path, const std::vector<hsize_t> &shape, const double *data);
  void write(const std::string &path, const std::vector<hsize_t> &shape, const unsigned int *data);
  void write_text(const std::string &path, const std::string &text);
  void set_attribute(const std::string &object, const std::string &name, const std::string &value);
  void set_attribute(const std::string &object, const std::string &name, long long value);
  void close();

private:
  Hdf5File f;
  ContentChecksum sum;
};

/// Hdf5File's reading calls (with all their checks), each item read also added to the checksum.
class ChecksummedReader
{
public:
  explicit ChecksummedReader(const std::string &name);
  bool exists(const std::string &path) const { return f.exists(path); }
  std::vector<std::string> members(const std::string &group) const { return f.members(group); }
  std::vector<hsize_t> shape(const std::string &path) const { return f.shape(path); }
  std::vector<double> read_doubles(const std::string &path, const std::vector<hsize_t> &shape);
  std::vector<unsigned int> read_unsigned(const std::string &path, const std::vector<hsize_t> &shape);
  std::string read_text(const std::string &path, std::size_t max_length);
  std::string string_attribute(const std::string &object, const std::string &name);
  long long integer_attribute(const std::string &object, const std::string &name);
  /// The checksum stored in the file (not itself summed); std::runtime_error if there is none.
  std::string stored_checksum() const;
  /// The checksum of every item read so far.
  std::string computed_checksum() const { return sum.hex(); }

private:
  Hdf5File f;
  ContentChecksum sum;
};
} // namespace flextrack::io
