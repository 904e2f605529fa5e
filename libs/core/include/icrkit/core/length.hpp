#pragma once
/// \file
/// A length given in metres or as a multiple of a point set's spacing (its
/// median nearest-neighbour distance): the two ways a window or ball radius
/// is chosen. "4 spacings" follows the sensor's resolution, "4 mm" is fixed.
/// Text form: "0.004" (metres) or "4x" (spacings).

#include <string>
#include <vector>

namespace icrkit {

struct Length {
  double value = 0.0;     ///< metres, or spacings when `relative`
  bool relative = false;  ///< value is a multiple of the spacing

  static Length metres(double metres) { return {metres, false}; }
  static Length spacings(double factor) { return {factor, true}; }

  /// The length in metres for a point set whose spacing is `spacing_m`.
  double metresFor(double spacing_m) const { return relative ? value * spacing_m : value; }
  /// Finite and > 0.
  bool valid() const;
  bool operator==(const Length& other) const { return value == other.value && relative == other.relative; }
};

/// "0.004" or "4x" (a trailing x or X), the number a whole token; throws
/// InputError(source) for anything else or a length that is not > 0.
Length parseLength(const std::string& source, const std::string& text);

/// A comma list of lengths, all in metres or all relative; InputError(source)
/// for an empty list or a mixed one.
std::vector<Length> parseLengths(const std::string& source, const std::string& text);

/// The text form: "0.004", "4x" (shortest round-trip digits).
std::string formatLength(const Length& length);

}  // namespace icrkit
