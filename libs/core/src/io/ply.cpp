// Stanford PLY reader and writer.
//
// The reader parses the header into a list of elements, then walks the body
// with one of two value sources (ASCII tokens or binary of either byte
// order). Every count in the header is checked against the bytes that are
// actually there before anything is allocated, so a corrupted count cannot
// exhaust memory or loop for long.

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/ply.hpp>

#include "io/text_scanner.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace icrkit::io {
namespace {

using detail::TextScanner;

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;  // item type for lists
  bool is_list = false;
  ScalarType count_type = ScalarType::UInt8;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t header_line = 0;
};

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;  // first byte after "end_header" and its line end
  std::size_t body_first_line = 0;
};

bool parseScalarType(std::string_view name, ScalarType& type) {
  struct Alias {
    const char* name;
    ScalarType type;
  };
  static constexpr Alias aliases[] = {
      {"char", ScalarType::Int8},     {"int8", ScalarType::Int8},      {"uchar", ScalarType::UInt8},
      {"uint8", ScalarType::UInt8},   {"short", ScalarType::Int16},    {"int16", ScalarType::Int16},
      {"ushort", ScalarType::UInt16}, {"uint16", ScalarType::UInt16},  {"int", ScalarType::Int32},
      {"int32", ScalarType::Int32},   {"uint", ScalarType::UInt32},    {"uint32", ScalarType::UInt32},
      {"float", ScalarType::Float32}, {"float32", ScalarType::Float32}, {"double", ScalarType::Float64},
      {"float64", ScalarType::Float64}};
  for (const Alias& a : aliases)
    if (name == a.name) {
      type = a.type;
      return true;
    }
  return false;
}

PlyHeader parseHeader(std::string_view bytes, const std::string& source) {
  PlyHeader header;
  TextScanner scanner(bytes, source);
  std::vector<std::string_view> tokens;
  bool have_format = false;
  bool first = true;
  while (true) {
    if (scanner.atEnd()) scanner.fail("unexpected end of file inside the header, expected 'end_header'");
    const std::size_t line_number = scanner.line();
    std::string_view line = scanner.restOfLine();
    if (first) {
      if (line != "ply") throw InputError(source, "line 1", "not a PLY file, expected the magic line 'ply'");
      first = false;
      continue;
    }
    detail::splitTokens(line, tokens);
    if (tokens.empty()) continue;
    auto fail = [&](const std::string& detail) {
      throw InputError(source, "line " + std::to_string(line_number), detail);
    };
    const std::string_view keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      if (tokens.size() != 3) fail("expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
      if (tokens[1] == "ascii")
        header.format = PlyFormat::Ascii;
      else if (tokens[1] == "binary_little_endian")
        header.format = PlyFormat::BinaryLittleEndian;
      else if (tokens[1] == "binary_big_endian")
        header.format = PlyFormat::BinaryBigEndian;
      else
        fail("unknown PLY format '" + TextScanner::clip(tokens[1]) +
             "', expected ascii, binary_little_endian or binary_big_endian");
      if (tokens[2] != "1.0" && tokens[2] != "1") fail("unsupported PLY version '" + TextScanner::clip(tokens[2]) + "'");
      have_format = true;
    } else if (keyword == "element") {
      unsigned long long count = 0;
      if (tokens.size() != 3 || !detail::parseNumber(tokens[2], count))
        fail("expected 'element <name> <count>' with a non-negative integer count");
      PlyElement element;
      element.name = std::string(tokens[1]);
      element.count = static_cast<std::size_t>(count);
      element.header_line = line_number;
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail("a 'property' line before any 'element' line");
      PlyProperty property;
      if (tokens.size() == 5 && tokens[1] == "list") {
        property.is_list = true;
        if (!parseScalarType(tokens[2], property.count_type) || isFloatingPoint(property.count_type))
          fail("expected an integer type for the list count, found '" + TextScanner::clip(tokens[2]) + "'");
        if (!parseScalarType(tokens[3], property.type))
          fail("unknown list item type '" + TextScanner::clip(tokens[3]) + "'");
        property.name = std::string(tokens[4]);
      } else if (tokens.size() == 3) {
        if (!parseScalarType(tokens[1], property.type))
          fail("unknown property type '" + TextScanner::clip(tokens[1]) + "'");
        property.name = std::string(tokens[2]);
      } else {
        fail("expected 'property <type> <name>' or 'property list <count type> <item type> <name>'");
      }
      auto& properties = header.elements.back().properties;
      for (const PlyProperty& p : properties)
        if (p.name == property.name) fail("duplicate property '" + property.name + "'");
      properties.push_back(std::move(property));
    } else if (keyword == "end_header") {
      break;
    } else {
      fail("unknown header line starting with '" + TextScanner::clip(keyword) + "'");
    }
  }
  if (!have_format) throw InputError(source, "line 2", "missing the 'format' line in the header");
  for (const PlyElement& e : header.elements)
    if (e.properties.empty() && e.count > 0)
      throw InputError(source, "line " + std::to_string(e.header_line),
                       "element '" + e.name + "' declares " + std::to_string(e.count) + " items but no properties");
  header.body_offset = scanner.offset();
  header.body_first_line = scanner.line();
  return header;
}

