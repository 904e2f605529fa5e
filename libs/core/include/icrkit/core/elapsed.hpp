#pragma once
/// \file
/// Wall-clock time of a stage, as the libraries' reports give it
/// (`time_ms` and the per-stage times).

#include <chrono>

namespace icrkit {

/// Milliseconds since `start` on the steady clock (never goes back, unlike
/// the system clock a user may set while a study runs).
inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace icrkit
