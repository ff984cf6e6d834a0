#include "core/mcap/mcap_reader.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <zstd.h>

namespace omniview::mcap {

namespace {

std::string at(const std::string& name, uint8_t opcode, uint64_t offset) {
  return name + ": " + opcode_name(opcode) + " record at offset " + std::to_string(offset);
}

std::string hex32(uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", v);
  return text;
}

class Reader {
 public:
  Reader(std::string_view data, const std::string& name, const ReadOptions& options, McapContents& out)
      : data_(data), name_(name), options_(options), out_(out) {}

  void read() {
    if (data_.size() < kMagic.size() || data_.substr(0, kMagic.size()) != kMagic) {
      if (data_.size() < kMagic.size() && kMagic.substr(0, data_.size()) == data_) {
        cut(0, "the file ends inside its opening magic");
        return;
      }
      throw McapError(name_ + ": not an MCAP file (no MCAP magic at its start)");
    }
    uint64_t pos = kMagic.size();
    bool first = true, data_end = false;
    uint64_t summary_start = 0;
    while (true) {
      if (data_.size() - pos < 9) {
        cut(pos, data_.size() == pos ? "the file ends after a complete record, before its footer"
                                     : "the file ends inside a record's opcode or length");
        return;
      }
      const auto opcode = static_cast<uint8_t>(data_[pos]);
      Cursor head(data_.substr(pos + 1, 8), at(name_, opcode, pos));
      const uint64_t length = head.u64("length");
      if (length > data_.size() - pos - 9) {
        cut(pos, at(name_, opcode, pos) + " is cut short (" + std::to_string(length) + " bytes of content, " +
                     std::to_string(data_.size() - pos - 9) + " in the file)");
        return;
      }
      const std::string_view content = data_.substr(pos + 9, length);
      const std::string what = at(name_, opcode, pos);
      if (first && opcode != kHeader) throw McapError(what + ": the first record must be a Header");
      out_.records.push_back({opcode, pos, length});
      const uint64_t next = pos + 9 + length;
      if (opcode == kFooter) {
        footer(content, what, pos, summary_start, data_end);
        if (data_.size() - next < kMagic.size()) {
          cut(next, "the file ends inside its closing magic");
          return;
        }
        if (data_.substr(next, kMagic.size()) != kMagic) throw McapError(name_ + ": no closing magic after the Footer");
        if (data_.size() != next + kMagic.size()) throw McapError(name_ + ": bytes after the closing magic");
        out_.complete = true;
        return;
      }
      if (opcode == kDataEnd) {
        Cursor c(content, what);
        const uint32_t crc = c.u32("data_section_crc");
        const uint32_t actual = crc32_of(data_.substr(0, pos));
        if (crc != 0 && crc != actual) {
          throw McapError(what + ": data section CRC " + hex32(crc) + " but the data reads " + hex32(actual));
        }
        data_end = true;
        summary_start = next;
      } else if (!data_end) {
        data_record(opcode, content, what, first);
      } else {
        summary_record(opcode, content, what);
      }
      first = false;
      pos = next;
    }
  }

 private:
  void cut(uint64_t at, std::string why) {
    out_.complete = false;
    out_.cut_at = at;
    out_.why = std::move(why);
  }

  void data_record(uint8_t opcode, std::string_view content, const std::string& what, bool first) {
    switch (opcode) {
      case kHeader: {
        if (!first) throw McapError(what + ": a second Header");
        Cursor c(content, what);
        out_.profile = c.str("profile");
        out_.library = c.str("library");
        return;
      }
      case kChunk: return chunk(content, what);
      case kSchema:
      case kChannel:
      case kMessage: return inner_record(opcode, content, what);
      case kMessageIndex: {
        Cursor c(content, what);
        c.u16("channel_id");
        const uint32_t bytes = c.u32("records");
        if (bytes % 16 != 0) c.fail("its records' length " + std::to_string(bytes) + " is not a multiple of 16");
        c.take(bytes, "records");
        return;
      }
      default: return;  // attachments, metadata and records of later versions: skipped, as the spec says
    }
  }

