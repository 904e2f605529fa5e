// PCL's PCD reader and writer.
//
// The header is parsed into a field list, then every size it claims (point
// count, field counts, compressed and uncompressed sizes) is checked against
// the bytes actually present before anything is allocated: a corrupted or
// hostile header must not cost more memory than the file could hold.
//
// Binary data is read in the file's byte order, which PCL never records and
// which is little endian on every platform that writes these files.

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/pcd.hpp>

#include "io/text_scanner.hpp"

#include <liblzf/lzf.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the PCD reader and writer assume a little-endian host"
#endif

namespace icrkit::io {
namespace {

using detail::TextScanner;

enum class DataEncoding { Ascii, Binary, BinaryCompressed };
enum class Role { X, Y, Z, NormalX, NormalY, NormalZ, Colour, Attribute, Skip };

struct PcdField {
  std::string name;
  char type = 'F';        // I, U or F
  std::size_t size = 4;   // bytes per value
  std::size_t count = 1;  // values per point
  Role role = Role::Skip;
  std::size_t offset = 0;  // byte offset in a point-major record
  std::size_t column = 0;  // first token in an ASCII line
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t points = 0;
  DataEncoding encoding = DataEncoding::Ascii;
  std::size_t point_size = 0;     // bytes per point
  std::size_t tokens_per_point = 0;
  std::size_t data_offset = 0;    // first byte after the DATA line
  std::size_t data_line = 0;      // line number of the first data line
};

// Bounds every COUNT so that sums of them cannot overflow; no real field
// (PCL's largest descriptors hold a few hundred values) comes near it.
constexpr std::uint64_t kMaxFieldCount = std::uint64_t{1} << 31;
// LZF turns at most 3 input bytes into 264 output bytes (a long back
// reference), so no valid stream expands by more than this.
constexpr std::uint64_t kMaxLzfRatio = 88;

bool parseUnsigned(std::string_view token, std::uint64_t& value) { return detail::parseNumber(token, value); }

bool knownType(char type, std::size_t size) {
  if (type == 'F') return size == 4 || size == 8;
  if (type == 'I' || type == 'U') return size == 1 || size == 2 || size == 4 || size == 8;
  return false;
}

// The attribute type of a field; false for 64-bit integers, which an
// attribute (held as double) cannot represent exactly.
bool attributeType(const PcdField& field, ScalarType& type) {
  switch (field.type) {
    case 'F': type = field.size == 4 ? ScalarType::Float32 : ScalarType::Float64; return true;
    case 'I':
      if (field.size == 8) return false;
      type = field.size == 1 ? ScalarType::Int8 : field.size == 2 ? ScalarType::Int16 : ScalarType::Int32;
      return true;
    default:
      if (field.size == 8) return false;
      type = field.size == 1 ? ScalarType::UInt8 : field.size == 2 ? ScalarType::UInt16 : ScalarType::UInt32;
      return true;
  }
}

Role roleOf(const std::string& name) {
  if (name == "x") return Role::X;
  if (name == "y") return Role::Y;
  if (name == "z") return Role::Z;
  if (name == "normal_x") return Role::NormalX;
  if (name == "normal_y") return Role::NormalY;
  if (name == "normal_z") return Role::NormalZ;
  if (name == "rgb" || name == "rgba") return Role::Colour;
  return Role::Attribute;
}

// Decides what each field becomes once the whole header is known: normals
// need all three components, colours a packed 4-byte value.
void assignRoles(PcdHeader& header, const std::function<void(const std::string&)>& fail) {
  for (std::size_t i = 0; i < header.fields.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (header.fields[j].name == header.fields[i].name && header.fields[i].name != "_")
        fail("field '" + TextScanner::clip(header.fields[i].name) + "' appears twice in FIELDS");
  for (const char* axis : {"x", "y", "z"}) {
    const PcdField* found = nullptr;
    for (const PcdField& field : header.fields)
      if (field.name == axis) found = &field;
    if (found == nullptr) fail(std::string("the header has no field '") + axis + "', expected x y z");
    if (found->count != 1)
      fail(std::string("field '") + axis + "' has COUNT " + std::to_string(found->count) + ", expected 1");
  }
  int normal_components = 0;
  bool have_colour = false;
  for (PcdField& field : header.fields) {
    Role role = roleOf(field.name);
    ScalarType type;
    if (field.name == "_" || field.count != 1) role = Role::Skip;  // PCL padding, histograms
    if (role >= Role::NormalX && role <= Role::NormalZ) ++normal_components;
    if (role == Role::Colour && (field.size != 4 || have_colour)) role = Role::Attribute;
    if (role == Role::Colour) have_colour = true;
    if (role == Role::Attribute && !attributeType(field, type)) role = Role::Skip;
    field.role = role;
  }
  if (normal_components != 3)
    for (PcdField& field : header.fields) {
      ScalarType type;
      if (field.role >= Role::NormalX && field.role <= Role::NormalZ)
        field.role = attributeType(field, type) ? Role::Attribute : Role::Skip;
    }
}

PcdHeader parseHeader(std::string_view bytes, const std::string& source) {
  PcdHeader header;
  TextScanner scanner(bytes, source);
  std::vector<std::string_view> tokens;
  std::vector<std::string_view> names, sizes, types, counts;
  std::uint64_t width = 0, height = 1, points = 0;
  bool have_width = false, have_points = false, have_data = false;
  std::size_t data_line = 0;

  while (!have_data) {
    if (scanner.atEnd()) scanner.fail("unexpected end of file in the header, expected a DATA line");
    const std::size_t line_number = scanner.line();
    detail::splitTokens(scanner.restOfLine(), tokens);
    auto fail = [&](const std::string& detail) -> void {
      throw InputError(source, "line " + std::to_string(line_number), detail);
    };
    if (tokens.empty() || tokens[0].front() == '#') continue;
    const std::string_view keyword = tokens[0];
    auto readCount = [&](std::uint64_t& value) {
      if (tokens.size() != 2 || !parseUnsigned(tokens[1], value))
        fail("expected '" + std::string(keyword) + " <non-negative integer>'");
    };
    if (keyword == "FIELDS" || keyword == "COLUMNS") {
      names.assign(tokens.begin() + 1, tokens.end());
      if (names.empty()) fail("FIELDS lists no field");
    } else if (keyword == "SIZE") {
      sizes.assign(tokens.begin() + 1, tokens.end());
    } else if (keyword == "TYPE") {
      types.assign(tokens.begin() + 1, tokens.end());
    } else if (keyword == "COUNT") {
      counts.assign(tokens.begin() + 1, tokens.end());
    } else if (keyword == "WIDTH") {
      readCount(width);
      have_width = true;
    } else if (keyword == "HEIGHT") {
      readCount(height);
    } else if (keyword == "POINTS") {
      readCount(points);
      have_points = true;
    } else if (keyword == "DATA") {
      if (tokens.size() != 2) fail("expected 'DATA ascii', 'DATA binary' or 'DATA binary_compressed'");
      if (tokens[1] == "ascii") header.encoding = DataEncoding::Ascii;
      else if (tokens[1] == "binary") header.encoding = DataEncoding::Binary;
      else if (tokens[1] == "binary_compressed") header.encoding = DataEncoding::BinaryCompressed;
      else fail("unknown DATA '" + TextScanner::clip(tokens[1]) + "', expected ascii, binary or binary_compressed");
      have_data = true;
      data_line = line_number;
    }
    // VERSION, VIEWPOINT and unknown keywords carry nothing icrkit keeps.
  }
  header.data_offset = scanner.offset();
  header.data_line = data_line + 1;

  const std::function<void(const std::string&)> fail = [&](const std::string& detail) {
    throw InputError(source, "line " + std::to_string(data_line), detail);
  };
  if (names.empty()) fail("the header has no FIELDS line");
  if (sizes.size() != names.size())
    fail("SIZE has " + std::to_string(sizes.size()) + " entries for " + std::to_string(names.size()) + " fields");
  if (types.size() != names.size())
    fail("TYPE has " + std::to_string(types.size()) + " entries for " + std::to_string(names.size()) + " fields");
  if (!counts.empty() && counts.size() != names.size())
    fail("COUNT has " + std::to_string(counts.size()) + " entries for " + std::to_string(names.size()) + " fields");

  std::uint64_t point_size = 0, tokens_per_point = 0;
  for (std::size_t i = 0; i < names.size(); ++i) {
    PcdField field;
    field.name = std::string(names[i]);
    std::uint64_t size = 0, count = 1;
    if (!parseUnsigned(sizes[i], size) || types[i].size() != 1 || !knownType(types[i][0], size))
      fail("field '" + TextScanner::clip(names[i]) + "' has SIZE " + TextScanner::clip(sizes[i]) + " TYPE " +
           TextScanner::clip(types[i]) + ", expected F 4, F 8 or I/U with 1, 2, 4 or 8 bytes");
    if (!counts.empty() && (!parseUnsigned(counts[i], count) || count == 0 || count > kMaxFieldCount))
      fail("field '" + TextScanner::clip(names[i]) + "' has COUNT '" + TextScanner::clip(counts[i]) +
           "', expected a positive integer");
    field.type = types[i][0];
    field.size = static_cast<std::size_t>(size);
    field.count = static_cast<std::size_t>(count);
    field.offset = static_cast<std::size_t>(point_size);
    field.column = static_cast<std::size_t>(tokens_per_point);
    // names.size() is bounded by the header length, so these sums stay far
    // from overflowing 64 bits.
    point_size += size * count;
    tokens_per_point += count;
    header.fields.push_back(std::move(field));
  }
  header.point_size = static_cast<std::size_t>(point_size);
  header.tokens_per_point = static_cast<std::size_t>(tokens_per_point);

  if (have_width) {
    if (height != 0 && width > std::numeric_limits<std::uint64_t>::max() / height)
      fail("WIDTH x HEIGHT overflows");
    const std::uint64_t grid = width * height;
    if (have_points && grid != points)
      fail("WIDTH " + std::to_string(width) + " x HEIGHT " + std::to_string(height) + " = " + std::to_string(grid) +
           " disagrees with POINTS " + std::to_string(points));
    if (!have_points) points = grid;
  } else if (!have_points) {
    fail("the header has neither POINTS nor WIDTH");
  }
  header.points = points;
  assignRoles(header, fail);
  return header;
}

// Where one field's values sit in a binary buffer: the value of point i is
// at start + i * stride.
struct BinaryColumn {
  const char* start = nullptr;
  std::size_t stride = 0;
};

template <typename T>
T load(const char* p) {
  T value;
  std::memcpy(&value, p, sizeof value);
  return value;
}

double loadScalar(const char* p, char type, std::size_t size) {
  switch (type) {
    case 'F': return size == 4 ? static_cast<double>(load<float>(p)) : load<double>(p);
    case 'I':
      switch (size) {
        case 1: return load<std::int8_t>(p);
        case 2: return load<std::int16_t>(p);
        case 4: return load<std::int32_t>(p);
        default: return static_cast<double>(load<std::int64_t>(p));
      }
    default:
      switch (size) {
        case 1: return load<std::uint8_t>(p);
        case 2: return load<std::uint16_t>(p);
        case 4: return load<std::uint32_t>(p);
        default: return static_cast<double>(load<std::uint64_t>(p));
      }
  }
}

Colour unpackColour(std::uint32_t packed) {
  // PCL packs 0xAARRGGBB, i.e. bytes b, g, r, a in little-endian memory.
  return Colour{static_cast<std::uint8_t>((packed >> 16) & 0xff), static_cast<std::uint8_t>((packed >> 8) & 0xff),
               static_cast<std::uint8_t>(packed & 0xff)};
}

// Accumulates points into a cloud, dropping those without a finite position.
class CloudBuilder {
public:
  CloudBuilder(const PcdHeader& header, std::size_t expected_points) : header_(header) {
    for (const PcdField& field : header.fields) {
      if (field.role == Role::NormalX) has_normals_ = true;
      if (field.role == Role::Colour) has_colours_ = true;
      if (field.role == Role::Attribute) {
        ScalarType type = ScalarType::Float32;
        attributeType(field, type);
        cloud_.attributes.add(field.name, type, std::vector<double>());
      }
    }
    cloud_.positions.reserve(expected_points);
    if (has_normals_) cloud_.normals.reserve(expected_points);
    if (has_colours_) cloud_.colours.reserve(expected_points);
    for (Attribute& a : cloud_.attributes) a.values.reserve(expected_points);
    values_.resize(header.fields.size());
  }

  /// The value of field f for the current point (unused for Skip fields).
  double& value(std::size_t f) { return values_[f]; }
  void setPacked(std::uint32_t packed) { packed_ = packed; }

  void finishPoint() {
    Eigen::Vector3d position, normal = Eigen::Vector3d::Zero();
    auto attribute = cloud_.attributes.begin();
    for (std::size_t f = 0; f < header_.fields.size(); ++f) {
      const Role role = header_.fields[f].role;
      if (role >= Role::X && role <= Role::Z) position[static_cast<int>(role) - static_cast<int>(Role::X)] = values_[f];
      if (role >= Role::NormalX && role <= Role::NormalZ)
        normal[static_cast<int>(role) - static_cast<int>(Role::NormalX)] = values_[f];
    }
    if (!position.allFinite()) return;
    cloud_.positions.push_back(position);
    if (has_normals_) cloud_.normals.push_back(normal);
    if (has_colours_) cloud_.colours.push_back(unpackColour(packed_));
    for (std::size_t f = 0; f < header_.fields.size(); ++f)
      if (header_.fields[f].role == Role::Attribute) (attribute++)->values.push_back(values_[f]);
  }

  PointCloud take() { return std::move(cloud_); }

private:
  const PcdHeader& header_;
  PointCloud cloud_;
  std::vector<double> values_;
  std::uint32_t packed_ = 0;
  bool has_normals_ = false;
  bool has_colours_ = false;
};

PointCloud readBinary(const PcdHeader& header, const std::vector<BinaryColumn>& columns) {
  const std::size_t n = static_cast<std::size_t>(header.points);
  CloudBuilder builder(header, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t f = 0; f < header.fields.size(); ++f) {
      const PcdField& field = header.fields[f];
      if (field.role == Role::Skip) continue;
      const char* p = columns[f].start + i * columns[f].stride;
      if (field.role == Role::Colour) builder.setPacked(load<std::uint32_t>(p));
      else builder.value(f) = loadScalar(p, field.type, field.size);
    }
    builder.finishPoint();
  }
  return builder.take();
}

bool parseAsciiScalar(std::string_view token, char type, std::size_t size, double& value) {
  if (type == 'F') {
    if (size == 8) return detail::parseNumber(token, value);
    float f = 0;
    if (!detail::parseNumber(token, f)) return false;
    value = f;
    return true;
  }
  if (type == 'I') {
    std::int64_t v = 0;
    if (!detail::parseNumber(token, v)) return false;
    const std::int64_t limit = size == 8 ? std::numeric_limits<std::int64_t>::max() : (std::int64_t{1} << (8 * size - 1)) - 1;
    if (v > limit || v < -limit - 1) return false;
    value = static_cast<double>(v);
    return true;
  }
  std::uint64_t v = 0;
  if (!detail::parseNumber(token, v)) return false;
  if (size < 8 && v >> (8 * size) != 0) return false;
  value = static_cast<double>(v);
  return true;
}

// ASCII rgb holds the packed bits: as a float for TYPE F (PCL's habit),
// else as an integer.
bool parseAsciiPacked(std::string_view token, char type, std::uint32_t& packed) {
  if (type == 'F') {
    float f = 0;
    if (!detail::parseNumber(token, f)) return false;
    std::memcpy(&packed, &f, sizeof packed);
    return true;
  }
  if (type == 'I') {
    std::int32_t v = 0;
    if (!detail::parseNumber(token, v)) return false;
    packed = static_cast<std::uint32_t>(v);
    return true;
  }
  return detail::parseNumber(token, packed);
}

PointCloud readAscii(std::string_view bytes, const std::string& source, const PcdHeader& header) {
  const std::string_view data = bytes.substr(header.data_offset);
  // Each value takes at least one character and one separator, which bounds
  // what is worth reserving; a POINTS beyond that fails on the count below.
  const std::uint64_t max_points = (static_cast<std::uint64_t>(data.size()) + 1) / (2 * header.tokens_per_point);
  const std::size_t n = static_cast<std::size_t>(header.points);
  CloudBuilder builder(header, static_cast<std::size_t>(std::min(header.points, max_points)));
  TextScanner scanner(data, source, header.data_line);
  std::vector<std::string_view> tokens;
  std::size_t read = 0;
  while (!scanner.atEnd()) {
    const std::size_t line = scanner.line();
    detail::splitTokens(scanner.restOfLine(), tokens);
    if (tokens.empty() || tokens[0].front() == '#') continue;
    auto fail = [&](const std::string& detail) {
      throw InputError(source, "line " + std::to_string(line), detail);
    };
    if (read == n) fail("more data lines than POINTS " + std::to_string(n));
    if (tokens.size() != header.tokens_per_point)
      fail("found " + std::to_string(tokens.size()) + " values, expected " + std::to_string(header.tokens_per_point));
    for (std::size_t f = 0; f < header.fields.size(); ++f) {
      const PcdField& field = header.fields[f];
      if (field.role == Role::Skip) continue;
      const std::string_view token = tokens[field.column];
      bool ok;
      if (field.role == Role::Colour) {
        std::uint32_t packed = 0;
        ok = parseAsciiPacked(token, field.type, packed);
        builder.setPacked(packed);
      } else {
        ok = parseAsciiScalar(token, field.type, field.size, builder.value(f));
      }
      if (!ok)
        fail("field '" + TextScanner::clip(field.name) + "' is '" + TextScanner::clip(token) + "', expected a " +
             std::string(1, field.type) + " " + std::to_string(field.size) + " value");
    }
    builder.finishPoint();
    ++read;
  }
  if (read != n)
    throw InputError(source, "line " + std::to_string(scanner.line()),
                     "unexpected end of data: found " + std::to_string(read) + " data lines, expected POINTS " + std::to_string(n));
  return builder.take();
}

PointCloud readBinaryData(std::string_view bytes, const std::string& source, const PcdHeader& header) {
  const std::size_t available = bytes.size() - header.data_offset;
  const std::string where = "byte " + std::to_string(header.data_offset);
  if (header.points > available / header.point_size)
    throw InputError(source, where,
                     "POINTS " + std::to_string(header.points) + " of " + std::to_string(header.point_size) +
                         " bytes need more than the " + std::to_string(available) + " bytes of data");
  std::vector<BinaryColumn> columns;
  for (const PcdField& field : header.fields)
    columns.push_back(BinaryColumn{bytes.data() + header.data_offset + field.offset, header.point_size});
  return readBinary(header, columns);
}

PointCloud readCompressedData(std::string_view bytes, const std::string& source, const PcdHeader& header) {
  const std::size_t available = bytes.size() - header.data_offset;
  const char* data = bytes.data() + header.data_offset;
  const std::string where = "byte " + std::to_string(header.data_offset);
  if (available < 8)
    throw InputError(source, where, "found " + std::to_string(available) +
                                        " bytes of data, expected at least the two 4-byte sizes of binary_compressed");
  const std::uint64_t compressed = load<std::uint32_t>(data);
  const std::uint64_t uncompressed = load<std::uint32_t>(data + 4);
  // A 32-bit size field cannot describe more than 2^32 points of data.
  if (header.points > std::numeric_limits<std::uint32_t>::max() ||
      header.point_size > std::numeric_limits<std::uint32_t>::max() ||
      uncompressed != header.points * header.point_size)
    throw InputError(source, where,
                     "uncompressed size " + std::to_string(uncompressed) + " disagrees with POINTS " +
                         std::to_string(header.points) + " x " + std::to_string(header.point_size) + " bytes");
  if (compressed > available - 8)
    throw InputError(source, where,
                     "compressed size " + std::to_string(compressed) + " exceeds the " + std::to_string(available - 8) +
                         " bytes that follow");
  if (header.points == 0) return CloudBuilder(header, 0).take();
  if (uncompressed > compressed * kMaxLzfRatio)
    throw InputError(source, where,
                     "uncompressed size " + std::to_string(uncompressed) + " cannot come from " +
                         std::to_string(compressed) + " bytes of LZF data");

  std::vector<char> buffer(static_cast<std::size_t>(uncompressed));
  const unsigned int produced = lzf_decompress(data + 8, static_cast<unsigned int>(compressed), buffer.data(),
                                               static_cast<unsigned int>(uncompressed));
  if (produced != uncompressed)
    throw InputError(source, where,
                     "the LZF data is corrupt: it decompressed to " + std::to_string(produced) + " bytes, expected " +
                         std::to_string(uncompressed));
  // PCL stores the compressed payload field by field, so each field's values
  // form one contiguous block.
  std::vector<BinaryColumn> columns;
  std::size_t block = 0;
  const std::size_t n = static_cast<std::size_t>(header.points);
  for (const PcdField& field : header.fields) {
    const std::size_t stride = field.size * field.count;
    columns.push_back(BinaryColumn{buffer.data() + block, stride});
    block += stride * n;
  }
  return readBinary(header, columns);
}

// ---- writing ----

struct OutField {
  std::string name;
  ScalarType type;
  std::function<double(std::size_t)> value;
};

char pcdTypeLetter(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::Int16:
    case ScalarType::Int32: return 'I';
    case ScalarType::UInt8:
    case ScalarType::UInt16:
    case ScalarType::UInt32: return 'U';
    case ScalarType::Float32:
    case ScalarType::Float64: return 'F';
  }
  return 'F';
}

void appendBinary(std::string& out, ScalarType type, double value) {
  auto put = [&](auto v) {
    char raw[sizeof v];
    std::memcpy(raw, &v, sizeof v);
    out.append(raw, sizeof v);
  };
  const double r = representAs(type, value);
  switch (type) {
    case ScalarType::Int8: put(static_cast<std::int8_t>(r)); break;
    case ScalarType::UInt8: put(static_cast<std::uint8_t>(r)); break;
    case ScalarType::Int16: put(static_cast<std::int16_t>(r)); break;
    case ScalarType::UInt16: put(static_cast<std::uint16_t>(r)); break;
    case ScalarType::Int32: put(static_cast<std::int32_t>(r)); break;
    case ScalarType::UInt32: put(static_cast<std::uint32_t>(r)); break;
    case ScalarType::Float32: put(static_cast<float>(value)); break;
    case ScalarType::Float64: put(value); break;
  }
}

void appendAscii(std::string& out, ScalarType type, double value) {
  if (type == ScalarType::Float32) {
    detail::appendRoundTrip(out, static_cast<float>(value));
  } else if (type == ScalarType::Float64) {
    detail::appendRoundTrip(out, value);
  } else {
    char buffer[24];
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, static_cast<long long>(representAs(type, value)));
    (void)ec;
    out.append(buffer, end);
  }
}

