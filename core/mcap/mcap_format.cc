#include "core/mcap/mcap_format.h"

#include <cstdio>

#include <zlib.h>

namespace omniview::mcap {

std::string opcode_name(uint8_t opcode) {
  switch (opcode) {
    case kHeader: return "Header";
    case kFooter: return "Footer";
    case kSchema: return "Schema";
    case kChannel: return "Channel";
    case kMessage: return "Message";
    case kChunk: return "Chunk";
    case kMessageIndex: return "MessageIndex";
    case kChunkIndex: return "ChunkIndex";
    case kAttachment: return "Attachment";
    case kAttachmentIndex: return "AttachmentIndex";
    case kStatistics: return "Statistics";
    case kMetadata: return "Metadata";
    case kMetadataIndex: return "MetadataIndex";
    case kSummaryOffset: return "SummaryOffset";
    case kDataEnd: return "DataEnd";
  }
  char text[32];
  std::snprintf(text, sizeof text, "opcode 0x%02x", opcode);
  return text;
}

Bytes& Bytes::str(std::string_view s) {
  u32(static_cast<uint32_t>(s.size()));
  return raw(s);
}

Bytes& Bytes::bytes32(std::string_view s) { return str(s); }

Bytes& Bytes::bytes64(std::string_view s) {
  u64(s.size());
  return raw(s);
}

std::string record(uint8_t opcode, std::string_view content) {
  std::string out;
  out.reserve(9 + content.size());
  Bytes(out).u8(opcode).u64(content.size()).raw(content);
  return out;
}

void Cursor::fail(const std::string& why) const { throw McapError(what_ + ": " + why); }

uint64_t Cursor::get(int n, const char* field) {
  if (left() < static_cast<size_t>(n)) {
    fail(std::string("ends inside its field '") + field + "'");
  }
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(static_cast<uint8_t>(data_[pos_ + i])) << (8 * i);
  pos_ += n;
  return v;
}

std::string_view Cursor::take(uint64_t n, const char* field) {
  if (n > left()) {
    fail(std::string("field '") + field + "' says " + std::to_string(n) + " bytes, but only " +
         std::to_string(left()) + " are left in the record");
  }
  std::string_view r = data_.substr(pos_, n);
  pos_ += n;
  return r;
}

std::string_view Cursor::str(const char* field) { return take(u32(field), field); }

std::string_view Cursor::bytes64(const char* field) { return take(u64(field), field); }

uint32_t crc32_of(std::string_view data, uint32_t crc) {
  // zlib takes uInt lengths: feed large buffers in pieces.
  const auto* p = reinterpret_cast<const Bytef*>(data.data());
  size_t left = data.size();
  uLong c = crc;
  while (left > 0) {
    const uInt n = static_cast<uInt>(std::min<size_t>(left, 1u << 30));
    c = ::crc32(c, p, n);
    p += n;
    left -= n;
  }
  return static_cast<uint32_t>(c);
}

}  // namespace omniview::mcap