  void chunk(std::string_view content, const std::string& what) {
    Cursor c(content, what);
    c.u64("message_start_time");
    c.u64("message_end_time");
    const uint64_t size = c.u64("uncompressed_size");
    const uint32_t crc = c.u32("uncompressed_crc");
    const std::string compression(c.str("compression"));
    const std::string_view stored = c.bytes64("records");
    if (size > options_.max_chunk_bytes) {
      c.fail("uncompressed size " + std::to_string(size) + " exceeds the limit of " +
             std::to_string(options_.max_chunk_bytes) + " bytes");
    }
    std::string plain;
    if (compression.empty()) {
      plain.assign(stored);
    } else if (compression == "zstd") {
      // A frame that says its size must say the chunk's (checked before allocating).
      const unsigned long long framed = ZSTD_getFrameContentSize(stored.data(), stored.size());
      if (framed == ZSTD_CONTENTSIZE_ERROR) c.fail("its records are not zstd data");
      if (framed != ZSTD_CONTENTSIZE_UNKNOWN && framed != size) {
        c.fail("uncompressed size " + std::to_string(size) + " but its zstd frame holds " + std::to_string(framed));
      }
      plain.resize(size);
      const size_t n = ZSTD_decompress(plain.data(), plain.size(), stored.data(), stored.size());
      if (ZSTD_isError(n)) c.fail(std::string("zstd: ") + ZSTD_getErrorName(n));
      plain.resize(n);
    } else {
      c.fail("compression '" + compression + "' is not supported (zstd or none)");
    }
    if (plain.size() != size) {
      c.fail("uncompressed size " + std::to_string(size) + " but the records are " + std::to_string(plain.size()) +
             " bytes");
    }
    if (crc != 0 && crc32_of(plain) != crc) {
      c.fail("uncompressed CRC " + hex32(crc) + " but the records read " + hex32(crc32_of(plain)));
    }
    ++out_.chunk_count;
    size_t pos = 0;
    while (pos < plain.size()) {
      if (plain.size() - pos < 9) c.fail("a record inside the chunk is cut short at " + std::to_string(pos));
      const auto opcode = static_cast<uint8_t>(plain[pos]);
      Cursor head(std::string_view(plain).substr(pos + 1, 8), what);
      const uint64_t length = head.u64("inner record length");
      if (length > plain.size() - pos - 9) c.fail("its record at " + std::to_string(pos) + " runs past its end");
      const std::string inner_what = what + ", its " + opcode_name(opcode) + " at " + std::to_string(pos);
      if (opcode == kSchema || opcode == kChannel || opcode == kMessage) {
        inner_record(opcode, std::string_view(plain).substr(pos + 9, length), inner_what);
      } else if (opcode == kChunk || opcode == kHeader || opcode == kFooter || opcode == kDataEnd ||
                 opcode == kMessageIndex || opcode == kChunkIndex) {
        throw McapError(inner_what + ": not allowed inside a chunk");
      }
      pos += 9 + length;
    }
  }

  void inner_record(uint8_t opcode, std::string_view content, const std::string& what) {
    Cursor c(content, what);
    if (opcode == kSchema) {
      SchemaInfo s;
      s.id = c.u16("id");
      s.name = c.str("name");
      s.encoding = c.str("encoding");
      s.data = c.str("data");
      if (s.id == 0) c.fail("schema id 0 is reserved");
      remember(out_.schemas, s.id, std::move(s), what, "schema");
    } else if (opcode == kChannel) {
      ChannelInfo ch;
      ch.id = c.u16("id");
      ch.schema_id = c.u16("schema_id");
      ch.topic = c.str("topic");
      ch.message_encoding = c.str("message_encoding");
      Cursor map(c.str("metadata"), what + " metadata");
      while (map.left() > 0) {
        std::string key(map.str("key"));
        ch.metadata[key] = map.str("value");
      }
      if (ch.schema_id != 0 && !out_.schemas.count(ch.schema_id)) {
        c.fail("channel '" + ch.topic + "' names schema " + std::to_string(ch.schema_id) + ", which came before it nowhere");
      }
      remember(out_.channels, ch.id, std::move(ch), what, "channel");
    } else {
      MessageInfo m;
      m.channel = c.u16("channel_id");
      m.sequence = c.u32("sequence");
      m.log_time = c.u64("log_time");
      m.publish_time = c.u64("publish_time");
      const std::string_view data = c.rest();
      if (!out_.channels.count(m.channel)) c.fail("a message on channel " + std::to_string(m.channel) + ", which is not defined before it");
      ++out_.message_counts[m.channel];
      if (options_.messages) m.data.assign(data);
      out_.messages.push_back(std::move(m));
    }
  }

