// Replays inputs through the fuzz targets without libFuzzer, in the
// ordinary test suite:
//   icrkit_fuzz_replay DIR          every DIR/<target>/* through <target>
//   icrkit_fuzz_replay TARGET FILE  one file
// A target's answer to bad bytes is an InputError, caught inside; anything
// that escapes (another exception) fails the replay naming the file; a
// crash fails it by itself.
#include "fuzz_targets.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using icrkit::fuzz::FuzzTarget;

namespace {

const FuzzTarget* findTarget(const std::string& name) {
  for (const FuzzTarget& t : icrkit::fuzz::fuzzTargets())
    if (name == t.name) return &t;
  return nullptr;
}

bool replay(const FuzzTarget& target, const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "%s: cannot read\n", file.c_str());
    return false;
  }
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  try {
    target.run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s (%s): escaped: %s\n", file.c_str(), target.name, e.what());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3) {
    const FuzzTarget* target = findTarget(argv[1]);
    if (!target) {
      std::fprintf(stderr, "unknown target %s\n", argv[1]);
      return 2;
    }
    return replay(*target, argv[2]) ? 0 : 1;
  }
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR | TARGET FILE\n", argv[0]);
    return 2;
  }
  std::size_t replayed = 0, failed = 0;
  for (const FuzzTarget& target : icrkit::fuzz::fuzzTargets()) {
    const fs::path dir = fs::path(argv[1]) / target.name;
    if (!fs::is_directory(dir)) continue;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) {
      ++replayed;
      if (!replay(target, file)) ++failed;
    }
  }
  std::printf("replayed %zu inputs, %zu failed\n", replayed, failed);
  return failed == 0 ? 0 : 1;
}
