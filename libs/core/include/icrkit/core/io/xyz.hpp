#pragma once
/// \file
/// Plain text points: one `x y z` or `x y z nx ny nz` per line; '#' starts
/// a comment; every data line must have the same number of columns.

#include <icrkit/core/point_cloud.hpp>

#include <ostream>
#include <string>
#include <string_view>

namespace icrkit::io {

PointCloud parseXyz(std::string_view text, const std::string& source);
void writeXyz(std::ostream& out, const PointCloud& cloud);

}  // namespace icrkit::io
