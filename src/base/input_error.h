// Errors a user can cause through the input: each names the file, the parameter entry and what
// is allowed. `main` prints what() as one line and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace flextrack
{
class InputError : public std::runtime_error
{
public:
  /// @p entry is the parameter path, e.g. "Arm/Material/Young's modulus".
  InputError(const std::string &entry, const std::string &message, const std::string &file = "")
    : std::runtime_error((file.empty() ? "" : file + ": ") + (entry.empty() ? "" : "entry '" + entry + "': ") + message),
      entry_path(entry), text(message), file_name(file)
  {}
  const std::string &entry() const { return entry_path; }
  const std::string &message() const { return text; }
  const std::string &file() const { return file_name; }
  /// The same error, attributed to @p file.
  InputError in_file(const std::string &file) const { return InputError(entry_path, text, file); }

private:
  std::string entry_path, text, file_name;
};
} // namespace flextrack
