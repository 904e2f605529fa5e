#pragma once
// Readers that take a path get the fuzz input through a file of its own:
// unique per process and call, removed when the call ends.

#include "fuzz_targets.hpp"

#include <icrkit/core/error.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

namespace icrkit::fuzz {

class TempInput {
 public:
  /// Writes the bytes to a new file named ...`suffix` (the reader may go by
  /// the extension) in $TMPDIR (or /tmp).
  TempInput(const std::uint8_t* data, std::size_t size, const std::string& suffix);
  ~TempInput();
  TempInput(const TempInput&) = delete;
  TempInput& operator=(const TempInput&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// The fuzz input read by `read(path)` through a file of its own; the
/// reader's InputError is the expected answer to bad bytes.
template <typename Read>
void readThroughFile(const std::uint8_t* data, std::size_t size, const std::string& suffix, Read read) {
  const TempInput file(data, size, suffix);
  try {
    read(file.path());
  } catch (const InputError& e) {
    rejected(e);
  }
}

}  // namespace icrkit::fuzz
