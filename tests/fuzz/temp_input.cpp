#include "temp_input.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <unistd.h>

namespace icrkit::fuzz {

TempInput::TempInput(const std::uint8_t* data, std::size_t size, const std::string& suffix) {
  const char* dir = std::getenv("TMPDIR");
  std::string pattern = std::string(dir && *dir ? dir : "/tmp") + "/icrkit-fuzz-XXXXXX" + suffix;
  const int fd = mkstemps(pattern.data(), static_cast<int>(suffix.size()));
  if (fd < 0) throw std::runtime_error("cannot create a temporary file for the fuzz input");
  path_ = pattern;
  std::size_t written = 0;
  while (written < size) {
    const ssize_t n = ::write(fd, data + written, size - written);
    if (n <= 0) {
      ::close(fd);
      std::remove(path_.c_str());
      throw std::runtime_error("cannot write the fuzz input to " + path_);
    }
    written += static_cast<std::size_t>(n);
  }
  ::close(fd);
}

TempInput::~TempInput() { std::remove(path_.c_str()); }

}  // namespace icrkit::fuzz
