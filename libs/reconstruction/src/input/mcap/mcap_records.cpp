#include "input/mcap/mcap_records.hpp"

#include <icrkit/core/error.hpp>

#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>

namespace icrkit::reconstruction::mcap {
namespace {

enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kDataEnd = 0x0F,
};

constexpr std::uint64_t kRecordHeaderBytes = 9;  // opcode u8 + length u64
// Below this a chunk may expand by any ratio: a frame of zeros compresses
// far beyond kMaxExpansion, and such an allocation harms nobody.
constexpr std::uint64_t kAlwaysAcceptedChunkBytes = std::uint64_t(1) << 26;

std::uint64_t littleEndian(const std::uint8_t* p, int bytes) {
  std::uint64_t value = 0;
  for (int i = bytes - 1; i >= 0; --i) value = (value << 8) | p[i];
  return value;
}

// Bounds-checked little-endian fields of one record body.
class BodyCursor {
 public:
  BodyCursor(const std::uint8_t* data, std::size_t size, const std::string& path, std::string where)
      : data_(data), size_(size), path_(path), where_(std::move(where)) {}

  std::uint64_t unsignedInt(int bytes, const char* field) {
    need(static_cast<std::size_t>(bytes), field);
    const std::uint64_t value = littleEndian(data_ + pos_, bytes);
    pos_ += static_cast<std::size_t>(bytes);
    return value;
  }
  std::string string(const char* field) {
    const std::uint64_t length = unsignedInt(4, field);
    need(length, field);
    std::string text(reinterpret_cast<const char*>(data_ + pos_), static_cast<std::size_t>(length));
    pos_ += static_cast<std::size_t>(length);
    return text;
  }
  // A u32- or u64-prefixed byte array, not copied.
  const std::uint8_t* bytes(int prefix_bytes, const char* field, std::size_t& length) {
    const std::uint64_t n = unsignedInt(prefix_bytes, field);
    need(n, field);
    const std::uint8_t* start = data_ + pos_;
    pos_ += static_cast<std::size_t>(n);
    length = static_cast<std::size_t>(n);
    return start;
  }
  const std::uint8_t* rest(std::size_t& length) {
    length = size_ - pos_;
    const std::uint8_t* start = data_ + pos_;
    pos_ = size_;
    return start;
  }

 private:
  void need(std::uint64_t bytes, const char* field) const {
    if (bytes > size_ - pos_)
      throw InputError(path_, where_,
                       std::string("the record ends inside its ") + field + " (needs " + std::to_string(bytes) +
                           " bytes, " + std::to_string(size_ - pos_) + " left)");
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  const std::string& path_;
  std::string where_;
};

std::string recordAt(std::uint64_t offset) {
  return "record at byte " + std::to_string(offset);
}
std::string chunkAt(std::uint64_t offset) {
  return "chunk at byte " + std::to_string(offset);
}

Schema parseSchema(const std::uint8_t* body, std::size_t size, const std::string& path, const std::string& where) {
  BodyCursor cursor(body, size, path, where);
  Schema schema;
  schema.id = static_cast<std::uint16_t>(cursor.unsignedInt(2, "schema id"));
  schema.name = cursor.string("schema name");
  schema.encoding = cursor.string("schema encoding");
  std::size_t ignored = 0;
  cursor.bytes(4, "schema data", ignored);
  return schema;
}

Channel parseChannel(const std::uint8_t* body, std::size_t size, const std::string& path, const std::string& where) {
  BodyCursor cursor(body, size, path, where);
  Channel channel;
  channel.id = static_cast<std::uint16_t>(cursor.unsignedInt(2, "channel id"));
  channel.schema_id = static_cast<std::uint16_t>(cursor.unsignedInt(2, "channel schema id"));
  channel.topic = cursor.string("channel topic");
  channel.message_encoding = cursor.string("channel message encoding");
  return channel;
}

MessageView parseMessage(const std::uint8_t* body, std::size_t size, const std::string& path,
                         const std::string& where) {
  BodyCursor cursor(body, size, path, where);
  MessageView message;
  message.channel_id = static_cast<std::uint16_t>(cursor.unsignedInt(2, "message channel id"));
  cursor.unsignedInt(4, "message sequence");
  message.log_time = cursor.unsignedInt(8, "message log time");
  cursor.unsignedInt(8, "message publish time");
  message.data = cursor.rest(message.size);
  return message;
}

std::vector<std::uint8_t> decompressZstd(const std::uint8_t* data, std::size_t size, std::uint64_t expected,
                                         const std::string& path, std::uint64_t chunk_offset) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(expected));
  const std::size_t produced = ZSTD_decompress(out.data(), out.size(), data, size);
  if (ZSTD_isError(produced))
    throw InputError(path, chunkAt(chunk_offset), std::string("zstd: ") + ZSTD_getErrorName(produced));
  if (produced != expected)
    throw InputError(path, chunkAt(chunk_offset),
                     "zstd: decompressed to " + std::to_string(produced) + " bytes, the chunk declares " +
                         std::to_string(expected));
  return out;
}

