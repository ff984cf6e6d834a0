#include "core/mcap/mcap_writer.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include <zstd.h>

#include "core/mcap/mcap_format.h"

namespace omniview::mcap {

// Where a chunk went, for its ChunkIndex in the summary.
struct ChunkIndexEntry {
  uint64_t start_time = 0, end_time = 0;
  uint64_t offset = 0, length = 0;
  std::map<uint16_t, uint64_t> index_offsets;  // channel -> its MessageIndex's file offset
  uint64_t index_length = 0;
  uint64_t compressed = 0, uncompressed = 0;
};

struct Writer::Impl {
  std::string path;
  WriterOptions options;
  std::FILE* file = nullptr;
  uint64_t position = 0;  // bytes written so far
  uint32_t data_crc = 0;  // of everything before DataEnd
  bool closed = false;

  std::vector<std::string> schema_records, channel_records;  // for the summary
  std::vector<bool> schema_written, channel_written;         // into the data section yet?
  std::vector<uint16_t> channel_schema;
  std::vector<uint32_t> sequence;
  std::map<uint16_t, uint64_t> channel_counts;
  uint64_t messages = 0;
  uint64_t first_time = std::numeric_limits<uint64_t>::max(), last_time = 0;

  // The open chunk: its records, and per channel the (log time, offset) of each message.
  std::string chunk;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index;
  uint64_t chunk_start = std::numeric_limits<uint64_t>::max(), chunk_end = 0;
  std::vector<ChunkIndexEntry> chunks;
  ZSTD_CCtx* zstd = nullptr;

  void put(std::string_view bytes, bool in_data_section = true) {
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size()) {
      throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
    }
    if (in_data_section) data_crc = crc32_of(bytes, data_crc);
    position += bytes.size();
  }

  void flush_chunk() {
    if (chunk.empty()) return;
    ChunkIndexEntry entry;
    entry.start_time = chunk_start == std::numeric_limits<uint64_t>::max() ? 0 : chunk_start;
    entry.end_time = chunk_end;
    entry.uncompressed = chunk.size();
    std::string stored;
    if (options.compression == "zstd") {
      stored.resize(ZSTD_compressBound(chunk.size()));
      const size_t n = ZSTD_compressCCtx(zstd, stored.data(), stored.size(), chunk.data(), chunk.size(),
                                         options.zstd_level);
      if (ZSTD_isError(n)) throw std::runtime_error("'" + path + "': zstd: " + ZSTD_getErrorName(n));
      stored.resize(n);
    } else {
      stored = chunk;
    }
    entry.compressed = stored.size();
    std::string content;
    Bytes(content)
        .u64(entry.start_time)
        .u64(entry.end_time)
        .u64(chunk.size())
        .u32(crc32_of(chunk))
        .str(options.compression)
        .bytes64(stored);
    entry.offset = position;
    put(record(kChunk, content));
    entry.length = position - entry.offset;
    const uint64_t index_start = position;
    for (const auto& [channel, entries] : chunk_index) {
      std::string index;
      Bytes b(index);
      b.u16(channel).u32(static_cast<uint32_t>(entries.size() * 16));
      for (const auto& [time, offset] : entries) b.u64(time).u64(offset);
      entry.index_offsets[channel] = position;
      put(record(kMessageIndex, index));
    }
    entry.index_length = position - index_start;
    chunks.push_back(std::move(entry));
    chunk.clear();
    chunk_index.clear();
    chunk_start = std::numeric_limits<uint64_t>::max();
    chunk_end = 0;
  }

  void finish() {
    flush_chunk();
    std::string data_end;
    Bytes(data_end).u32(data_crc);
    put(record(kDataEnd, data_end), false);

    const uint64_t summary_start = position;
    uint32_t summary_crc = 0;
    auto summary = [&](std::string_view bytes) {
      summary_crc = crc32_of(bytes, summary_crc);
      put(bytes, false);
    };
    struct Group {
      uint8_t opcode;
      uint64_t start, length;
    };
    std::vector<Group> groups;
    auto group = [&](uint8_t opcode, const std::vector<std::string>& records) {
      if (records.empty()) return;
      const uint64_t start = position;
      for (const auto& r : records) summary(r);
      groups.push_back({opcode, start, position - start});
    };
    group(kSchema, schema_records);
    group(kChannel, channel_records);
    {
      std::string stats;
      Bytes b(stats);
      b.u64(messages)
          .u16(static_cast<uint16_t>(schema_records.size()))
          .u32(static_cast<uint32_t>(channel_records.size()))
          .u32(0)  // attachments
          .u32(0)  // metadata
          .u32(static_cast<uint32_t>(chunks.size()))
          .u64(messages ? first_time : 0)
          .u64(messages ? last_time : 0)
          .u32(static_cast<uint32_t>(channel_counts.size() * 10));
      for (const auto& [channel, count] : channel_counts) b.u16(channel).u64(count);
      group(kStatistics, {record(kStatistics, stats)});
    }
    std::vector<std::string> indexes;
    for (const auto& c : chunks) {
      std::string content;
      Bytes b(content);
      b.u64(c.start_time).u64(c.end_time).u64(c.offset).u64(c.length);
      b.u32(static_cast<uint32_t>(c.index_offsets.size() * 10));
      for (const auto& [channel, offset] : c.index_offsets) b.u16(channel).u64(offset);
      b.u64(c.index_length).str(options.compression).u64(c.compressed).u64(c.uncompressed);
      indexes.push_back(record(kChunkIndex, content));
    }
    group(kChunkIndex, indexes);

    const uint64_t offsets_start = position;
    for (const auto& g : groups) {
      std::string content;
      Bytes(content).u8(g.opcode).u64(g.start).u64(g.length);
      summary(record(kSummaryOffset, content));
    }
    // The footer's CRC covers the summary, the offsets and the footer up to the CRC itself.
    std::string footer;
    Bytes(footer).u8(kFooter).u64(20).u64(summary_start).u64(offsets_start);
    summary_crc = crc32_of(footer, summary_crc);
    Bytes(footer).u32(summary_crc);
    put(footer, false);
    put(kMagic, false);
    if (std::fflush(file) != 0) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
  }
};

