// The MCAP conformance corpus, generated here because its committed `.mcap` files are Git LFS objects: the
// variant matrix of foxglove/mcap's tests/conformance (six inputs × the writer's feature switches, 416 files),
// written record by record with the official TypeScript writer (@mcap/core's McapRecordBuilder and
// McapChunkBuilder), then read back with the official streamed reader (@mcap/core's McapStreamReader, CRCs
// checked) to state what each file holds. Used by tests/mcap_conformance.rs.
//
// Usage: node generate.mjs OUT_DIR
// Writes OUT_DIR/<input>/<variant>.mcap and prints one JSON array: for every variant its name, path, features,
// its SHA-256 and what the reader found (messages, per-topic counts and message encodings, log-time range,
// attachments, metadata).
import { crc32, crc32Final, crc32Init, crc32Update } from "@foxglove/crc";
import { McapChunkBuilder, McapRecordBuilder, McapStreamReader, Opcode } from "@mcap/core";
import { createHash } from "node:crypto";
import fs from "node:fs";
import path from "node:path";

// The writer's feature switches and their short names (the variant names use them, sorted).
const F = {
  chunks: "ch",
  messageIndex: "mx",
  statistics: "st",
  repeatedSchemas: "rsh",
  repeatedChannels: "rch",
  attachmentIndex: "ax",
  metadataIndex: "mdx",
  chunkIndex: "chx",
  summaryOffsets: "sum",
  padding: "pad",
};

const schema = { type: "Schema", id: 1, name: "Example", encoding: "c", data: new Uint8Array([4, 5, 6]) };
const channel = {
  type: "Channel",
  id: 1,
  topic: "example",
  schemaId: 1,
  messageEncoding: "a",
  metadata: new Map([["foo", "bar"]]),
};
const message = (logTime, publishTime, sequence) => ({
  type: "Message",
  channelId: 1,
  publishTime,
  logTime,
  data: new Uint8Array([1, 2, 3]),
  sequence,
});

// The six inputs (log times out of order on purpose in TenMessages).
const INPUTS = [
  ["NoData", []],
  [
    "OneSchemalessMessage",
    [{ ...channel, schemaId: 0, messageEncoding: "text", metadata: new Map() }, message(2n, 1n, 10)],
  ],
  ["OneMessage", [schema, channel, message(2n, 1n, 10)]],
  [
    "OneAttachment",
    [
      {
        type: "Attachment",
        name: "myFile",
        mediaType: "application/octet-stream",
        logTime: 2n,
        createTime: 1n,
        data: new Uint8Array([1, 2, 3]),
      },
    ],
  ],
  ["OneMetadata", [{ type: "Metadata", name: "myMetadata", metadata: new Map([["foo", "bar"]]) }]],
  [
    "TenMessages",
    [schema, channel, ...[0n, 2n, 1n, 3n, 3n, 5n, 4n, 7n, 8n, 9n].map((t, i) => message(t, t, i))],
  ],
];

// Every subset of the switches, kept when it makes sense for the input (the generator's own rules).
function* variants() {
  const all = Object.values(F);
  for (const [base, records] of INPUTS) {
    const has = (type) => records.some((r) => r.type === type);
    for (let mask = 0; mask < 1 << all.length; mask++) {
      const f = new Set(all.filter((_, i) => mask & (1 << i)));
      if (f.has(F.attachmentIndex) && !has("Attachment")) continue;
      if (f.has(F.metadataIndex) && !has("Metadata")) continue;
      if (f.has(F.repeatedSchemas) && !has("Schema")) continue;
      if (f.has(F.repeatedChannels) && !has("Channel")) continue;
      const streams = has("Message") || has("Channel") || has("Schema");
      if (!streams && (f.has(F.chunks) || f.has(F.chunkIndex) || f.has(F.messageIndex))) continue;
      const summarised = [
        F.chunkIndex,
        F.repeatedSchemas,
        F.repeatedChannels,
        F.metadataIndex,
        F.attachmentIndex,
        F.statistics,
      ].some((x) => f.has(x));
      if (f.has(F.summaryOffsets) && !summarised) continue;
      if ((f.has(F.chunkIndex) || f.has(F.messageIndex)) && !f.has(F.chunks)) continue;
      yield { base, name: [base, ...[...f].sort()].join("-"), records, features: f };
    }
  }
}

