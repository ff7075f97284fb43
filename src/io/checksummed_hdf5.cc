#include <io/checksummed_hdf5.h>

#include <iomanip>
#include <sstream>

namespace flextrack::io
{
// The bytes of numbers are hashed as they lie in memory; the definition is little-endian.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the content checksum assumes a little-endian machine");

namespace
{
constexpr std::uint64_t fnv_offset = 14695981039346656037ull, fnv_prime = 1099511628211ull;

std::uint64_t fnv1a(const void *data, const std::size_t bytes)
{
  std::uint64_t h = fnv_offset;
  for (std::size_t i = 0; i < bytes; ++i) h = (h ^ static_cast<const unsigned char *>(data)[i]) * fnv_prime;
  return h;
}

std::size_t value_count(const std::vector<hsize_t> &shape)
{
  std::size_t count = 1;
  for (const auto s : shape) count *= s;
  return count;
}

std::string attribute_key(const std::string &object, const std::string &name) { return object + "@" + name; }
} // namespace

void ContentChecksum::add(const std::string &key, const void *data, const std::size_t bytes)
{
  items[key] = fnv1a(data, bytes);
}

void ContentChecksum::add(const std::string &key, const std::string &text)
{
  const auto last = text.find_last_not_of('\0');
  add(key, text.data(), last == std::string::npos ? 0 : last + 1);
}

void ContentChecksum::add(const std::string &key, const long long value) { add(key, &value, sizeof value); }

std::string ContentChecksum::hex() const
{
  std::string all;
  for (const auto &[key, h] : items)
    {
      all += key;
      all += '\0';
      all.append(reinterpret_cast<const char *>(&h), sizeof h);
    }
  std::ostringstream s;
  s << std::hex << std::setw(16) << std::setfill('0') << fnv1a(all.data(), all.size());
  return s.str();
}

ChecksummedWriter::ChecksummedWriter(const std::string &name) : f(name, Hdf5File::Mode::create) {}

void ChecksummedWriter::create_group(const std::string &path) { f.create_group(path); }

void ChecksummedWriter::write(const std::string &path, const std::vector<hsize_t> &shape, const double *data)
{
  f.write(path, shape, data);
  sum.add(path, data, value_count(shape) * sizeof(double));
}

void ChecksummedWriter::write(const std::string &path, const std::vector<hsize_t> &shape, const unsigned int *data)
{
  f.write(path, shape, data);
  sum.add(path, data, value_count(shape) * sizeof(unsigned int));
}

void ChecksummedWriter::write_text(const std::string &path, const std::string &text)
{
  f.write_text(path, text);
  sum.add(path, text);
}

void ChecksummedWriter::set_attribute(const std::string &object, const std::string &name, const std::string &value)
{
  f.set_attribute(object, name, value);
  sum.add(attribute_key(object, name), value);
}

void ChecksummedWriter::set_attribute(const std::string &object, const std::string &name, const long long value)
{
  f.set_attribute(object, name, value);
  sum.add(attribute_key(object, name), value);
}

void ChecksummedWriter::close()
{
  f.set_attribute("/", "content_checksum", sum.hex());
  f.close();
}

ChecksummedReader::ChecksummedReader(const std::string &name) : f(name, Hdf5File::Mode::read) {}

std::vector<double> ChecksummedReader::read_doubles(const std::string &path, const std::vector<hsize_t> &shape)
{
  auto v = f.read_doubles(path, shape);
  sum.add(path, v.data(), v.size() * sizeof(double));
  return v;
}

std::vector<unsigned int> ChecksummedReader::read_unsigned(const std::string &path, const std::vector<hsize_t> &shape)
{
  auto v = f.read_unsigned(path, shape);
  sum.add(path, v.data(), v.size() * sizeof(unsigned int));
  return v;
}

std::string ChecksummedReader::read_text(const std::string &path, const std::size_t max_length)
{
  auto text = f.read_text(path, max_length);
  sum.add(path, text);
  return text;
}

std::string ChecksummedReader::string_attribute(const std::string &object, const std::string &name)
{
  auto value = f.string_attribute(object, name);
  sum.add(attribute_key(object, name), value);
  return value;
}

long long ChecksummedReader::integer_attribute(const std::string &object, const std::string &name)
{
  const auto value = f.integer_attribute(object, name);
  sum.add(attribute_key(object, name), value);
  return value;
}

std::string ChecksummedReader::stored_checksum() const { return f.string_attribute("/", "content_checksum"); }
} // namespace flextrack::io
