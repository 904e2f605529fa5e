#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <unistd.h>

namespace icrkit {
namespace {

std::string temporaryNameFor(const std::string& path) {
  // Unique per process and call, so concurrent writers of different outputs
  // in one directory never share a temporary.
  static std::atomic<unsigned> counter{0};
  std::filesystem::path p(path);
  std::string name = "." + p.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                     std::to_string(counter.fetch_add(1));
  return (p.parent_path() / name).string();
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write, bool binary) {
  const std::string temporary = temporaryNameFor(path);
  try {
    {
      std::ofstream out(temporary, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
      if (!out) throw InputError(path, "", std::string("cannot create the output file: ") + std::strerror(errno));
      write(out);
      out.flush();
      if (!out) throw InputError(path, "", "writing failed (disk full or I/O error)");
    }
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) throw InputError(path, "", "cannot move the finished output into place: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void writeFileAtomically(const std::string& path, const std::string& contents) {
  writeFileAtomically(path, [&](std::ostream& out) { out << contents; });
}

}  // namespace icrkit