// ---------------------------------------------------------------------------
// Value sources. Both read one scalar at a time as double (exact for every
// PLY type) and name the element item in their errors.

std::string itemName(const PlyElement& element, std::size_t index) {
  return element.name + " " + std::to_string(index);
}

class AsciiSource {
public:
  AsciiSource(std::string_view body, const std::string& source, std::size_t first_line)
      : scanner_(body, source, first_line), size_(body.size()) {}

  double read(ScalarType type, const PlyElement& element, std::size_t index, const std::string& property) {
    std::string_view token = scanner_.nextToken();
    if (token.empty())
      scanner_.fail("unexpected end of file in " + itemName(element, index) + ", expected property '" + property +
                    "' (" + plyTypeName(type) + "); the header declares " + std::to_string(element.count) + " " +
                    element.name + " items");
    double value = 0.0;
    bool ok;
    if (isFloatingPoint(type)) {
      ok = detail::parseNumber(token, value);
      if (ok && type == ScalarType::Float32) value = static_cast<float>(value);
    } else {
      long long integer = 0;
      ok = detail::parseNumber(token, integer) && representAs(type, static_cast<double>(integer)) == integer;
      value = static_cast<double>(integer);
    }
    if (!ok)
      scanner_.fail("in " + itemName(element, index) + ", expected a " + plyTypeName(type) + " for property '" +
                    property + "', found '" + TextScanner::clip(token) + "'");
    return value;
  }

  [[noreturn]] void fail(const PlyElement& element, std::size_t index, const std::string& detail) {
    scanner_.fail("in " + itemName(element, index) + ": " + detail);
  }

  void expectEnd() {
    std::string_view token = scanner_.nextToken();
    if (!token.empty())
      scanner_.fail("more data than the header declares: found '" + TextScanner::clip(token) +
                    "' after the last element");
  }

  /// Lower bound of the bytes one item of `element` takes: a digit and a separator per value.
  static std::size_t minimumItemBytes(const PlyElement& element) { return 2 * element.properties.size(); }
  std::size_t remaining() const { return size_ - scanner_.offset(); }

private:
  TextScanner scanner_;
  std::size_t size_;
};

template <typename T>
T loadScalar(const char* data, bool swap) {
  T value;
  if (!swap) {
    std::memcpy(&value, data, sizeof(T));
  } else {
    char reversed[sizeof(T)];
    for (std::size_t i = 0; i < sizeof(T); ++i) reversed[i] = data[sizeof(T) - 1 - i];
    std::memcpy(&value, reversed, sizeof(T));
  }
  return value;
}

class BinarySource {
public:
  BinarySource(std::string_view body, const std::string& source, bool swap, std::size_t body_offset)
      : body_(body), source_(source), swap_(swap), body_offset_(body_offset) {}