bool reservedName(const std::string& name) {
  return roleOf(name) != Role::Attribute || name == "_";
}

}  // namespace

PointCloud parsePcd(std::string_view bytes, const std::string& source) {
  const PcdHeader header = parseHeader(bytes, source);
  switch (header.encoding) {
    case DataEncoding::Ascii: return readAscii(bytes, source, header);
    case DataEncoding::Binary: return readBinaryData(bytes, source, header);
    case DataEncoding::BinaryCompressed: return readCompressedData(bytes, source, header);
  }
  return {};
}

void writePcd(std::ostream& out, const PointCloud& cloud, const WriteOptions& options) {
  const std::size_t n = cloud.size();
  if (cloud.hasNormals() && cloud.normals.size() != n)
    throw std::invalid_argument("writePcd: " + std::to_string(cloud.normals.size()) + " normals for " +
                                std::to_string(n) + " points");
  if (cloud.hasColours() && cloud.colours.size() != n)
    throw std::invalid_argument("writePcd: " + std::to_string(cloud.colours.size()) + " colours for " +
                                std::to_string(n) + " points");
  const ScalarType real = options.real_type == ScalarType::Float32 ? ScalarType::Float32 : ScalarType::Float64;

  std::vector<OutField> fields;
  const char* axes[] = {"x", "y", "z"};
  const char* normal_axes[] = {"normal_x", "normal_y", "normal_z"};
  for (int k = 0; k < 3; ++k)
    fields.push_back({axes[k], real, [&cloud, k](std::size_t i) { return cloud.positions[i][k]; }});
  if (cloud.hasNormals())
    for (int k = 0; k < 3; ++k)
      fields.push_back({normal_axes[k], real, [&cloud, k](std::size_t i) { return cloud.normals[i][k]; }});
  if (cloud.hasColours())
    // "rgba" U 4 is the field PCL's PointXYZRGBA declares, so PCL maps it by name and type.
    fields.push_back({"rgba", ScalarType::UInt32, [&cloud](std::size_t i) {
                        const Colour& c = cloud.colours[i];
                        // Opaque alpha, as PCL's own point types default to.
                        return static_cast<double>(0xff000000u | std::uint32_t{c[0]} << 16 | std::uint32_t{c[1]} << 8 |
                                                   std::uint32_t{c[2]});
                      }});
  for (const Attribute& attribute : cloud.attributes) {
    bool plain = !attribute.name.empty();
    for (char c : attribute.name)
      if (static_cast<unsigned char>(c) <= 32 || static_cast<unsigned char>(c) > 126) plain = false;
    if (!plain || reservedName(attribute.name))
      throw std::invalid_argument("writePcd: attribute '" + attribute.name +
                                  "' cannot be a PCD field (spaces, control characters or a reserved name)");
    if (attribute.values.size() != n)
      throw std::invalid_argument("writePcd: attribute '" + attribute.name + "' has " +
                                  std::to_string(attribute.values.size()) + " values for " + std::to_string(n) +
                                  " points");
    fields.push_back({attribute.name, attribute.type, [&attribute](std::size_t i) { return attribute.values[i]; }});
  }

  std::string buffer = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS";
  for (const OutField& f : fields) buffer += ' ' + f.name;
  buffer += "\nSIZE";
  for (const OutField& f : fields) buffer += ' ' + std::to_string(scalarSize(f.type));
  buffer += "\nTYPE";
  for (const OutField& f : fields) buffer += std::string(" ") + pcdTypeLetter(f.type);
  buffer += "\nCOUNT";
  for (std::size_t i = 0; i < fields.size(); ++i) buffer += " 1";
  buffer += "\nWIDTH " + std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(n) +
            "\nDATA " + (options.encoding == Encoding::Ascii ? "ascii" : "binary") + "\n";

  constexpr std::size_t kFlushSize = 1 << 20;
  const bool ascii = options.encoding == Encoding::Ascii;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t f = 0; f < fields.size(); ++f) {
      const double value = fields[f].value(i);
      if (ascii) {
        if (f > 0) buffer += ' ';
        appendAscii(buffer, fields[f].type, value);
      } else {
        appendBinary(buffer, fields[f].type, value);
      }
    }
    if (ascii) buffer += '\n';
    if (buffer.size() >= kFlushSize) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

}  // namespace icrkit::io
