// Plain text points: `x y z` or `x y z nx ny nz` per line.
//
// The first data line fixes the column count; a later line that differs is
// an error rather than a silent reinterpretation, since a mixed file almost
// always means a concatenation of different kinds of data.

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/xyz.hpp>

#include "io/text_scanner.hpp"

#include <array>
#include <cmath>
#include <string>

namespace icrkit::io {
namespace {

using detail::TextScanner;

constexpr std::size_t kMaxColumns = 6;

}  // namespace

PointCloud parseXyz(std::string_view text, const std::string& source) {
  PointCloud cloud;
  TextScanner scanner(text, source);
  std::size_t columns = 0;  // 0 until the first data line
  std::array<double, kMaxColumns> values{};

  while (true) {
    std::string_view token = scanner.nextToken();
    if (token.empty()) break;
    if (token.front() == '#') {
      scanner.restOfLine();
      continue;
    }
    std::size_t count = 0;
    for (; !token.empty() && token.front() != '#'; token = scanner.nextTokenOnLine()) {
      if (count < kMaxColumns) {
        const std::size_t column = count;
        if (!detail::parseNumber(token, values[column]))
          scanner.fail("expected a number in column " + std::to_string(column + 1) + ", found '" +
                       TextScanner::clip(token) + "'");
        if (!std::isfinite(values[column]))
          scanner.fail("column " + std::to_string(column + 1) + " is '" + TextScanner::clip(token) +
                       "', expected a finite number");
      }
      ++count;
    }
    if (count != 3 && count != 6)
      scanner.fail("found " + std::to_string(count) + " columns, expected 3 (x y z) or 6 (x y z nx ny nz)");
    if (columns == 0) {
      columns = count;
    } else if (count != columns) {
      scanner.fail("found " + std::to_string(count) + " columns, expected " + std::to_string(columns) +
                   " like the first data line");
    }
    cloud.positions.emplace_back(values[0], values[1], values[2]);
    if (columns == 6) cloud.normals.emplace_back(values[3], values[4], values[5]);
    scanner.restOfLine();
  }
  return cloud;
}

void writeXyz(std::ostream& out, const PointCloud& cloud) {
  const bool with_normals = cloud.hasNormals();
  std::string buffer;
  constexpr std::size_t kFlushSize = 1 << 20;
  buffer.reserve(kFlushSize + 256);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d& p = cloud.positions[i];
    for (int k = 0; k < 3; ++k) {
      if (k > 0) buffer += ' ';
      detail::appendRoundTrip(buffer, p[k]);
    }
    if (with_normals) {
      const Eigen::Vector3d& n = cloud.normals.at(i);
      for (int k = 0; k < 3; ++k) {
        buffer += ' ';
        detail::appendRoundTrip(buffer, n[k]);
      }
    }
    buffer += '\n';
    if (buffer.size() >= kFlushSize) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

}  // namespace icrkit::io