  double read(ScalarType type, const PlyElement& element, std::size_t index, const std::string& property) {
    const std::size_t size = scalarSize(type);
    if (body_.size() - pos_ < size)
      throw InputError(source_, itemName(element, index),
                       "unexpected end of file (byte " + std::to_string(body_offset_ + pos_) +
                           "), expected property '" + property + "' (" + plyTypeName(type) +
                           "); the header declares " + std::to_string(element.count) + " " + element.name + " items");
    const char* p = body_.data() + pos_;
    pos_ += size;
    switch (type) {
      case ScalarType::Int8: return loadScalar<std::int8_t>(p, false);
      case ScalarType::UInt8: return loadScalar<std::uint8_t>(p, false);
      case ScalarType::Int16: return loadScalar<std::int16_t>(p, swap_);
      case ScalarType::UInt16: return loadScalar<std::uint16_t>(p, swap_);
      case ScalarType::Int32: return loadScalar<std::int32_t>(p, swap_);
      case ScalarType::UInt32: return loadScalar<std::uint32_t>(p, swap_);
      case ScalarType::Float32: return loadScalar<float>(p, swap_);
      case ScalarType::Float64: return loadScalar<double>(p, swap_);
    }
    return 0.0;
  }

  [[noreturn]] void fail(const PlyElement& element, std::size_t index, const std::string& detail) {
    throw InputError(source_, itemName(element, index), detail);
  }

  void expectEnd() {
    // Writers sometimes pad with a line end or zeros; anything else means the
    // header's counts do not match the data.
    for (std::size_t i = pos_; i < body_.size(); ++i) {
      const char c = body_[i];
      if (c != '\n' && c != '\r' && c != ' ' && c != '\0')
        throw InputError(source_, "byte " + std::to_string(body_offset_ + pos_),
                         "more data than the header declares: " + std::to_string(body_.size() - pos_) +
                             " bytes left after the last element");
    }
  }

  static std::size_t minimumItemBytes(const PlyElement& element) {
    std::size_t bytes = 0;
    for (const PlyProperty& p : element.properties) bytes += scalarSize(p.is_list ? p.count_type : p.type);
    return bytes;
  }
  std::size_t remaining() const { return body_.size() - pos_; }

private:
  std::string_view body_;
  const std::string& source_;
  bool swap_;
  std::size_t body_offset_;
  std::size_t pos_ = 0;
};

// ---------------------------------------------------------------------------
// Body walker.

enum class VertexRole { Skip, X, Y, Z, NX, NY, NZ, Red, Green, Blue, Attribute, Count };

VertexRole roleOf(const PlyProperty& p) {
  if (p.is_list) return VertexRole::Skip;
  const std::string& n = p.name;
  if (n == "x") return VertexRole::X;
  if (n == "y") return VertexRole::Y;
  if (n == "z") return VertexRole::Z;
  if (n == "nx" || n == "normal_x") return VertexRole::NX;
  if (n == "ny" || n == "normal_y") return VertexRole::NY;
  if (n == "nz" || n == "normal_z") return VertexRole::NZ;
  if (p.type == ScalarType::UInt8) {
    if (n == "red" || n == "diffuse_red") return VertexRole::Red;
    if (n == "green" || n == "diffuse_green") return VertexRole::Green;
    if (n == "blue" || n == "diffuse_blue") return VertexRole::Blue;
  }
  return VertexRole::Attribute;
}

template <typename Source>
void checkCountFits(Source& source, const PlyElement& element, const std::string& file) {
  const std::size_t min_bytes = std::max<std::size_t>(1, Source::minimumItemBytes(element));
  // +1: the last ASCII value of a file may lack its trailing separator.
  if (element.count > (source.remaining() + 1) / min_bytes)
    throw InputError(file, "line " + std::to_string(element.header_line),
                     "the header declares " + std::to_string(element.count) + " " + element.name +
                         " items of at least " + std::to_string(min_bytes) + " bytes each, but only " +
                         std::to_string(source.remaining()) +
                         " bytes remain: the file is truncated or the count is wrong");
}

template <typename Source>
std::size_t readListCount(Source& source, const PlyProperty& p, const PlyElement& element, std::size_t index) {
  const double count = source.read(p.count_type, element, index, p.name + " (list count)");
  if (count < 0) source.fail(element, index, "negative list length " + std::to_string(count) + " for '" + p.name + "'");
  // Each list item takes at least one byte, which bounds a corrupted length.
  if (count > static_cast<double>(source.remaining()))
    source.fail(element, index, "list '" + p.name + "' claims " + std::to_string(static_cast<long long>(count)) +
                                    " items, more than the rest of the file holds");
  return static_cast<std::size_t>(count);
}

