// Reads an MCAP file (https://mcap.dev/spec) front to back: every record listed, every CRC
// checked (chunks, the data section, the summary), chunks decompressed (zstd or stored),
// and the messages handed out in file order. A file cut short (a writer that crashed) is
// read up to its last complete record and reported as such; damage anywhere else (a wrong
// CRC, a record that does not parse, a message on an unknown channel) throws McapError
// naming the file, the record and its offset. Enough for our tests, our fuzz target and
// `omniview export`'s own check; the indexed readers of the Foxglove tools do the seeking.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/mcap/mcap_format.h"

namespace omniview::mcap {

struct SchemaInfo {
  uint16_t id = 0;
  std::string name, encoding, data;
};

struct ChannelInfo {
  uint16_t id = 0;
  uint16_t schema_id = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};

struct MessageInfo {
  uint16_t channel = 0;
  uint32_t sequence = 0;
  uint64_t log_time = 0, publish_time = 0;
  std::string data;
};

// One top-level record as found in the file (a chunk's inner records are not listed).
struct RecordInfo {
  uint8_t opcode = 0;
  uint64_t offset = 0;  // of its opcode byte
  uint64_t length = 0;  // of its content
};

struct StatisticsInfo {
  uint64_t message_count = 0;
  uint16_t schema_count = 0;
  uint32_t channel_count = 0, chunk_count = 0;
  uint64_t message_start_time = 0, message_end_time = 0;
  std::map<uint16_t, uint64_t> channel_message_counts;
};

struct ReadOptions {
  bool messages = true;                    // keep the messages' data (else only counted)
  uint64_t max_chunk_bytes = 256ull << 20;  // a chunk that claims more is refused (not allocated)
};

struct McapContents {
  std::string profile, library;
  std::map<uint16_t, SchemaInfo> schemas;
  std::map<uint16_t, ChannelInfo> channels;
  std::vector<MessageInfo> messages;  // in file order (empty data unless ReadOptions::messages)
  std::map<uint16_t, uint64_t> message_counts;  // per channel
  std::vector<RecordInfo> records;
  size_t chunk_count = 0;
  size_t chunk_index_count = 0;       // ChunkIndex records in the summary
  bool has_statistics = false;
  StatisticsInfo statistics;
  // A whole file: DataEnd, the summary, the footer and the closing magic, CRCs right. When
  // false, `cut_at` is where the last complete record ended and `why` says what was missing.
  bool complete = false;
  uint64_t cut_at = 0;
  std::string why;
};

// `name` only names the data in messages (a file's path). Throws McapError.
McapContents read_mcap(std::string_view data, const std::string& name, const ReadOptions& options = {});
// Reads the file first; throws std::runtime_error naming it when it cannot be read.
McapContents read_mcap_file(const std::string& path, const ReadOptions& options = {});

}  // namespace omniview::mcap