std::vector<std::uint8_t> decompressLz4(const std::uint8_t* data, std::size_t size, std::uint64_t expected,
                                        const std::string& path, std::uint64_t chunk_offset) {
  LZ4F_dctx* raw_context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw_context, LZ4F_VERSION)))
    throw InputError(path, chunkAt(chunk_offset), "lz4: cannot create a decompression context");
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> context(
      raw_context, &LZ4F_freeDecompressionContext);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(expected));
  std::uint8_t scratch = 0;  // a valid destination once `out` is full
  std::size_t in_pos = 0, out_pos = 0;
  std::size_t hint = 1;
  // Frames may be concatenated; the declared size bounds the output.
  while (in_pos < size) {
    const bool full = out_pos == out.size();
    std::size_t out_room = full ? 0 : out.size() - out_pos;
    std::size_t in_room = size - in_pos;
    hint = LZ4F_decompress(context.get(), full ? &scratch : out.data() + out_pos, &out_room, data + in_pos,
                           &in_room, nullptr);
    if (LZ4F_isError(hint))
      throw InputError(path, chunkAt(chunk_offset), std::string("lz4: ") + LZ4F_getErrorName(hint));
    if (in_room == 0 && out_room == 0)
      throw InputError(path, chunkAt(chunk_offset),
                       "lz4: the data does not fit the " + std::to_string(expected) + " bytes the chunk declares");
    out_pos += out_room;
    in_pos += in_room;
  }
  if (hint != 0)
    throw InputError(path, chunkAt(chunk_offset), "lz4: the compressed data ends inside a frame");
  if (out_pos != expected)
    throw InputError(path, chunkAt(chunk_offset),
                     "lz4: decompressed to " + std::to_string(out_pos) + " bytes, the chunk declares " +
                         std::to_string(expected));
  return out;
}

}  // namespace

std::string describe(const MessageLocation& location) {
  return location.in_chunk ? chunkAt(location.record_offset) : recordAt(location.record_offset);
}

std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFFu] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

std::vector<std::uint8_t> decompressChunkRecords(const std::string& compression, const std::uint8_t* data,
                                                 std::size_t size, std::uint64_t uncompressed_size,
                                                 std::uint32_t uncompressed_crc, const std::string& path,
                                                 std::uint64_t chunk_offset) {
  if (uncompressed_size > kMaxChunkBytes ||
      (uncompressed_size > kAlwaysAcceptedChunkBytes && uncompressed_size / kMaxExpansion > size))
    throw InputError(path, chunkAt(chunk_offset),
                     "declares " + std::to_string(uncompressed_size) + " uncompressed bytes for " +
                         std::to_string(size) + " stored ones, more than a chunk can hold");
  std::vector<std::uint8_t> records;
  if (compression.empty()) {
    if (uncompressed_size != size)
      throw InputError(path, chunkAt(chunk_offset),
                       "an uncompressed chunk of " + std::to_string(size) + " bytes declares " +
                           std::to_string(uncompressed_size));
    records.assign(data, data + size);
  } else if (compression == "zstd") {
    records = decompressZstd(data, size, uncompressed_size, path, chunk_offset);
  } else if (compression == "lz4") {
    records = decompressLz4(data, size, uncompressed_size, path, chunk_offset);
  } else {
    throw InputError(path, chunkAt(chunk_offset),
                     "unknown chunk compression '" + compression + "' (expected none, zstd or lz4)");
  }
  if (uncompressed_crc != 0) {
    const std::uint32_t actual = crc32(records.data(), records.size());
    if (actual != uncompressed_crc)
      throw InputError(path, chunkAt(chunk_offset),
                       "CRC-32 of the records is " + std::to_string(actual) + ", the chunk declares " +
                           std::to_string(uncompressed_crc) + " (corrupt chunk)");
  }
  return records;
}