// One file: data section (one chunk or loose records), then the summary the switches ask for, footer, magic.
function write(f, records) {
  const b = new McapRecordBuilder({ padRecords: f.has(F.padding) });
  b.writeMagic();
  b.writeHeader({ profile: "", library: "" });
  const chunk = f.has(F.chunks) ? new McapChunkBuilder({ useMessageIndex: f.has(F.messageIndex) }) : undefined;
  const stats = { messages: 0n, channels: 0, schemas: 0, attachments: 0, metadata: 0, perChannel: new Map() };
  let start, end;
  const attachmentIndexes = [];
  const metadataIndexes = [];
  const chunkIndexes = [];
  for (const r of records) {
    if (r.type === "Schema") {
      stats.schemas++;
      chunk ? chunk.addSchema(r) : b.writeSchema(r);
    } else if (r.type === "Channel") {
      stats.channels++;
      chunk ? chunk.addChannel(r) : b.writeChannel(r);
    } else if (r.type === "Message") {
      stats.messages++;
      stats.perChannel.set(r.channelId, (stats.perChannel.get(r.channelId) ?? 0n) + 1n);
      chunk ? chunk.addMessage(r) : b.writeMessage(r);
      if (start === undefined || r.logTime < start) start = r.logTime;
      if (end === undefined || r.logTime > end) end = r.logTime;
    } else if (r.type === "Attachment") {
      stats.attachments++;
      const offset = BigInt(b.length);
      const length = b.writeAttachment(r);
      if (f.has(F.attachmentIndex)) {
        attachmentIndexes.push({
          name: r.name,
          length,
          offset,
          dataSize: BigInt(r.data.byteLength),
          mediaType: r.mediaType,
          logTime: r.logTime,
          createTime: r.createTime,
        });
      }
    } else if (r.type === "Metadata") {
      stats.metadata++;
      const offset = BigInt(b.length);
      const length = b.writeMetadata(r);
      if (f.has(F.metadataIndex)) metadataIndexes.push({ name: r.name, length, offset });
    }
  }
  if (chunk) {
    const chunkStartOffset = BigInt(b.length);
    const size = BigInt(chunk.buffer.byteLength);
    const chunkLength = b.writeChunk({
      compression: "",
      messageStartTime: chunk.messageStartTime,
      messageEndTime: chunk.messageEndTime,
      uncompressedCrc: crc32(chunk.buffer),
      uncompressedSize: size,
      records: chunk.buffer,
    });
    const messageIndexOffsets = new Map();
    let messageIndexLength = 0n;
    for (const index of chunk.indices) {
      messageIndexOffsets.set(index.channelId, BigInt(b.length));
      messageIndexLength += b.writeMessageIndex(index);
    }
    if (f.has(F.chunkIndex)) {
      chunkIndexes.push({
        compression: "",
        messageStartTime: chunk.messageStartTime,
        messageEndTime: chunk.messageEndTime,
        uncompressedSize: size,
        compressedSize: size,
        chunkStartOffset,
        chunkLength,
        messageIndexLength,
        messageIndexOffsets,
      });
    }
  }
  b.writeDataEnd({ dataSectionCrc: crc32(b.buffer) });

  const summaryStart = BigInt(b.length);
  const groups = [];
  const group = (opcode, emit) => {
    const at = BigInt(b.length);
    emit();
    const length = BigInt(b.length) - at;
    if (length !== 0n) groups.push({ groupOpcode: opcode, groupStart: at, groupLength: length });
  };
  group(Opcode.SCHEMA, () => {
    if (f.has(F.repeatedSchemas)) records.filter((r) => r.type === "Schema").forEach((r) => b.writeSchema(r));
  });
  group(Opcode.CHANNEL, () => {
    if (f.has(F.repeatedChannels)) records.filter((r) => r.type === "Channel").forEach((r) => b.writeChannel(r));
  });
  group(Opcode.STATISTICS, () => {
    if (!f.has(F.statistics)) return;
    b.writeStatistics({
      messageCount: stats.messages,
      channelCount: stats.channels,
      schemaCount: stats.schemas,
      attachmentCount: stats.attachments,
      metadataCount: stats.metadata,
      chunkCount: chunk ? 1 : 0,
      messageStartTime: start ?? 0n,
      messageEndTime: end ?? 0n,
      channelMessageCounts: stats.perChannel,
    });
  });
  group(Opcode.METADATA_INDEX, () => metadataIndexes.forEach((r) => b.writeMetadataIndex(r)));
  group(Opcode.ATTACHMENT_INDEX, () => attachmentIndexes.forEach((r) => b.writeAttachmentIndex(r)));
  group(Opcode.CHUNK_INDEX, () => chunkIndexes.forEach((r) => b.writeChunkIndex(r)));
  const hasSummary = BigInt(b.length) !== summaryStart;
  let summaryOffsetStart = 0n;
  if (f.has(F.summaryOffsets)) {
    summaryOffsetStart = BigInt(b.length);
    groups.forEach((g) => b.writeSummaryOffset(g));
  }
  // The summary CRC covers the summary and the footer up to its own CRC field.
  let crc = crc32Init();
  const buf = b.buffer;
  crc = crc32Update(crc, new Uint8Array(buf.buffer, buf.byteOffset + Number(summaryStart), buf.byteLength - Number(summaryStart)));
  const head = new DataView(new ArrayBuffer(25));
  head.setUint8(0, Opcode.FOOTER);
  head.setBigUint64(1, 20n, true);
  head.setBigUint64(9, hasSummary ? summaryStart : 0n, true);
  head.setBigUint64(17, summaryOffsetStart, true);
  crc = crc32Final(crc32Update(crc, head));
  b.writeFooter({ summaryStart: hasSummary ? summaryStart : 0n, summaryOffsetStart, summaryCrc: crc });
  b.writeMagic();
  return b.buffer;
}

