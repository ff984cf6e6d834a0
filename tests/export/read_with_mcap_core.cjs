// Reads an MCAP file with @mcap/core's McapIndexedReader and prints what it found, one
// fact a line, for tests/export/export_test.cc to compare with its own reader:
//   library TEXT
//   schema ID NAME ENCODING
//   channel ID TOPIC SCHEMA_NAME MESSAGE_ENCODING COUNT     (counted by reading every message)
//   statistics MESSAGES START_NS END_NS CHUNKS
//   decoded SCHEMA_NAME JSON                                (the first message of each schema)
// Exits non-zero, saying why, where the file or the counts disagree.
"use strict";
const fs = require("fs");
const { McapIndexedReader } = require("@mcap/core");
const protobuf = require("protobufjs");
require("protobufjs/ext/descriptor");
const fzstd = require("fzstd");

function fail(why) {
  console.error("read_with_mcap_core: " + why);
  process.exit(1);
}

async function main() {
  const file = process.argv[2];
  if (!file) fail("usage: read_with_mcap_core.cjs FILE.mcap");
  const fd = fs.openSync(file, "r");
  const size = fs.fstatSync(fd).size;
  const readable = {
    size: async () => BigInt(size),
    read: async (offset, length) => {
      const buffer = Buffer.alloc(Number(length));
      fs.readSync(fd, buffer, 0, Number(length), Number(offset));
      return new Uint8Array(buffer.buffer, buffer.byteOffset, buffer.length);
    },
  };
  const reader = await McapIndexedReader.Initialize({
    readable,
    decompressHandlers: { zstd: (data, decompressedSize) => fzstd.decompress(data, new Uint8Array(Number(decompressedSize))) },
  });
  console.log("library " + reader.header.library);
  const types = new Map();
  for (const [id, schema] of reader.schemasById) {
    console.log(`schema ${id} ${schema.name} ${schema.encoding}`);
    if (schema.encoding !== "protobuf") continue;
    const root = protobuf.Root.fromDescriptor(Buffer.from(schema.data));
    types.set(id, root.lookupType(schema.name));
  }
  if (!reader.statistics) fail("no Statistics record in the summary");
  if (reader.chunkIndexes.length === 0) fail("no ChunkIndex records in the summary");
  const counts = new Map();
  const decoded = new Map();
  let last = -1n;
  for await (const message of reader.readMessages()) {
    if (message.logTime < last) fail("messages out of log-time order");
    last = message.logTime;
    counts.set(message.channelId, (counts.get(message.channelId) || 0) + 1);
    const channel = reader.channelsById.get(message.channelId);
    if (!channel) fail("a message on unknown channel " + message.channelId);
    if (!decoded.has(channel.schemaId) && types.has(channel.schemaId)) {
      const type = types.get(channel.schemaId);
      const object = type.toObject(type.decode(message.data), { longs: String, bytes: String });
      // Long byte fields (images, video, points) shortened to their length.
      for (const [k, v] of Object.entries(object)) {
        if (typeof v === "string" && v.length > 64) object[k] = `<${Buffer.from(v, "base64").length} bytes>`;
      }
      decoded.set(channel.schemaId, object);
    }
  }
  for (const [id, channel] of reader.channelsById) {
    const schema = reader.schemasById.get(channel.schemaId);
    const n = counts.get(id) || 0;
    const stated = reader.statistics.channelMessageCounts.get(id);
    if (stated !== undefined && BigInt(n) !== stated) fail(`${channel.topic}: ${n} messages read, Statistics say ${stated}`);
    console.log(`channel ${id} ${channel.topic} ${schema ? schema.name : "-"} ${channel.messageEncoding} ${n}`);
  }
  const s = reader.statistics;
  console.log(`statistics ${s.messageCount} ${s.messageStartTime} ${s.messageEndTime} ${s.chunkCount}`);
  for (const [id, object] of decoded) console.log(`decoded ${reader.schemasById.get(id).name} ${JSON.stringify(object)}`);
}

main().catch((e) => fail(e && e.stack ? e.stack : String(e)));
