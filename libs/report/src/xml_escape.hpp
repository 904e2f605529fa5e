#pragma once
// Text for SVG and HTML bodies: the five XML special characters escaped.
// Shared by the figures of libs/eval (Table I, Fig. 8, the sensitivity plot).

#include <string>

namespace icrkit::report::detail {

inline std::string xmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace icrkit::report::detail
