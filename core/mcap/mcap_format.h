// The MCAP container's wire vocabulary (https://mcap.dev/spec, major version 0): magic,
// record opcodes, and the little-endian primitives records are made of. The writer and
// the reader (mcap_writer.h, mcap_reader.h) share it; nothing here does any I/O.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace omniview::mcap {

// 0x89 "MCAP" '0' "\r\n": begins and ends every file.
inline constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};

enum Opcode : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// "Chunk", "Message", ... or "opcode 0x42": for messages.
std::string opcode_name(uint8_t opcode);

// Appends little-endian integers and the spec's length-prefixed strings and byte arrays.
class Bytes {
 public:
  explicit Bytes(std::string& out) : out_(out) {}
  Bytes& u8(uint8_t v) { return put(v, 1); }
  Bytes& u16(uint16_t v) { return put(v, 2); }
  Bytes& u32(uint32_t v) { return put(v, 4); }
  Bytes& u64(uint64_t v) { return put(v, 8); }
  Bytes& str(std::string_view s);     // uint32 length + bytes
  Bytes& bytes32(std::string_view s);  // uint32 length + bytes (Schema data)
  Bytes& bytes64(std::string_view s);  // uint64 length + bytes (Chunk records)
  Bytes& raw(std::string_view s) {
    out_.append(s);
    return *this;
  }

 private:
  Bytes& put(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
    return *this;
  }
  std::string& out_;
};

// One record: opcode, uint64 content length, content.
std::string record(uint8_t opcode, std::string_view content);

// Malformed or damaged MCAP data; the message names the file, the record and its offset.
struct McapError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads the same primitives from a record's content, bounds-checked: running past the end
// throws McapError naming `what` (the record) and the field.
class Cursor {
 public:
  Cursor(std::string_view data, std::string what) : data_(data), what_(std::move(what)) {}
  uint8_t u8(const char* field) { return static_cast<uint8_t>(get(1, field)); }
  uint16_t u16(const char* field) { return static_cast<uint16_t>(get(2, field)); }
  uint32_t u32(const char* field) { return static_cast<uint32_t>(get(4, field)); }
  uint64_t u64(const char* field) { return get(8, field); }
  std::string_view str(const char* field);      // uint32 length + bytes
  std::string_view bytes64(const char* field);  // uint64 length + bytes
  std::string_view take(uint64_t n, const char* field);
  std::string_view rest() {
    std::string_view r = data_.substr(pos_);
    pos_ = data_.size();
    return r;
  }
  size_t left() const { return data_.size() - pos_; }
  size_t pos() const { return pos_; }
  [[noreturn]] void fail(const std::string& why) const;

 private:
  uint64_t get(int n, const char* field);
  std::string_view data_;
  size_t pos_ = 0;
  std::string what_;
};

// zlib's CRC-32 (the one MCAP uses), continued from `crc` (0 to start).
uint32_t crc32_of(std::string_view data, uint32_t crc = 0);

}  // namespace omniview::mcap
