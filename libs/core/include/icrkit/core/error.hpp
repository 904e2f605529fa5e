#pragma once
/// \file
/// The error types that icrkit's libraries throw.
///
/// `InputError` means "the input is not what was expected" (a malformed file,
/// an argument out of range); the `icrkit` command turns it into a one-line
/// message and exit code 2. Anything else that escapes is an internal error
/// (exit code 1).

#include <stdexcept>
#include <string>

namespace icrkit {

class InputError : public std::runtime_error {
public:
  /// \param source   the file path, or a name such as "--radius" for an argument
  /// \param location where in the source, e.g. "line 12", "vertex 45", "byte 1024"; may be empty
  /// \param detail   what was found and what was expected
  InputError(std::string source, std::string location, std::string detail);

  const std::string& source() const noexcept { return source_; }
  const std::string& location() const noexcept { return location_; }
  const std::string& detail() const noexcept { return detail_; }

private:
  std::string source_;
  std::string location_;
  std::string detail_;
};

}  // namespace icrkit
