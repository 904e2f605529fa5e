#include <icrkit/core/length.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/number_text.hpp>

#include "io/text_scanner.hpp"

#include <cmath>
#include <string_view>

namespace icrkit {
namespace {

// The whole token as a finite number (the text readers' parser, which no
// locale changes); blanks around it, as in "1.5x, 2.5x", are allowed.
bool parseWholeNumber(std::string_view text, double& value) {
  while (!text.empty() && io::detail::isBlank(text.front())) text.remove_prefix(1);
  while (!text.empty() && io::detail::isBlank(text.back())) text.remove_suffix(1);
  return io::detail::parseNumber(text, value) && std::isfinite(value);
}

std::vector<std::string> splitAtCommas(const std::string& text) {
  std::vector<std::string> parts;
  std::string part;
  for (char c : text) {
    if (c == ',') {
      parts.push_back(part);
      part.clear();
    } else {
      part += c;
    }
  }
  if (!text.empty()) parts.push_back(part);
  return parts;
}

}  // namespace

bool Length::valid() const {
  return std::isfinite(value) && value > 0.0;
}

Length parseLength(const std::string& source, const std::string& text) {
  Length length;
  length.relative = !text.empty() && (text.back() == 'x' || text.back() == 'X');
  const std::string_view number =
      length.relative ? std::string_view(text).substr(0, text.size() - 1) : std::string_view(text);
  if (!parseWholeNumber(number, length.value))
    throw InputError(
        source, "",
        "expected metres (e.g. 0.004) or a multiple of the median point spacing (e.g. 4x), got '" + text + "'");
  if (!(length.value > 0)) throw InputError(source, "", "must be positive, got '" + text + "'");
  return length;
}

std::vector<Length> parseLengths(const std::string& source, const std::string& text) {
  std::vector<Length> lengths;
  for (const std::string& item : splitAtCommas(text)) lengths.push_back(parseLength(source, item));
  if (lengths.empty()) throw InputError(source, "", "expected at least one length");
  for (const Length& l : lengths)
    if (l.relative != lengths.front().relative)
      throw InputError(source, "",
                       "give all lengths in metres or all as multiples of the spacing (x), got '" + text + "'");
  return lengths;
}

std::string formatLength(const Length& length) {
  return formatShortest(length.value) + (length.relative ? "x" : "");
}

}  // namespace icrkit