RecordFile::RecordFile(const std::string& path) : path_(path) {
  in_.open(path, std::ios::binary);
  if (!in_) throw InputError(path, "", "cannot be read");
  in_.seekg(0, std::ios::end);
  size_ = static_cast<std::uint64_t>(in_.tellg());
  in_.seekg(0);
  unsigned char magic[sizeof kMagic] = {};
  if (size_ < sizeof kMagic || !in_.read(reinterpret_cast<char*>(magic), sizeof magic) ||
      std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw InputError(path, "byte 0", "expected MCAP's magic bytes \\x89MCAP0\\r\\n");
  RecordHeader header;
  if (!readRecordHeader(sizeof kMagic, header) || header.opcode != kHeader)
    throw InputError(path, recordAt(sizeof kMagic), "expected the Header record (opcode 0x01) after the magic");
  data_start_ = header.offset + kRecordHeaderBytes + header.length;
}

bool RecordFile::readRecordHeader(std::uint64_t offset, RecordHeader& header) {
  if (offset >= size_) return false;
  if (size_ - offset < kRecordHeaderBytes)
    throw InputError(path_, recordAt(offset), "the file ends inside a record's opcode and length (truncated)");
  std::uint8_t bytes[kRecordHeaderBytes];
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(offset));
  if (!in_.read(reinterpret_cast<char*>(bytes), sizeof bytes)) throw InputError(path_, recordAt(offset), "cannot be read");
  header.opcode = bytes[0];
  header.length = littleEndian(bytes + 1, 8);
  header.offset = offset;
  const std::uint64_t left = size_ - offset - kRecordHeaderBytes;
  if (header.length > left)
    throw InputError(path_, recordAt(offset),
                     "declares " + std::to_string(header.length) + " bytes but the file holds " +
                         std::to_string(left) + " more (truncated or corrupt)");
  return true;
}

void RecordFile::readBody(const RecordHeader& header, std::vector<std::uint8_t>& body) {
  body.resize(static_cast<std::size_t>(header.length));
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(header.offset + kRecordHeaderBytes));
  if (!body.empty() && !in_.read(reinterpret_cast<char*>(body.data()), static_cast<std::streamsize>(body.size())))
    throw InputError(path_, recordAt(header.offset), "cannot be read");
}

const std::vector<std::uint8_t>& RecordFile::chunkRecords(std::uint64_t chunk_offset) {
  if (cached_chunk_offset_ == chunk_offset) return cached_chunk_;
  RecordHeader header;
  if (!readRecordHeader(chunk_offset, header) || header.opcode != kChunk)
    throw InputError(path_, chunkAt(chunk_offset), "expected a Chunk record");
  readBody(header, body_);
  const std::string where = chunkAt(chunk_offset);
  BodyCursor cursor(body_.data(), body_.size(), path_, where);
  cursor.unsignedInt(8, "message start time");
  cursor.unsignedInt(8, "message end time");
  const std::uint64_t uncompressed_size = cursor.unsignedInt(8, "uncompressed size");
  const auto uncompressed_crc = static_cast<std::uint32_t>(cursor.unsignedInt(4, "uncompressed CRC"));
  const std::string compression = cursor.string("compression");
  std::size_t stored = 0;
  const std::uint8_t* records = cursor.bytes(8, "records", stored);
  cached_chunk_offset_ = ~std::uint64_t(0);
  cached_chunk_ =
      decompressChunkRecords(compression, records, stored, uncompressed_size, uncompressed_crc, path_, chunk_offset);
  cached_chunk_offset_ = chunk_offset;
  return cached_chunk_;
}

