#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

using namespace icrkit;

namespace {
std::size_t entries(const std::filesystem::path& dir) {
  return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir), {}));
}
}  // namespace

TEST(AtomicFile, WritesAndReplaces) {
  test::ScratchDir dir;
  writeFileAtomically(dir.file("a.txt"), [](std::ostream& out) { out << "first"; });
  writeFileAtomically(dir.file("a.txt"), [](std::ostream& out) { out << "second"; });
  EXPECT_EQ(io::readFileBytes(dir.file("a.txt")), "second");
  EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(AtomicFile, WholeContentOverload) {
  test::ScratchDir dir;
  const std::string bytes("one\ntwo\r\n\0three", 16);
  writeFileAtomically(dir.file("b.txt"), bytes);
  EXPECT_EQ(io::readFileBytes(dir.file("b.txt")), bytes) << "binary: no newline translation, NUL kept";
  EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(AtomicFile, FailureLeavesTheOldFileAndNoTemporary) {
  test::ScratchDir dir;
  writeFileAtomically(dir.file("a.txt"), [](std::ostream& out) { out << "kept"; });
  EXPECT_THROW(writeFileAtomically(dir.file("a.txt"),
                                   [](std::ostream& out) {
                                     out << "partial";
                                     throw std::runtime_error("writer failed half-way");
                                   }),
               std::runtime_error);
  EXPECT_EQ(io::readFileBytes(dir.file("a.txt")), "kept");
  EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(AtomicFile, MissingDirectoryIsAnInputError) {
  test::ScratchDir dir;
  EXPECT_THROW(writeFileAtomically(dir.file("no/such/dir/a.txt"), [](std::ostream& out) { out << "x"; }), InputError);
}