Writer::Writer(const std::string& path, WriterOptions options) : impl_(std::make_unique<Impl>()) {
  if (options.compression != "zstd" && !options.compression.empty()) {
    throw std::invalid_argument("MCAP compression '" + options.compression + "': only zstd or none");
  }
  impl_->path = path;
  impl_->options = std::move(options);
  impl_->file = std::fopen(path.c_str(), "wb");
  if (!impl_->file) throw std::runtime_error("cannot create '" + path + "': " + std::strerror(errno));
  impl_->zstd = ZSTD_createCCtx();
  if (!impl_->zstd) throw std::runtime_error("'" + path + "': zstd: out of memory");
  impl_->put(kMagic);
  std::string header;
  Bytes(header).str(impl_->options.profile).str(impl_->options.library);
  impl_->put(record(kHeader, header));
}

Writer::~Writer() {
  try {
    close();
  } catch (const std::exception&) {
  }
  if (impl_->zstd) ZSTD_freeCCtx(impl_->zstd);
}

uint16_t Writer::add_schema(const std::string& name, const std::string& encoding, std::string_view data) {
  if (impl_->schema_records.size() >= 0xfffe) throw std::invalid_argument("MCAP: too many schemas");
  const auto id = static_cast<uint16_t>(impl_->schema_records.size() + 1);
  std::string content;
  Bytes(content).u16(id).str(name).str(encoding).bytes32(data);
  impl_->schema_records.push_back(record(kSchema, content));
  impl_->schema_written.push_back(false);
  return id;
}

uint16_t Writer::add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                             const std::map<std::string, std::string>& metadata) {
  if (schema_id > impl_->schema_records.size()) {
    throw std::invalid_argument("MCAP channel '" + topic + "': no schema " + std::to_string(schema_id));
  }
  if (impl_->channel_records.size() >= 0xfffe) throw std::invalid_argument("MCAP: too many channels");
  const auto id = static_cast<uint16_t>(impl_->channel_records.size() + 1);
  std::string content;
  Bytes b(content);
  b.u16(id).u16(schema_id).str(topic).str(message_encoding);
  std::string map;
  for (const auto& [k, v] : metadata) Bytes(map).str(k).str(v);
  b.bytes32(map);
  impl_->channel_records.push_back(record(kChannel, content));
  impl_->channel_written.push_back(false);
  impl_->channel_schema.push_back(schema_id);
  impl_->sequence.push_back(0);
  return id;
}

void Writer::write(uint16_t channel, uint64_t log_time, uint64_t publish_time, std::string_view data) {
  Impl& m = *impl_;
  if (m.closed) throw std::logic_error("MCAP '" + m.path + "': write after close");
  if (channel == 0 || channel > m.channel_records.size()) {
    throw std::invalid_argument("MCAP '" + m.path + "': no channel " + std::to_string(channel));
  }
  const size_t c = channel - 1;
  // The records a reader needs before this message, in this same chunk.
  if (const uint16_t schema = m.channel_schema[c]; schema != 0 && !m.schema_written[schema - 1]) {
    m.chunk += m.schema_records[schema - 1];
    m.schema_written[schema - 1] = true;
  }
  if (!m.channel_written[c]) {
    m.chunk += m.channel_records[c];
    m.channel_written[c] = true;
  }
  m.chunk_index[channel].emplace_back(log_time, m.chunk.size());
  std::string head;
  Bytes(head).u8(kMessage).u64(2 + 4 + 8 + 8 + data.size()).u16(channel).u32(m.sequence[c]++).u64(log_time).u64(
      publish_time);
  m.chunk += head;
  m.chunk.append(data);
  m.chunk_start = std::min(m.chunk_start, log_time);
  m.chunk_end = std::max(m.chunk_end, log_time);
  m.first_time = std::min(m.first_time, log_time);
  m.last_time = std::max(m.last_time, log_time);
  ++m.channel_counts[channel];
  ++m.messages;
  if (m.chunk.size() >= m.options.chunk_bytes) {
    m.flush_chunk();
    // A schema or channel is repeated in the next chunk only for a reader that starts
    // there: the indexed readers take them from the summary; keep each written once.
  }
}

void Writer::close() {
  Impl& m = *impl_;
  if (m.closed) return;
  m.closed = true;  // one try: a failed close leaves a file cut short, which readers handle
  try {
    m.finish();
  } catch (...) {
    std::fclose(m.file);
    m.file = nullptr;
    throw;
  }
  const int rc = std::fclose(m.file);
  m.file = nullptr;
  if (rc != 0) throw std::runtime_error("cannot write '" + m.path + "': " + std::strerror(errno));
}

uint64_t Writer::message_count() const { return impl_->messages; }

uint64_t Writer::bytes_written() const { return impl_->position; }

}  // namespace omniview::mcap
