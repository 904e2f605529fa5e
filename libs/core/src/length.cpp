#include <icrkit/core/length.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/number_text.hpp>

#include <cmath>
#include <locale>
#include <sstream>

namespace icrkit {
namespace {

// Whole-token parsing: "12y", "" or "nan" fail instead of giving 12 or 0;
// the classic locale, whatever the user's, reads the decimal point.
bool parseWholeNumber(const std::string& text, double& value) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  in >> value;
  if (in.fail() || !std::isfinite(value)) return false;
  in >> std::ws;
  return in.eof();
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
  if (!parseWholeNumber(length.relative ? text.substr(0, text.size() - 1) : text, length.value))
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