  template <typename T>
  void remember(std::map<uint16_t, T>& into, uint16_t id, T value, const std::string& what, const char* kind) {
    const auto [it, inserted] = into.emplace(id, value);
    if (inserted) return;
    // The same record may come again (in a later chunk, in the summary); a different one may not.
    bool same;
    if constexpr (std::is_same_v<T, SchemaInfo>) {
      same = it->second.name == value.name && it->second.encoding == value.encoding && it->second.data == value.data;
    } else {
      same = it->second.topic == value.topic && it->second.schema_id == value.schema_id &&
             it->second.message_encoding == value.message_encoding && it->second.metadata == value.metadata;
    }
    if (!same) throw McapError(what + ": " + kind + " " + std::to_string(id) + " defined twice, differently");
  }

  void summary_record(uint8_t opcode, std::string_view content, const std::string& what) {
    Cursor c(content, what);
    switch (opcode) {
      case kSchema:
      case kChannel: return inner_record(opcode, content, what);
      case kChunkIndex: {
        c.u64("message_start_time");
        c.u64("message_end_time");
        const uint64_t offset = c.u64("chunk_start_offset");
        c.u64("chunk_length");
        Cursor map(c.str("message_index_offsets"), what);
        while (map.left() > 0) {
          map.u16("channel");
          map.u64("offset");
        }
        c.u64("message_index_length");
        c.str("compression");
        c.u64("compressed_size");
        c.u64("uncompressed_size");
        if (offset >= data_.size() || static_cast<uint8_t>(data_[offset]) != kChunk) {
          c.fail("chunk_start_offset " + std::to_string(offset) + " does not point at a Chunk");
        }
        ++out_.chunk_index_count;
        return;
      }
      case kStatistics: {
        StatisticsInfo& s = out_.statistics;
        s.message_count = c.u64("message_count");
        s.schema_count = c.u16("schema_count");
        s.channel_count = c.u32("channel_count");
        c.u32("attachment_count");
        c.u32("metadata_count");
        s.chunk_count = c.u32("chunk_count");
        s.message_start_time = c.u64("message_start_time");
        s.message_end_time = c.u64("message_end_time");
        Cursor map(c.str("channel_message_counts"), what);
        while (map.left() > 0) {
          const uint16_t channel = map.u16("channel");
          s.channel_message_counts[channel] = map.u64("count");
        }
        out_.has_statistics = true;
        return;
      }
      case kSummaryOffset: {
        const uint8_t group = c.u8("group_opcode");
        const uint64_t start = c.u64("group_start");
        const uint64_t length = c.u64("group_length");
        if (start > data_.size() || length > data_.size() - start) {
          c.fail("the " + opcode_name(group) + " group it points at lies outside the file");
        }
        return;
      }
      case kHeader:
      case kChunk:
      case kMessage:
      case kMessageIndex: throw McapError(what + ": not allowed in the summary section");
      default: return;
    }
  }

  void footer(std::string_view content, const std::string& what, uint64_t pos, uint64_t summary_start,
              bool data_end) {
    Cursor c(content, what);
    const uint64_t start = c.u64("summary_start");
    const uint64_t offsets = c.u64("summary_offset_start");
    const uint32_t crc = c.u32("summary_crc");
    if (!data_end) throw McapError(what + ": a Footer without a DataEnd record before it");
    if (start != 0 && start != summary_start) {
      c.fail("summary_start " + std::to_string(start) + " but the summary starts at " + std::to_string(summary_start));
    }
    if (offsets != 0 && (offsets < summary_start || offsets > pos)) {
      c.fail("summary_offset_start " + std::to_string(offsets) + " lies outside the summary");
    }
    if (crc != 0 && start != 0) {
      const uint32_t actual = crc32_of(data_.substr(start, pos + 1 + 8 + 16 - start));
      if (actual != crc) c.fail("summary CRC " + hex32(crc) + " but the summary reads " + hex32(actual));
    }
    if (out_.has_statistics) {
      uint64_t total = 0;
      for (const auto& [_, n] : out_.message_counts) total += n;
      if (out_.statistics.message_count != total) {
        c.fail("Statistics count " + std::to_string(out_.statistics.message_count) + " messages, the file holds " +
               std::to_string(total));
      }
    }
  }

  std::string_view data_;
  const std::string& name_;
  const ReadOptions& options_;
  McapContents& out_;
};

}  // namespace

McapContents read_mcap(std::string_view data, const std::string& name, const ReadOptions& options) {
  McapContents out;
  Reader(data, name, options, out).read();
  return out;
}

McapContents read_mcap_file(const std::string& path, const ReadOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open '" + path + "': " + std::strerror(errno));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw std::runtime_error("cannot read '" + path + "'");
  return read_mcap(bytes.view(), path, options);
}

}  // namespace omniview::mcap
