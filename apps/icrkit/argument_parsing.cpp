#include "argument_parsing.hpp"

#include <icrkit/core/error.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace icrkit::app {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

bool parseNumber(const std::string& text, double& value) {
  std::istringstream in(text);
  in >> value;
  if (in.fail() || !std::isfinite(value)) return false;
  in >> std::ws;
  return in.eof();
}

Eigen::Vector3d parsePoint(const std::string& option, const std::string& text) {
  const std::vector<std::string> parts = split(text, ',');
  Eigen::Vector3d p;
  bool ok = parts.size() == 3;
  for (std::size_t k = 0; ok && k < 3; ++k) ok = parseNumber(parts[k], p[static_cast<Eigen::Index>(k)]);
  if (!ok) throw InputError(option, "", "expected x,y,z in metres, got '" + text + "'");
  return p;
}

std::string lowercaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace icrkit::app
