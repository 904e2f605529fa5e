#pragma once
/// \file
/// Numbers as text for output files (tables, plots, reports) that must not
/// change with the user's locale: std::to_chars ignores LC_NUMERIC.

#include <string>

namespace icrkit {

/// `value` with exactly `decimals` digits after the point (0..100), e.g.
/// formatFixed(0.25, 1) == "0.2" (round half to even, as printf).
std::string formatFixed(double value, int decimals);

/// The shortest text that reads back as the same double, e.g. "0.1", "1e-07".
std::string formatShortest(double value);

}  // namespace icrkit
