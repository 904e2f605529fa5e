#include <icrkit/core/number_text.hpp>

#include <algorithm>
#include <charconv>

namespace icrkit {

std::string formatFixed(double value, int decimals) {
  // 309 integer digits (DBL_MAX), a sign, a point and at most 100 decimals.
  char buffer[420];
  const auto result =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, std::clamp(decimals, 0, 100));
  return std::string(buffer, result.ptr);
}

std::string formatShortest(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

}  // namespace icrkit
