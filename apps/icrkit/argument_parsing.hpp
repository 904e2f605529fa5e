#pragma once
// Parsing of the option values several commands share: whole-token numbers,
// comma lists, x,y,z points (and, from core/length.hpp, lengths in metres or
// spacings). Errors are InputErrors naming the option.

#include <icrkit/core/error.hpp>
#include <icrkit/core/length.hpp>  // parseLength, parseLengths: lengths in metres or spacings ("4x")

#include <Eigen/Core>

#include <string>
#include <vector>

namespace icrkit::app {

/// Splits at every separator; "a,,b" and "a," keep their empty items.
std::vector<std::string> split(const std::string& text, char separator);

/// Whole-token number parsing: "12x", "" or "nan" fail instead of giving 12 or 0.
bool parseNumber(const std::string& text, double& value);

/// Runs `work`; an InputError the library raised about `library_source`
/// (e.g. "point cloud", "images") is raised again naming `user_source`, the
/// file the user gave.
template <typename Work>
auto renamingInputErrors(const std::string& library_source, const std::string& user_source, Work&& work) {
  try {
    return work();
  } catch (const InputError& error) {
    if (error.source() != library_source) throw;
    throw InputError(user_source, error.location(), error.detail());
  }
}

/// A path's extension, lower case, with its dot (".ply"; "" without one).
std::string lowercaseExtension(const std::string& path);

/// "x,y,z" in metres.
Eigen::Vector3d parsePoint(const std::string& option, const std::string& text);

}  // namespace icrkit::app