template <typename Source>
void readVertices(Source& source, const PlyElement& element, const std::string& file, PointCloud& cloud) {
  checkCountFits(source, element, file);
  std::vector<VertexRole> roles;
  bool has[static_cast<int>(VertexRole::Count)] = {};
  for (const PlyProperty& p : element.properties) {
    roles.push_back(roleOf(p));
    has[static_cast<int>(roles.back())] = true;
  }
  if (!has[static_cast<int>(VertexRole::X)] || !has[static_cast<int>(VertexRole::Y)] ||
      !has[static_cast<int>(VertexRole::Z)])
    throw InputError(file, "line " + std::to_string(element.header_line),
                     "the vertex element has no x, y and z properties");
  const bool normals = has[static_cast<int>(VertexRole::NX)] && has[static_cast<int>(VertexRole::NY)] &&
                       has[static_cast<int>(VertexRole::NZ)];
  const bool colours = has[static_cast<int>(VertexRole::Red)] && has[static_cast<int>(VertexRole::Green)] &&
                      has[static_cast<int>(VertexRole::Blue)];
  // A lone nx (or red) without its siblings is kept as a plain attribute.
  for (std::size_t k = 0; k < roles.size(); ++k) {
    VertexRole& r = roles[k];
    if (!normals && (r == VertexRole::NX || r == VertexRole::NY || r == VertexRole::NZ)) r = VertexRole::Attribute;
    if (!colours && (r == VertexRole::Red || r == VertexRole::Green || r == VertexRole::Blue)) r = VertexRole::Attribute;
  }

  const std::size_t n = element.count;
  cloud.positions.assign(n, Eigen::Vector3d::Zero());
  if (normals) cloud.normals.assign(n, Eigen::Vector3d::Zero());
  if (colours) cloud.colours.assign(n, Colour{0, 0, 0});
  // Add every attribute before taking pointers: adding may move the others.
  for (std::size_t k = 0; k < roles.size(); ++k)
    if (roles[k] == VertexRole::Attribute) {
      const PlyProperty& p = element.properties[k];
      cloud.attributes.add(p.name, p.type, n, 0.0);
    }
  std::vector<std::vector<double>*> attribute_of(roles.size(), nullptr);
  for (std::size_t k = 0; k < roles.size(); ++k)
    if (roles[k] == VertexRole::Attribute) attribute_of[k] = &cloud.attributes.get(element.properties[k].name).values;

  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < roles.size(); ++k) {
      const PlyProperty& p = element.properties[k];
      if (p.is_list) {
        const std::size_t length = readListCount(source, p, element, i);
        for (std::size_t j = 0; j < length; ++j) source.read(p.type, element, i, p.name);
        continue;
      }
      const double value = source.read(p.type, element, i, p.name);
      switch (roles[k]) {
        case VertexRole::X: cloud.positions[i].x() = value; break;
        case VertexRole::Y: cloud.positions[i].y() = value; break;
        case VertexRole::Z: cloud.positions[i].z() = value; break;
        case VertexRole::NX: cloud.normals[i].x() = value; break;
        case VertexRole::NY: cloud.normals[i].y() = value; break;
        case VertexRole::NZ: cloud.normals[i].z() = value; break;
        case VertexRole::Red: cloud.colours[i][0] = static_cast<std::uint8_t>(value); break;
        case VertexRole::Green: cloud.colours[i][1] = static_cast<std::uint8_t>(value); break;
        case VertexRole::Blue: cloud.colours[i][2] = static_cast<std::uint8_t>(value); break;
        case VertexRole::Attribute: (*attribute_of[k])[i] = value; break;
        case VertexRole::Skip:
        case VertexRole::Count: break;
      }
    }
    if (!cloud.positions[i].allFinite())
      source.fail(element, i, "non-finite vertex coordinate, expected finite x, y and z");
    if (normals && !cloud.normals[i].allFinite())
      source.fail(element, i, "non-finite normal, expected finite nx, ny and nz");
  }
}

