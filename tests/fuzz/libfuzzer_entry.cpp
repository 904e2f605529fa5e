// libFuzzer's entry for one target, chosen at compile time
// (ICRKIT_FUZZ_TARGET, one of fuzz_targets.hpp's functions).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  icrkit::fuzz::ICRKIT_FUZZ_TARGET(data, size);
  return 0;
}
