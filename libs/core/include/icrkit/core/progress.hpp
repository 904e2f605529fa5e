#pragma once
/// \file
/// Progress of long work, reported through a callback so that libraries stay
/// silent; the `icrkit` command draws it on stderr when that is a terminal
/// (apps/icrkit/terminal_progress.hpp).

#include <cstddef>
#include <functional>
#include <string>

namespace icrkit {

/// Called with a stage name, work done and total work (total 0 = unknown).
/// May be called from several threads; implementations must be thread-safe.
using ProgressCallback = std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

/// Reports to `progress` when one is given (an empty callback is silence).
inline void reportProgress(const ProgressCallback& progress, const std::string& stage, std::size_t done,
                           std::size_t total) {
  if (progress) progress(stage, done, total);
}

}  // namespace icrkit
