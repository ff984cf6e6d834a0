// core/mcap: what the writer writes, the reader reads back (chunks, indexes, summary,
// CRCs); a file cut anywhere reads up to its last complete record; damage is named.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/mcap/mcap_reader.h"
#include "core/mcap/mcap_writer.h"

namespace omniview::mcap {
namespace {

namespace fs = std::filesystem;

class McapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (fs::temp_directory_path() / ("mcap_test_" + std::to_string(::getpid()) + "_" +
                                          ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".mcap"))
                .string();
  }
  void TearDown() override { fs::remove(path_); }

  // Two channels over one schema and one without; `n` messages each, small chunks.
  void write_file(int n, WriterOptions options = {}) {
    options.chunk_bytes = 4096;
    Writer w(path_, options);
    const uint16_t schema = w.add_schema("test.Blob", "protobuf", std::string("\x0a\x03" "abc", 5));
    const uint16_t a = w.add_channel(schema, "/a", "protobuf", {{"k", "v"}});
    const uint16_t b = w.add_channel(schema, "/b", "protobuf");
    const uint16_t c = w.add_channel(0, "/c", "json");
    for (int i = 0; i < n; ++i) {
      const uint64_t t = 1'700'000'000'000'000'000ull + uint64_t(i) * 1'000'000;
      w.write(a, t, t, std::string(100 + i, char('a' + i % 26)));
      w.write(b, t + 1, t + 1, std::string(300, char(i)));
      if (i % 10 == 0) w.write(c, t + 2, t + 2, "{\"i\":" + std::to_string(i) + "}");
    }
    w.close();
    EXPECT_EQ(w.message_count(), uint64_t(2 * n + (n + 9) / 10));
  }

