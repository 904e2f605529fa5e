#pragma once
/// \file
/// Table I as a figure: SVG written directly (no plotting runtime) and the
/// same layout rasterized to PNG with OpenCV, our medians beside the paper's.

#include <icrkit/eval/results_tables.hpp>

#include <string>
#include <vector>

namespace icrkit::report {

/// A self-contained SVG document of the table (rows of `table` and its
/// Average; the paper's values in grey where the dataset is one of its).
std::string tableOneSvg(const eval::TableOne& table);
/// The same table as PNG bytes.
std::vector<unsigned char> tableOnePng(const eval::TableOne& table);

void writeTableOneSvg(const std::string& path, const eval::TableOne& table);
void writeTableOnePng(const std::string& path, const eval::TableOne& table);

}  // namespace icrkit::report
