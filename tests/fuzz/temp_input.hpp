#pragma once
// Readers that take a path get the fuzz input through a file of its own:
// unique per process and call, removed when the call ends.

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

}  // namespace icrkit::fuzz
