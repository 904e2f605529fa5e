#include "argument_parsing.hpp"

#include <icrkit/core/error.hpp>

#include <cmath>
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

Length parseLength(const std::string& option, const std::string& text) {
  Length length;
  length.relative = !text.empty() && (text.back() == 'x' || text.back() == 'X');
  if (!parseNumber(length.relative ? text.substr(0, text.size() - 1) : text, length.value))
    throw InputError(option, "",
                     "expected metres (e.g. 0.004) or a multiple of the median point spacing (e.g. 4x), got '" +
                         text + "'");
  if (!(length.value > 0)) throw InputError(option, "", "must be positive, got '" + text + "'");
  return length;
}

std::vector<Length> parseLengths(const std::string& option, const std::string& text) {
  std::vector<Length> lengths;
  for (const std::string& item : split(text, ',')) lengths.push_back(parseLength(option, item));
  if (lengths.empty()) throw InputError(option, "", "expected at least one length");
  for (const Length& l : lengths)
    if (l.relative != lengths.front().relative)
      throw InputError(option, "", "give all lengths in metres or all as multiples of the spacing (x), got '" +
                                       text + "'");
  return lengths;
}

}  // namespace icrkit::app