void RecordFile::readAll(const std::function<void(const Schema&)>& on_schema,
                         const std::function<void(const Channel&)>& on_channel,
                         const std::function<void(const MessageView&)>& on_message) {
  // The records of one level (the file, or a chunk's records).
  auto visit = [&](std::uint8_t opcode, const std::uint8_t* body, std::size_t size, const std::string& where,
                   const MessageLocation& location) {
    if (opcode == kSchema) {
      on_schema(parseSchema(body, size, path_, where));
    } else if (opcode == kChannel) {
      on_channel(parseChannel(body, size, path_, where));
    } else if (opcode == kMessage) {
      MessageView message = parseMessage(body, size, path_, where);
      message.location = location;
      on_message(message);
    }
  };

  std::uint64_t offset = data_start_;
  RecordHeader header;
  while (readRecordHeader(offset, header)) {
    offset = header.offset + kRecordHeaderBytes + header.length;
    if (header.opcode == kDataEnd || header.opcode == kFooter) break;
    if (header.opcode == kSchema || header.opcode == kChannel || header.opcode == kMessage) {
      readBody(header, body_);
      MessageLocation location;
      location.record_offset = header.offset;
      visit(header.opcode, body_.data(), body_.size(), recordAt(header.offset), location);
    } else if (header.opcode == kChunk) {
      const std::vector<std::uint8_t>& records = chunkRecords(header.offset);
      std::size_t pos = 0;
      while (pos < records.size()) {
        const std::string where = chunkAt(header.offset) + ", record at byte " + std::to_string(pos) + " of its records";
        if (records.size() - pos < kRecordHeaderBytes)
          throw InputError(path_, where, "the chunk's records end inside a record's opcode and length");
        const std::uint8_t opcode = records[pos];
        const std::uint64_t length = littleEndian(records.data() + pos + 1, 8);
        const std::size_t body_start = pos + kRecordHeaderBytes;
        if (length > records.size() - body_start)
          throw InputError(path_, where,
                           "declares " + std::to_string(length) + " bytes but the chunk holds " +
                               std::to_string(records.size() - body_start) + " more");
        MessageLocation location;
        location.record_offset = header.offset;
        location.offset_in_chunk = pos;
        location.in_chunk = true;
        visit(opcode, records.data() + body_start, static_cast<std::size_t>(length), where, location);
        pos = body_start + static_cast<std::size_t>(length);
      }
    }
  }
}

MessageView RecordFile::messageAt(const MessageLocation& location) {
  if (!location.in_chunk) {
    RecordHeader header;
    if (!readRecordHeader(location.record_offset, header) || header.opcode != kMessage)
      throw InputError(path_, recordAt(location.record_offset), "expected a Message record");
    readBody(header, body_);
    MessageView message = parseMessage(body_.data(), body_.size(), path_, recordAt(location.record_offset));
    message.location = location;
    return message;
  }
  const std::vector<std::uint8_t>& records = chunkRecords(location.record_offset);
  const std::string where =
      chunkAt(location.record_offset) + ", record at byte " + std::to_string(location.offset_in_chunk);
  const std::size_t pos = static_cast<std::size_t>(location.offset_in_chunk);
  if (records.size() < kRecordHeaderBytes || pos > records.size() - kRecordHeaderBytes || records[pos] != kMessage)
    throw InputError(path_, where, "expected a Message record");
  const std::uint64_t length = littleEndian(records.data() + pos + 1, 8);
  if (length > records.size() - pos - kRecordHeaderBytes) throw InputError(path_, where, "truncated Message record");
  MessageView message =
      parseMessage(records.data() + pos + kRecordHeaderBytes, static_cast<std::size_t>(length), path_, where);
  message.location = location;
  return message;
}

}  // namespace icrkit::reconstruction::mcap
