#pragma once
/// \file
/// The subset of OMG CDR (XCDR1, "plain" CDR) that ROS 2 serialises its
/// messages in: a 4-byte encapsulation header (0x00 0x01: little endian,
/// 0x00 0x00: big endian), then primitives aligned to their own size
/// counted from the byte after the header, strings as a u32 length that
/// includes the terminating NUL, sequences as a u32 count.

#include <cstddef>
#include <cstdint>
#include <string>

namespace icrkit::reconstruction::mcap {

class CdrReader {
 public:
  /// `source` and `where` name the message in the InputErrors thrown for a
  /// header other than plain CDR and for any read past the end.
  CdrReader(const std::uint8_t* data, std::size_t size, std::string source, std::string where);

  std::uint8_t uint8();
  std::uint16_t uint16();
  std::uint32_t uint32();
  std::int32_t int32();
  double float64();
  std::string string();
  /// A sequence's element count, refused when the elements (each at least
  /// `min_element_bytes`) cannot fit in what is left.
  std::uint32_t sequenceLength(std::size_t min_element_bytes);
  /// `count` bytes (a uint8[] body), not copied.
  const std::uint8_t* bytes(std::size_t count);

  bool littleEndian() const { return little_endian_; }
  std::size_t remaining() const { return size_ - pos_; }
  [[noreturn]] void fail(const std::string& detail) const;

 private:
  void align(std::size_t alignment);
  void need(std::size_t bytes, const char* what) const;
  std::uint64_t unsignedInt(std::size_t bytes);

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  bool little_endian_ = true;
  std::string source_;
  std::string where_;
};

}  // namespace icrkit::reconstruction::mcap