  std::string bytes() const {
    std::ifstream in(path_, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  std::string path_;
};

TEST_F(McapTest, RoundTripKeepsSchemasChannelsMessagesAndStatistics) {
  write_file(100);
  const McapContents m = read_mcap_file(path_);
  EXPECT_TRUE(m.complete) << m.why;
  EXPECT_EQ(m.library, "omniview");
  ASSERT_EQ(m.schemas.size(), 1u);
  EXPECT_EQ(m.schemas.at(1).name, "test.Blob");
  EXPECT_EQ(m.schemas.at(1).data, std::string("\x0a\x03" "abc", 5));
  ASSERT_EQ(m.channels.size(), 3u);
  EXPECT_EQ(m.channels.at(1).topic, "/a");
  EXPECT_EQ(m.channels.at(1).metadata.at("k"), "v");
  EXPECT_EQ(m.channels.at(3).schema_id, 0);
  EXPECT_EQ(m.message_counts.at(1), 100u);
  EXPECT_EQ(m.message_counts.at(2), 100u);
  EXPECT_EQ(m.message_counts.at(3), 10u);
  EXPECT_GT(m.chunk_count, 5u) << "4 KiB chunks";
  EXPECT_EQ(m.chunk_index_count, m.chunk_count);
  ASSERT_TRUE(m.has_statistics);
  EXPECT_EQ(m.statistics.message_count, 210u);
  EXPECT_EQ(m.statistics.chunk_count, m.chunk_count);
  EXPECT_EQ(m.statistics.channel_message_counts.at(2), 100u);
  EXPECT_EQ(m.statistics.message_start_time, 1'700'000'000'000'000'000ull);
  EXPECT_EQ(m.statistics.message_end_time, 1'700'000'000'000'000'000ull + 99'000'000 + 1);
  // Per channel, sequences count from 0 and data come back as written.
  uint32_t next_a = 0;
  for (const auto& msg : m.messages) {
    if (msg.channel != 1) continue;
    EXPECT_EQ(msg.sequence, next_a);
    EXPECT_EQ(msg.data, std::string(100 + next_a, char('a' + next_a % 26)));
    ++next_a;
  }
  EXPECT_EQ(next_a, 100u);
}

TEST_F(McapTest, UncompressedChunksReadToo) {
  WriterOptions options;
  options.compression = "";
  write_file(20, options);
  const McapContents m = read_mcap_file(path_);
  EXPECT_TRUE(m.complete);
  EXPECT_EQ(m.messages.size(), 42u);
}

TEST_F(McapTest, ZstdMakesRepetitiveDataSmall) {
  write_file(200);
  EXPECT_LT(fs::file_size(path_), 200u * 400 / 4);
}

TEST_F(McapTest, AFileCutAnywhereReadsUpToItsLastCompleteRecord) {
  write_file(60);
  const std::string whole = bytes();
  const McapContents full = read_mcap(whole, path_);
  size_t last_messages = 0;
  // Every cut: never an exception, and messages only grow with the length kept.
  for (size_t n = 0; n < whole.size(); n += (n < 64 ? 1 : 97)) {
    const std::string cut = whole.substr(0, n);
    McapContents m;
    ASSERT_NO_THROW(m = read_mcap(cut, "cut")) << "cut at " << n;
    EXPECT_FALSE(m.complete) << "cut at " << n;
    EXPECT_LE(m.cut_at, n);
    EXPECT_GE(m.messages.size(), last_messages) << "cut at " << n;
    last_messages = m.messages.size();
  }
  // Cut just before DataEnd: every message is there.
  const auto data_end = std::find_if(full.records.begin(), full.records.end(),
                                     [](const RecordInfo& r) { return r.opcode == kDataEnd; });
  ASSERT_NE(data_end, full.records.end());
  const McapContents m = read_mcap(std::string_view(whole).substr(0, data_end->offset + 10), "cut");
  EXPECT_FALSE(m.complete);
  EXPECT_EQ(m.cut_at, data_end->offset);
  EXPECT_EQ(m.messages.size(), full.messages.size());
  EXPECT_NE(m.why.find("DataEnd record at offset"), std::string::npos) << m.why;
}

TEST_F(McapTest, DamageIsNamedWithTheRecordAndItsOffset) {
  write_file(30);
  const std::string whole = bytes();
  const McapContents full = read_mcap(whole, path_);
  const auto chunk = std::find_if(full.records.begin(), full.records.end(),
                                  [](const RecordInfo& r) { return r.opcode == kChunk; });
  ASSERT_NE(chunk, full.records.end());
  std::string damaged = whole;
  damaged[chunk->offset + 9 + 8 + 8 + 8] ^= 1;  // its uncompressed CRC
  try {
    read_mcap(damaged, "x.mcap");
    FAIL() << "a wrong chunk CRC was not noticed";
  } catch (const McapError& e) {
    EXPECT_NE(std::string(e.what()).find("x.mcap: Chunk record at offset " + std::to_string(chunk->offset)),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("CRC"), std::string::npos) << e.what();
  }
  // The summary's CRC: a flipped byte in a ChunkIndex.
  const auto index = std::find_if(full.records.begin(), full.records.end(),
                                  [](const RecordInfo& r) { return r.opcode == kChunkIndex; });
  ASSERT_NE(index, full.records.end());
  damaged = whole;
  damaged[index->offset + 9 + 3] ^= 1;  // message_start_time's third byte
  EXPECT_THROW(read_mcap(damaged, "x.mcap"), McapError);
  // The data section's CRC (DataEnd): a flipped byte of the Header's library string.
  damaged = whole;
  damaged[8 + 9 + 4 + 4] ^= 1;
  EXPECT_THROW(read_mcap(damaged, "x.mcap"), McapError);
  EXPECT_THROW(read_mcap("GIF89a...", "x.gif"), McapError);
}

TEST_F(McapTest, WritingToAFolderThatIsNotThereNamesThePath) {
  try {
    Writer w("/nonexistent-folder/x.mcap");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/x.mcap"), std::string::npos) << e.what();
  }
}

TEST_F(McapTest, AFullDiskIsAnErrorNamingTheFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  try {
    Writer w("/dev/full");
    w.add_channel(0, "/x", "json");
    for (int i = 0; i < 1000; ++i) w.write(1, i, i, std::string(1000, 'x'));
    w.close();
    FAIL() << "writing to a full disk went unnoticed";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write '/dev/full'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace omniview::mcap