template <typename Source>
void readFaces(Source& source, const PlyElement& element, const std::string& file, std::size_t vertex_count,
               std::vector<Triangle>& faces) {
  checkCountFits(source, element, file);
  int index_property = -1;
  for (std::size_t k = 0; k < element.properties.size(); ++k) {
    const PlyProperty& p = element.properties[k];
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index") && !isFloatingPoint(p.type)) {
      index_property = static_cast<int>(k);
      break;
    }
  }
  if (index_property < 0)
    throw InputError(file, "line " + std::to_string(element.header_line),
                     "the face element has no integer list property 'vertex_indices'");
  faces.reserve(element.count);
  std::vector<int> polygon;
  for (std::size_t i = 0; i < element.count; ++i) {
    for (std::size_t k = 0; k < element.properties.size(); ++k) {
      const PlyProperty& p = element.properties[k];
      if (!p.is_list) {
        source.read(p.type, element, i, p.name);
        continue;
      }
      const std::size_t length = readListCount(source, p, element, i);
      if (static_cast<int>(k) != index_property) {
        for (std::size_t j = 0; j < length; ++j) source.read(p.type, element, i, p.name);
        continue;
      }
      if (length < 3)
        source.fail(element, i, "a face needs at least 3 vertex indices, found " + std::to_string(length));
      polygon.clear();
      for (std::size_t j = 0; j < length; ++j) {
        const double index = source.read(p.type, element, i, p.name);
        if (index < 0 || index >= static_cast<double>(vertex_count))
          source.fail(element, i, "vertex index " + std::to_string(static_cast<long long>(index)) +
                                      " out of range, expected 0.." + std::to_string(vertex_count) + "-1");
        polygon.push_back(static_cast<int>(index));
      }
      for (std::size_t j = 1; j + 1 < polygon.size(); ++j) faces.emplace_back(polygon[0], polygon[j], polygon[j + 1]);
    }
  }
}

template <typename Source>
void skipElement(Source& source, const PlyElement& element, const std::string& file) {
  checkCountFits(source, element, file);
  for (std::size_t i = 0; i < element.count; ++i)
    for (const PlyProperty& p : element.properties) {
      if (!p.is_list) {
        source.read(p.type, element, i, p.name);
        continue;
      }
      const std::size_t length = readListCount(source, p, element, i);
      for (std::size_t j = 0; j < length; ++j) source.read(p.type, element, i, p.name);
    }
}

template <typename Source>
TriangleMesh readBody(Source& source, const PlyHeader& header, const std::string& file) {
  TriangleMesh mesh;
  bool have_vertices = false;
  const PlyElement* pending_faces = nullptr;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex" && !have_vertices) {
      readVertices(source, element, file, mesh.vertices);
      have_vertices = true;
    } else if (element.name == "face" && pending_faces == nullptr) {
      if (!have_vertices)
        throw InputError(file, "line " + std::to_string(element.header_line),
                         "the face element comes before the vertex element; expected vertices first");
      pending_faces = &element;
      readFaces(source, element, file, mesh.vertices.size(), mesh.faces);
    } else {
      skipElement(source, element, file);
    }
  }
  if (!have_vertices) throw InputError(file, "", "the file has no 'vertex' element");
  source.expectEnd();
  return mesh;
}

// ---------------------------------------------------------------------------
// Writer.

