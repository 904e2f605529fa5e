#pragma once
/// \file
/// The record layer of MCAP (https://mcap.dev/spec): the data section read
/// front to back, chunks decompressed (none, zstd, lz4) and CRC-checked, and
/// any message found again later by where it was seen. The summary section
/// is never needed, so bags whose recorder died before writing it are read.

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace icrkit::reconstruction::mcap {

inline constexpr unsigned char kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

/// A chunk may not claim more than this uncompressed, nor more than
/// kMaxExpansion times its compressed size: a corrupt size must not become
/// an allocation.
inline constexpr std::uint64_t kMaxChunkBytes = std::uint64_t(1) << 31;
inline constexpr std::uint64_t kMaxExpansion = 1024;

struct Schema {
  std::uint16_t id = 0;
  std::string name;      ///< e.g. sensor_msgs/msg/Image
  std::string encoding;  ///< ros2msg for ROS 2
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;  ///< cdr for ROS 2
};

/// Where a message lies: the top-level record holding it (a Chunk or the
/// Message itself) and, inside a chunk, its offset in the decompressed records.
struct MessageLocation {
  std::uint64_t record_offset = 0;
  std::uint64_t offset_in_chunk = 0;
  bool in_chunk = false;
};

/// "chunk at byte N" or "record at byte N", for error messages.
std::string describe(const MessageLocation& location);

struct MessageView {
  std::uint16_t channel_id = 0;
  std::uint64_t log_time = 0;  ///< nanoseconds
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  MessageLocation location;
};

/// The standard CRC-32 (zlib's, reflected polynomial 0xEDB88320) MCAP uses.
std::uint32_t crc32(const std::uint8_t* data, std::size_t size);

/// Decompresses a chunk's records. Throws InputError(path, "chunk at byte
/// N", ...) for an unknown compression, undecodable data, a size other than
/// the one declared, an implausible size or a CRC mismatch.
std::vector<std::uint8_t> decompressChunkRecords(const std::string& compression, const std::uint8_t* data,
                                                 std::size_t size, std::uint64_t uncompressed_size,
                                                 std::uint32_t uncompressed_crc, const std::string& path,
                                                 std::uint64_t chunk_offset);

/// One bag file opened for reading. Not thread-safe.
class RecordFile {
 public:
  /// Opens the file and checks the magic and the Header record.
  explicit RecordFile(const std::string& path);

  /// Reads the data section in file order: every schema, channel and
  /// message, chunks included, until DataEnd, the Footer or the end of the
  /// file. Unknown records are skipped. The message's bytes are valid only
  /// during the call.
  void readAll(const std::function<void(const Schema&)>& on_schema,
               const std::function<void(const Channel&)>& on_channel,
               const std::function<void(const MessageView&)>& on_message);

  /// The message found at `location` by readAll(). Keeps the last chunk
  /// decompressed, so that reading messages in file order decompresses
  /// each chunk once.
  MessageView messageAt(const MessageLocation& location);

  const std::string& path() const { return path_; }

 private:
  struct RecordHeader {
    std::uint8_t opcode = 0;
    std::uint64_t length = 0;
    std::uint64_t offset = 0;  ///< of the opcode
  };
  bool readRecordHeader(std::uint64_t offset, RecordHeader& header);
  void readBody(const RecordHeader& header, std::vector<std::uint8_t>& body);
  const std::vector<std::uint8_t>& chunkRecords(std::uint64_t chunk_offset);

  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::uint64_t data_start_ = 0;  ///< first record after the Header
  std::vector<std::uint8_t> body_;
  std::uint64_t cached_chunk_offset_ = ~std::uint64_t(0);
  std::vector<std::uint8_t> cached_chunk_;
};

}  // namespace icrkit::reconstruction::mcap
