// Writes an MCAP file (https://mcap.dev/spec) as Foxglove, Lichtblick and the mcap tools
// read it best: messages in chunks of about `chunk_bytes`, each zstd-compressed and followed
// by one MessageIndex per channel; then DataEnd (the data section's CRC), a summary
// section (Schemas, Channels, Statistics, ChunkIndexes), a SummaryOffset per group and
// the Footer (the summary's CRC). Schema and Channel records also go into the data section,
// in the chunk before the first message that needs them, so a file cut short (a crash
// before close()) is still readable front to back up to its last complete chunk.
//
// Not written: attachments, metadata, their indexes. One thread at a time.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>

namespace omniview::mcap {

struct WriterOptions {
  std::string profile;                // the Header's profile ("" : none in particular)
  std::string library = "omniview";   // the Header's library
  size_t chunk_bytes = 1 << 20;       // a chunk is closed once its records reach this size
  std::string compression = "zstd";   // "zstd" or "" (stored)
  int zstd_level = 3;
};

class Writer {
 public:
  // Creates (or truncates) `path` and writes the magic and Header. Throws std::runtime_error
  // naming the path when it cannot.
  Writer(const std::string& path, WriterOptions options = {});
  ~Writer();  // close()s, swallowing errors (call close() to see them)
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Ids count from 1 (a Channel's schema id 0 means "no schema").
  uint16_t add_schema(const std::string& name, const std::string& encoding, std::string_view data);
  uint16_t add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                       const std::map<std::string, std::string>& metadata = {});
  // One message; its sequence number counts per channel from 0. Throws std::invalid_argument
  // for an unknown channel, std::runtime_error naming the file if a write fails (disk full).
  void write(uint16_t channel, uint64_t log_time_ns, uint64_t publish_time_ns, std::string_view data);

  // Finishes the file (last chunk, DataEnd, summary, footer, magic). Throws
  // std::runtime_error naming the file if a write fails.
  void close();

  uint64_t message_count() const;
  uint64_t bytes_written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace omniview::mcap