bool hostIsLittleEndian() {
  const std::uint16_t probe = 1;
  std::uint8_t first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

class BinarySink {
public:
  explicit BinarySink(bool swap) : swap_(swap) {}
  template <typename T>
  void put(T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (swap_) std::reverse(bytes, bytes + sizeof(T));
    buffer_.append(bytes, sizeof(T));
  }
  void putAs(ScalarType type, double value) {
    switch (type) {
      case ScalarType::Int8: put(static_cast<std::int8_t>(value)); break;
      case ScalarType::UInt8: put(static_cast<std::uint8_t>(value)); break;
      case ScalarType::Int16: put(static_cast<std::int16_t>(value)); break;
      case ScalarType::UInt16: put(static_cast<std::uint16_t>(value)); break;
      case ScalarType::Int32: put(static_cast<std::int32_t>(value)); break;
      case ScalarType::UInt32: put(static_cast<std::uint32_t>(value)); break;
      case ScalarType::Float32: put(static_cast<float>(value)); break;
      case ScalarType::Float64: put(value); break;
    }
  }
  void endItem() {}
  std::string& buffer() { return buffer_; }

private:
  bool swap_;
  std::string buffer_;
};

class AsciiSink {
public:
  void putAs(ScalarType type, double value) {
    if (!first_) buffer_.push_back(' ');
    first_ = false;
    if (type == ScalarType::Float64)
      detail::appendRoundTrip(buffer_, value);
    else if (type == ScalarType::Float32)
      detail::appendRoundTrip(buffer_, static_cast<float>(value));
    else
      buffer_ += std::to_string(static_cast<long long>(value));
  }
  void endItem() {
    buffer_.push_back('\n');
    first_ = true;
  }
  std::string& buffer() { return buffer_; }

private:
  bool first_ = true;
  std::string buffer_;
};

template <typename Sink>
void writeBody(Sink& sink, std::ostream& out, const PointCloud& v, const std::vector<Triangle>& faces,
               ScalarType real_type) {
  constexpr std::size_t flush_bytes = 1 << 20;
  auto flushIfLarge = [&] {
    if (sink.buffer().size() >= flush_bytes) {
      out.write(sink.buffer().data(), static_cast<std::streamsize>(sink.buffer().size()));
      sink.buffer().clear();
    }
  };
  for (std::size_t i = 0; i < v.size(); ++i) {
    for (int k = 0; k < 3; ++k) sink.putAs(real_type, v.positions[i][k]);
    if (v.hasNormals())
      for (int k = 0; k < 3; ++k) sink.putAs(real_type, v.normals[i][k]);
    if (v.hasColours())
      for (int k = 0; k < 3; ++k) sink.putAs(ScalarType::UInt8, v.colours[i][k]);
    for (const Attribute& a : v.attributes) sink.putAs(a.type, representAs(a.type, a.values[i]));
    sink.endItem();
    flushIfLarge();
  }
  for (const Triangle& f : faces) {
    sink.putAs(ScalarType::UInt8, 3);
    for (int k = 0; k < 3; ++k) sink.putAs(ScalarType::Int32, f[k]);
    sink.endItem();
    flushIfLarge();
  }
  out.write(sink.buffer().data(), static_cast<std::streamsize>(sink.buffer().size()));
}

}  // namespace

TriangleMesh parsePly(std::string_view bytes, const std::string& source) {
  const PlyHeader header = parseHeader(bytes, source);
  std::string_view body = bytes.substr(header.body_offset);
  if (header.format == PlyFormat::Ascii) {
    AsciiSource ascii(body, source, header.body_first_line);
    return readBody(ascii, header, source);
  }
  const bool file_little = header.format == PlyFormat::BinaryLittleEndian;
  BinarySource binary(body, source, file_little != hostIsLittleEndian(), header.body_offset);
  return readBody(binary, header, source);
}

void writePly(std::ostream& out, const PointCloud& vertices, const std::vector<Triangle>& faces,
              const WriteOptions& options) {
  const ScalarType real_type = options.real_type == ScalarType::Float32 ? ScalarType::Float32 : ScalarType::Float64;
  const bool ascii = options.encoding == Encoding::Ascii;
  std::string header = "ply\nformat ";
  header += ascii ? "ascii" : (options.big_endian ? "binary_big_endian" : "binary_little_endian");
  header += " 1.0\ncomment written by icrkit\n";
  header += "element vertex " + std::to_string(vertices.size()) + "\n";
  const std::string real = plyTypeName(real_type);
  for (const char* axis : {"x", "y", "z"}) header += "property " + real + " " + axis + "\n";
  if (vertices.hasNormals())
    for (const char* axis : {"nx", "ny", "nz"}) header += "property " + real + " " + axis + "\n";
  if (vertices.hasColours())
    for (const char* channel : {"red", "green", "blue"}) header += std::string("property uchar ") + channel + "\n";
  for (const Attribute& a : vertices.attributes) header += std::string("property ") + plyTypeName(a.type) + " " + a.name + "\n";
  if (!faces.empty()) {
    header += "element face " + std::to_string(faces.size()) + "\n";
    header += "property list uchar int vertex_indices\n";
  }
  header += "end_header\n";
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  if (ascii) {
    AsciiSink sink;
    writeBody(sink, out, vertices, faces, real_type);
  } else {
    BinarySink sink(options.big_endian == hostIsLittleEndian());
    writeBody(sink, out, vertices, faces, real_type);
  }
}

}  // namespace icrkit::io