// What the official streamed reader finds in a file (chunks opened, CRCs checked).
function read(bytes) {
  const reader = new McapStreamReader({ validateCrcs: true });
  reader.append(bytes);
  const topics = new Map();
  const counts = {};
  const encodings = {};
  let messages = 0;
  let start = null;
  let end = null;
  let attachments = 0;
  let metadata = 0;
  for (let r; (r = reader.nextRecord()); ) {
    if (r.type === "Channel") {
      topics.set(r.id, r.topic);
      counts[r.topic] ??= 0;
      encodings[r.topic] ??= r.messageEncoding;
    }
    else if (r.type === "Message") {
      messages++;
      const topic = topics.get(r.channelId);
      counts[topic] = (counts[topic] ?? 0) + 1;
      if (start === null || r.logTime < start) start = r.logTime;
      if (end === null || r.logTime > end) end = r.logTime;
    } else if (r.type === "Attachment") attachments++;
    else if (r.type === "Metadata") metadata++;
  }
  if (!reader.done()) throw new Error("the reader did not reach the end of the file");
  return {
    messages,
    topics: counts,
    encodings,
    start_ns: start === null ? null : Number(start),
    end_ns: end === null ? null : Number(end),
    attachments,
    metadata,
  };
}

const out = process.argv[2];
if (!out) {
  console.error("usage: node generate.mjs OUT_DIR");
  process.exit(2);
}
const manifest = [];
for (const v of variants()) {
  const dir = path.join(out, v.base);
  fs.mkdirSync(dir, { recursive: true });
  const file = path.join(dir, `${v.name}.mcap`);
  const bytes = write(v.features, v.records);
  fs.writeFileSync(file, bytes);
  const sha256 = createHash("sha256").update(bytes).digest("hex");
  manifest.push({ name: v.name, path: file, sha256, features: [...v.features].sort(), ...read(bytes) });
}
process.stdout.write(JSON.stringify(manifest));
