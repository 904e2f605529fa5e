// Randomly corrupted files must either load into a valid mesh/cloud or throw
// InputError: never crash, hang, allocate without bound or throw anything else.
// Run this binary under ASan+UBSan (./run sanitize) to catch memory errors.

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/obj.hpp>
#include <icrkit/core/io/pcd.hpp>
#include <icrkit/core/io/ply.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <sstream>
#include <string>

using namespace icrkit;

namespace {

constexpr int kCorruptionsPerFile = 1000;

TriangleMesh sampleMesh() {
  TriangleMesh m;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 40; ++i) {
    m.vertices.positions.emplace_back(u(rng), u(rng), u(rng));
    m.vertices.normals.push_back(Eigen::Vector3d(u(rng), u(rng), 1.0).normalized());
  }
  m.vertices.attributes.add("cardinality", ScalarType::Int32, 40, 12);
  m.vertices.attributes.add("excluded", ScalarType::UInt8, 40, 1);
  for (int i = 0; i + 2 < 40; ++i) m.faces.emplace_back(i, i + 1, i + 2);
  return m;
}

// One random corruption: byte flips, digit/sign/delimiter swaps, truncation,
// insertion, deletion or duplication of a chunk.
std::string corrupt(const std::string& original, std::mt19937& rng) {
  std::string s = original;
  std::uniform_int_distribution<int> kind(0, 6);
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits && !s.empty(); ++e) {
    const std::size_t pos = rng() % s.size();
    switch (kind(rng)) {
      case 0: s[pos] = static_cast<char>(rng() & 0xff); break;
      case 1: s[pos] = "0123456789-+.eE \n/#nai"[rng() % 22]; break;
      case 2: s.resize(pos); break;
      case 3: s.insert(pos, std::string(1 + rng() % 8, static_cast<char>(rng() & 0xff))); break;
      case 4: s.erase(pos, 1 + rng() % 16); break;
      case 5: {
        const std::size_t len = std::min<std::size_t>(1 + rng() % 64, s.size() - pos);
        s.insert(pos, s.substr(pos, len));
        break;
      }
      case 6: s[pos] = static_cast<char>(s[pos] ^ (1 << (rng() % 8))); break;
    }
  }
  return s;
}

struct FuzzOutcome {
  int loaded = 0;
  int rejected = 0;
};

FuzzOutcome fuzz(const std::string& original, const std::function<void(const std::string&)>& parse, unsigned seed) {
  std::mt19937 rng(seed);
  FuzzOutcome outcome;
  for (int i = 0; i < kCorruptionsPerFile; ++i) {
    const std::string bytes = corrupt(original, rng);
    try {
      parse(bytes);
      ++outcome.loaded;
    } catch (const InputError& e) {
      ++outcome.rejected;
      EXPECT_FALSE(std::string(e.what()).empty());
    } catch (const std::exception& e) {
      ADD_FAILURE() << "corruption " << i << " threw a non-InputError: " << e.what();
    }
  }
  return outcome;
}

void parseMeshChecked(const TriangleMesh& m) {
  // Whatever loads must be a valid mesh: finite, indices in range.
  EXPECT_NO_THROW(m.validate());
}

}  // namespace

TEST(Fuzz, CorruptedAsciiPly) {
  const TriangleMesh m = sampleMesh();
  std::ostringstream out;
  io::WriteOptions options;
  options.encoding = io::Encoding::Ascii;
  io::writePly(out, m.vertices, m.faces, options);
  const FuzzOutcome o = fuzz(out.str(), [](const std::string& b) { parseMeshChecked(io::parsePly(b, "fuzz.ply")); }, 1);
  EXPECT_EQ(o.loaded + o.rejected, kCorruptionsPerFile);
  EXPECT_GT(o.rejected, 0);
}

TEST(Fuzz, CorruptedBinaryPly) {
  const TriangleMesh m = sampleMesh();
  for (bool big : {false, true}) {
    std::ostringstream out;
    io::WriteOptions options;
    options.big_endian = big;
    io::writePly(out, m.vertices, m.faces, options);
    const FuzzOutcome o =
        fuzz(out.str(), [](const std::string& b) { parseMeshChecked(io::parsePly(b, "fuzz.ply")); }, big ? 3 : 2);
    EXPECT_EQ(o.loaded + o.rejected, kCorruptionsPerFile);
    EXPECT_GT(o.rejected, 0);
  }
}

TEST(Fuzz, CorruptedObj) {
  const TriangleMesh m = sampleMesh();
  std::ostringstream out;
  io::writeObj(out, m.vertices, m.faces);
  const FuzzOutcome o = fuzz(out.str(), [](const std::string& b) { parseMeshChecked(io::parseObj(b, "fuzz.obj")); }, 4);
  EXPECT_EQ(o.loaded + o.rejected, kCorruptionsPerFile);
  EXPECT_GT(o.rejected, 0);
}

TEST(Fuzz, CorruptedPcd) {
  const TriangleMesh m = sampleMesh();
  for (io::Encoding encoding : {io::Encoding::Binary, io::Encoding::Ascii}) {
    std::ostringstream out;
    io::WriteOptions options;
    options.encoding = encoding;
    io::writePcd(out, m.vertices, options);
    const FuzzOutcome o = fuzz(
        out.str(),
        [](const std::string& b) {
          const PointCloud cloud = io::parsePcd(b, "fuzz.pcd");
          EXPECT_NO_THROW(cloud.validate());
        },
        encoding == io::Encoding::Binary ? 5 : 6);
    EXPECT_EQ(o.loaded + o.rejected, kCorruptionsPerFile);
    EXPECT_GT(o.rejected, 0);
  }
}
