#include "input/mcap/cdr_reader.hpp"

#include <icrkit/core/error.hpp>

#include <cstring>

namespace icrkit::reconstruction::mcap {
namespace {
constexpr std::size_t kEncapsulationBytes = 4;
}

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size, std::string source, std::string where)
    : data_(data), size_(size), source_(std::move(source)), where_(std::move(where)) {
  if (size_ < kEncapsulationBytes) fail("the message is shorter than CDR's 4-byte encapsulation header");
  if (data_[0] != 0 || data_[1] > 1)
    fail("unsupported CDR encapsulation 0x" + std::to_string(data_[0]) + "," + std::to_string(data_[1]) +
         " (expected plain CDR: 0x00 0x01 little endian or 0x00 0x00 big endian)");
  little_endian_ = data_[1] == 1;
  pos_ = kEncapsulationBytes;
}

void CdrReader::fail(const std::string& detail) const {
  throw InputError(source_, where_, detail);
}

void CdrReader::need(std::size_t bytes, const char* what) const {
  if (bytes > size_ - pos_)
    fail(std::string("the message ends inside its ") + what + " (byte " + std::to_string(pos_) + " of " +
         std::to_string(size_) + ")");
}

void CdrReader::align(std::size_t alignment) {
  // Alignment counts from the end of the encapsulation header.
  const std::size_t misaligned = (pos_ - kEncapsulationBytes) % alignment;
  if (misaligned == 0) return;
  need(alignment - misaligned, "padding");
  pos_ += alignment - misaligned;
}

std::uint64_t CdrReader::unsignedInt(std::size_t bytes) {
  align(bytes);
  need(bytes, "fields");
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < bytes; ++i) {
    const std::uint64_t byte = data_[pos_ + (little_endian_ ? bytes - 1 - i : i)];
    value = (value << 8) | byte;
  }
  pos_ += bytes;
  return value;
}

std::uint8_t CdrReader::uint8() {
  return static_cast<std::uint8_t>(unsignedInt(1));
}
std::uint16_t CdrReader::uint16() {
  return static_cast<std::uint16_t>(unsignedInt(2));
}
std::uint32_t CdrReader::uint32() {
  return static_cast<std::uint32_t>(unsignedInt(4));
}
std::int32_t CdrReader::int32() {
  const std::uint32_t bits = uint32();
  std::int32_t value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
double CdrReader::float64() {
  const std::uint64_t bits = unsignedInt(8);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

std::string CdrReader::string() {
  const std::uint32_t length = uint32();
  need(length, "string");
  // The length counts the terminating NUL; a writer that omits it (length
  // 0 for an empty string) is tolerated.
  std::size_t characters = length;
  if (characters > 0 && data_[pos_ + characters - 1] == 0) --characters;
  std::string text(reinterpret_cast<const char*>(data_ + pos_), characters);
  pos_ += length;
  return text;
}

std::uint32_t CdrReader::sequenceLength(std::size_t min_element_bytes) {
  const std::uint32_t count = uint32();
  if (min_element_bytes > 0 && count > (size_ - pos_) / min_element_bytes)
    fail("a sequence of " + std::to_string(count) + " elements does not fit in the " +
         std::to_string(size_ - pos_) + " bytes left of the message");
  return count;
}

const std::uint8_t* CdrReader::bytes(std::size_t count) {
  need(count, "byte array");
  const std::uint8_t* start = data_ + pos_;
  pos_ += count;
  return start;
}

}  // namespace icrkit::reconstruction::mcap
