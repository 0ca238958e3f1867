// Reads the fixtures written by make_fixtures.mjs back and checks them
// against expected.json:
//   - McapStreamReader (every file): records, CRCs, messages in file order;
//   - McapIndexedReader (files with a summary): statistics, indexes, and
//     messages in log-time order;
//   - message payloads decoded twice: with @foxglove/cdr's CdrReader and with
//     a small hand-written decoder that applies the CDR alignment rules itself;
//   - every compressed chunk decompressed again with the zstd / lz4 command-line
//     tools (when installed) and compared with the wasm decompressors' output.
//
// Usage: node check_fixtures.mjs <fixtures folder>   (e.g. ../../data/mcap)

import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { execFileSync } from "node:child_process";

import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { CdrReader } from "@foxglove/cdr";
import zstd from "@foxglove/wasm-zstd";
import lz4 from "@foxglove/wasm-lz4";

const dir = process.argv[2];
if (!dir) {
  console.error("usage: node check_fixtures.mjs <fixtures folder>");
  process.exit(2);
}
const expected = JSON.parse(fs.readFileSync(path.join(dir, "expected.json"), "utf8"));

await zstd.isLoaded;
await lz4.isLoaded;
const decompressHandlers = {
  zstd: (buf, size) => zstd.decompress(buf, Number(size)),
  lz4: (buf, size) => lz4(buf, Number(size)),
};

let failures = 0;
let passes = 0;
function check(cond, what) {
  if (cond) passes++;
  else {
    failures++;
    console.log(`  FAIL: ${what}`);
  }
}
// Structural equality (BigInts compared as decimal strings).
const json = (v) => JSON.stringify(v, (_, x) => (typeof x === "bigint" ? x.toString() : x));
const eq = (a, b) => json(a) === json(b);

// ---------------------------------------------------------------------------
// Hand-written CDR decoding (little-endian, alignment counted from the byte
// after the 4-byte encapsulation header), independent of @foxglove/cdr.

class ManualCdr {
  constructor(bytes) {
    this.bytes = bytes;
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.pos = 4;
  }
  align(n) {
    const rel = this.pos - 4;
    this.pos += (n - (rel % n)) % n;
  }
  u8() {
    return this.view.getUint8(this.pos++);
  }
  u16() {
    this.align(2);
    const v = this.view.getUint16(this.pos, true);
    this.pos += 2;
    return v;
  }
  u32() {
    this.align(4);
    const v = this.view.getUint32(this.pos, true);
    this.pos += 4;
    return v;
  }
  i32() {
    this.align(4);
    const v = this.view.getInt32(this.pos, true);
    this.pos += 4;
    return v;
  }
  f32() {
    this.align(4);
    const v = this.view.getFloat32(this.pos, true);
    this.pos += 4;
    return v;
  }
  u64() {
    this.align(8);
    const v = this.view.getBigUint64(this.pos, true);
    this.pos += 8;
    return v;
  }
  str() {
    const n = this.u32(); // includes the terminating NUL
    const s = new TextDecoder().decode(this.bytes.subarray(this.pos, this.pos + n - 1));
    this.pos += n;
    return s;
  }
  raw(n) {
    const b = this.bytes.subarray(this.pos, this.pos + n);
    this.pos += n;
    return b;
  }
}

// ---------------------------------------------------------------------------
// Message decoders: each returns the same shape as expected.json's entries.

function decodeChatter(data) {
  const r = new CdrReader(data);
  const m = new ManualCdr(data);
  const viaLib = r.string();
  const viaHand = m.str();
  check(viaLib === viaHand, "chatter: CdrReader and hand decoder agree");
  check(m.pos === data.length, "chatter: hand decoder consumed every byte");
  return { data: viaLib };
}

function decodePoints(data) {
  const r = new CdrReader(data);
  const out = {
    stamp: { sec: r.int32(), nanosec: r.uint32() },
    frame_id: r.string(),
    height: r.uint32(),
    width: r.uint32(),
  };
  const nFields = r.sequenceLength();
  const fields = [];
  for (let i = 0; i < nFields; i++) {
    fields.push({ name: r.string(), offset: r.uint32(), datatype: r.uint8(), count: r.uint32() });
  }
  out.is_bigendian = r.uint8() !== 0;
  out.point_step = r.uint32();
  out.row_step = r.uint32();
  const bytes = r.uint8Array();
  out.is_dense = r.uint8() !== 0;
  check(r.decodedBytes === data.length, "points: CdrReader consumed every byte");
  check(eq(fields, expected.points_fields), "points: field list");

  // The point buffer, read at the field offsets.
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const pad = expected.points_padding;
  const points = [];
  for (let o = 0; o < bytes.length; o += out.point_step) {
    points.push([
      view.getFloat32(o + 0, true),
      view.getFloat32(o + 4, true),
      view.getFloat32(o + 8, true),
      view.getFloat32(o + 12, true),
      view.getUint16(o + 16, true),
      view.getFloat32(o + 20, true),
    ]);
    check(pad.bytes.every((b) => view.getUint8(o + b) === pad.value), "points: padding bytes are 0xAB");
  }
  out.points = points;

  // Same message through the hand decoder.
  const m = new ManualCdr(data);
  const hand = { stamp: { sec: m.i32(), nanosec: m.u32() }, frame_id: m.str(), height: m.u32(), width: m.u32() };
  const handFields = [];
  for (let i = 0, n = m.u32(); i < n; i++) {
    handFields.push({ name: m.str(), offset: m.u32(), datatype: m.u8(), count: m.u32() });
  }
  hand.is_bigendian = m.u8() !== 0;
  hand.point_step = m.u32();
  hand.row_step = m.u32();
  const handBytes = m.raw(m.u32());
  hand.is_dense = m.u8() !== 0;
  check(m.pos === data.length, "points: hand decoder consumed every byte");
  check(eq(handFields, fields) && Buffer.from(handBytes).equals(Buffer.from(bytes)), "points: hand decoder agrees");
  for (const k of ["stamp", "frame_id", "height", "width", "is_bigendian", "point_step", "row_step", "is_dense"]) {
    check(eq(hand[k], out[k]), `points: hand decoder agrees on ${k}`);
  }
  return out;
}

function decodeLivox(data) {
  const r = new CdrReader(data);
  const out = {
    stamp: { sec: r.int32(), nanosec: r.uint32() },
    frame_id: r.string(),
    timebase: r.uint64().toString(),
    point_num: r.uint32(),
    lidar_id: r.uint8(),
    rsvd: Array.from(r.uint8Array(3)),
  };
  const n = r.sequenceLength();
  out.points = [];
  for (let i = 0; i < n; i++) {
    const offset_time = r.uint32();
    const x = r.float32();
    const y = r.float32();
    const z = r.float32();
    const reflectivity = r.uint8();
    const tag = r.uint8();
    const line = r.uint8();
    out.points.push([x, y, z, reflectivity, tag, line, offset_time]);
  }
  check(r.decodedBytes === data.length, "livox: CdrReader consumed every byte");

  const m = new ManualCdr(data);
  const hand = { stamp: { sec: m.i32(), nanosec: m.u32() }, frame_id: m.str() };
  const timebaseAt = (m.align(8), m.pos);
  hand.timebase = m.u64().toString();
  hand.point_num = m.u32();
  hand.lidar_id = m.u8();
  hand.rsvd = Array.from(m.raw(3));
  hand.points = [];
  for (let i = 0, k = m.u32(); i < k; i++) {
    const offset_time = m.u32();
    hand.points.push([m.f32(), m.f32(), m.f32(), m.u8(), m.u8(), m.u8(), offset_time]);
  }
  check(m.pos === data.length, "livox: hand decoder consumed every byte");
  check(eq(hand, out), "livox: hand decoder agrees");
  check(timebaseAt % 8 === 4, "livox: timebase at 8-aligned offset after the encapsulation header");
  return out;
}

const DECODERS = { "/chatter": decodeChatter, "/points": decodePoints, "/livox/lidar": decodeLivox };

// A message record decoded into expected.json's shape.
function decodeMessage(topic, rec) {
  const head = [...rec.data.subarray(0, 4)];
  check(eq(head, [0, 1, 0, 0]), `${topic}: encapsulation header 00 01 00 00`);
  const body = DECODERS[topic](rec.data);
  const base = { log_time: rec.logTime.toString(), publish_time: rec.publishTime.toString(), sequence: rec.sequence };
  return { ...base, ...body, cdr_size: rec.data.length };
}

// Compare decoded messages (already in log-time order) with expected ones.
function compareMessages(label, byTopic, exp) {
  for (const [topic, list] of Object.entries(exp)) {
    const got = byTopic.get(topic) ?? [];
    check(got.length === list.length, `${label} ${topic}: ${got.length} messages, expected ${list.length}`);
    list.forEach((e, i) => {
      const g = got[i];
      if (!g) return;
      for (const [key, value] of Object.entries(e)) {
        check(eq(g[key], value), `${label} ${topic}[${i}].${key}: got ${JSON.stringify(g[key])}, expected ${JSON.stringify(value)}`);
      }
    });
  }
  for (const topic of byTopic.keys()) check(topic in exp, `${label}: unexpected topic ${topic}`);
}

const byLogTime = (a, b) => (a.logTime < b.logTime ? -1 : a.logTime > b.logTime ? 1 : 0);

// ---------------------------------------------------------------------------
// Top-level record walk (opcode u8, length u64, body) for the report.

const OPCODES = {
  0x01: "Header", 0x02: "Footer", 0x03: "Schema", 0x04: "Channel", 0x05: "Message", 0x06: "Chunk",
  0x07: "MessageIndex", 0x08: "ChunkIndex", 0x09: "Attachment", 0x0a: "AttachmentIndex",
  0x0b: "Statistics", 0x0c: "Metadata", 0x0d: "MetadataIndex", 0x0e: "SummaryOffset", 0x0f: "DataEnd",
};

function walkRecords(bytes, start, end) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const out = [];
  for (let pos = start; pos < end; ) {
    const opcode = view.getUint8(pos);
    const length = Number(view.getBigUint64(pos + 1, true));
    out.push({ opcode, name: OPCODES[opcode] ?? `0x${opcode.toString(16)}`, pos, body: bytes.subarray(pos + 9, pos + 9 + length) });
    pos += 9 + length;
    if (opcode === 0x02) break; // Footer: only the closing magic follows
  }
  return out;
}

// Run-length summary of a record list, e.g. "Header DataEnd Schema×2".
function summarize(records) {
  const parts = [];
  for (const r of records) {
    const last = parts[parts.length - 1];
    if (last && last.name === r.name) last.n++;
    else parts.push({ name: r.name, n: 1 });
  }
  return parts.map((p) => (p.n > 1 ? `${p.name}×${p.n}` : p.name)).join(" ");
}

// Decompress a chunk's bytes with the command-line tool, if installed.
const CLI = {};
for (const tool of ["zstd", "lz4"]) {
  try {
    execFileSync("which", [tool], { stdio: "pipe" });
    CLI[tool] = true;
  } catch {
    CLI[tool] = false;
  }
}
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), "mcap-check-"));
let cliChecked = 0;
function cliDecompress(compression, data) {
  if (!CLI[compression]) return null;
  const file = path.join(tmp, `chunk.${compression === "zstd" ? "zst" : "lz4"}`);
  fs.writeFileSync(file, data);
  return execFileSync(compression, ["-d", "-c", "-q", file], { maxBuffer: 1 << 24 });
}

// ---------------------------------------------------------------------------
// One MCAP file: returns its messages (in file order) and a report line.

async function checkFile(file, exp) {
  const bytes = fs.readFileSync(file);
  const label = path.relative(dir, file);
  const report = { file: label, size: bytes.length };

  // 1. Raw structure: top-level records, and the records inside each chunk.
  const top = walkRecords(bytes, 8, bytes.length - 8);
  report.top_level = summarize(top);
  const footerRec = top[top.length - 1];
  const fv = new DataView(footerRec.body.buffer, footerRec.body.byteOffset, footerRec.body.byteLength);
  report.footer = {
    summary_start: fv.getBigUint64(0, true).toString(),
    summary_offset_start: fv.getBigUint64(8, true).toString(),
    summary_crc: fv.getUint32(16, true),
  };
  check(report.footer.summary_start === exp.layout.footer_summary_start, `${label}: footer summary_start`);
  report.chunks = [];
  for (const rec of top.filter((r) => r.name === "Chunk")) {
    const v = new DataView(rec.body.buffer, rec.body.byteOffset, rec.body.byteLength);
    const start = v.getBigUint64(0, true);
    const end = v.getBigUint64(8, true);
    const uncompressedSize = Number(v.getBigUint64(16, true));
    const nameLen = v.getUint32(28, true);
    const compression = new TextDecoder().decode(rec.body.subarray(32, 32 + nameLen));
    const recLen = Number(v.getBigUint64(32 + nameLen, true));
    const compressed = rec.body.subarray(40 + nameLen, 40 + nameLen + recLen);
    let inner = compressed;
    if (compression !== "") {
      inner = decompressHandlers[compression](compressed, uncompressedSize);
      const viaCli = cliDecompress(compression, compressed);
      if (viaCli) {
        cliChecked++;
        check(Buffer.from(viaCli).equals(Buffer.from(inner)), `${label}: ${compression} CLI output equals wasm output`);
      }
      // Frame magic numbers: zstd 28 B5 2F FD, LZ4 frame 04 22 4D 18.
      const magic = Buffer.from(compressed.subarray(0, 4)).toString("hex");
      check(magic === (compression === "zstd" ? "28b52ffd" : "04224d18"), `${label}: ${compression} frame magic`);
    }
    check(inner.length === uncompressedSize, `${label}: chunk uncompressed size`);
    report.chunks.push({
      compression,
      time: `${start}..${end}`,
      compressed_size: compressed.length,
      uncompressed_size: uncompressedSize,
      records: summarize(walkRecords(inner, 0, inner.length)),
    });
  }
  check(report.chunks.length === exp.layout.chunk_count, `${label}: chunk count`);

  // 2. McapStreamReader: every record, CRCs validated.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  const channels = new Map();
  const schemas = new Map();
  const messages = [];
  let header;
  for (let rec; (rec = stream.nextRecord()); ) {
    if (rec.type === "Header") header = rec;
    if (rec.type === "Schema") schemas.set(rec.id, rec);
    if (rec.type === "Channel") channels.set(rec.id, rec);
    if (rec.type === "Message") messages.push(rec);
  }
  check(stream.done(), `${label}: stream reader reached the footer`);
  check(header?.profile === "ros2", `${label}: header profile ros2`);
  report.library = header?.library;
  for (const ch of channels.values()) {
    const schema = schemas.get(ch.schemaId);
    const t = exp.topics.find((x) => x.name === ch.topic);
    check(t !== undefined, `${label}: channel ${ch.topic} expected`);
    check(ch.messageEncoding === "cdr", `${label}: ${ch.topic} message encoding cdr`);
    check(schema?.encoding === "ros2msg" && schema?.name === t?.type, `${label}: ${ch.topic} schema`);
  }
  const topicOf = (rec) => channels.get(rec.channelId).topic;

  // File order is the write order: the writer does not sort.
  const fileOrder = messages.map((m) => `${topicOf(m)}@${m.logTime}`);
  check(eq(fileOrder, exp.write_order), `${label}: messages stored in write order`);
  report.file_order = fileOrder.map((s) => s.replace(/000000$/, "ms").replace(/^\/(\w+).*@/, "$1@"));

  // Sorted by log time, decoded, compared with expected.json.
  const decodeAll = (list) => {
    const byTopic = new Map();
    for (const rec of list) {
      const topic = topicOf(rec);
      if (!byTopic.has(topic)) byTopic.set(topic, []);
      byTopic.get(topic).push(decodeMessage(topic, rec));
    }
    return byTopic;
  };
  const sorted = [...messages].sort(byLogTime);
  const streamDecoded = decodeAll(sorted);

  // 3. McapIndexedReader, when there is a summary.
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
  };
  if (exp.layout.has_summary) {
    const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
    const s = reader.statistics;
    check(s !== undefined, `${label}: statistics present`);
    if (s) {
      check(s.messageCount === BigInt(exp.message_count), `${label}: statistics message count`);
      check(s.messageStartTime.toString() === exp.message_start_time, `${label}: statistics start time`);
      check(s.messageEndTime.toString() === exp.message_end_time, `${label}: statistics end time`);
      check(s.chunkCount === exp.layout.chunk_count, `${label}: statistics chunk count`);
      for (const t of exp.topics) {
        const id = [...reader.channelsById.values()].find((c) => c.topic === t.name)?.id;
        check(s.channelMessageCounts.get(id) === BigInt(t.message_count), `${label}: statistics count for ${t.name}`);
      }
    }
    check(reader.chunkIndexes.length === exp.layout.chunk_count, `${label}: chunk index count`);
    check(reader.channelsById.size === exp.topics.length, `${label}: summary channels`);
    check(reader.schemasById.size === exp.topics.length, `${label}: summary schemas`);
    report.summary_offsets = [...reader.summaryOffsetsByOpcode.keys()].map((o) => OPCODES[o]).join(" ");
    const indexed = [];
    for await (const rec of reader.readMessages()) indexed.push(rec);
    report.indexed_reader_messages = indexed.length;
    if (exp.layout.chunked) {
      // Delivered in log-time order across (out-of-order) chunks.
      check(eq(indexed.map((m) => m.logTime), sorted.map((m) => m.logTime)), `${label}: indexed reader log-time order`);
      compareMessages(`${label} (indexed)`, decodeAll(indexed), exp.messages);
    } else {
      // readMessages() only reads chunks; an unchunked file yields nothing.
      check(indexed.length === 0, `${label}: indexed reader yields no messages without chunks`);
    }
  } else {
    try {
      await McapIndexedReader.Initialize({ readable, decompressHandlers });
      report.indexed_reader = "initialized (unexpected)";
      check(false, `${label}: indexed reader should refuse a file without summary`);
    } catch (err) {
      report.indexed_reader = `refused: ${err.message}`;
    }
  }

  return { messages: sorted, streamDecoded, report };
}

// ---------------------------------------------------------------------------

const reports = [];
for (const [name, exp] of Object.entries(expected.files)) {
  console.log(`checking ${name}`);
  if (exp.kind === "file") {
    const { streamDecoded, report } = await checkFile(path.join(dir, name), exp);
    compareMessages(`${name} (stream)`, streamDecoded, exp.messages);
    reports.push(report);
    continue;
  }

  // rosbag2 folder: metadata.yaml, then each part, then all messages together.
  const folder = path.join(dir, name);
  const yaml = fs.readFileSync(path.join(folder, "metadata.yaml"), "utf8");
  check(/^rosbag2_bagfile_information:\n  version: \d+\n  storage_identifier: mcap\n/.test(yaml), `${name}: metadata.yaml head`);
  check(yaml.includes(`  message_count: ${exp.message_count}\n`), `${name}: metadata.yaml message_count`);
  const listed = [...yaml.matchAll(/^    - (\S+\.mcap)$/gm)].map((mm) => mm[1]);
  check(eq(listed, exp.relative_file_paths), `${name}: metadata.yaml relative_file_paths`);
  const all = new Map();
  for (const part of exp.relative_file_paths) {
    const partExp = exp.parts[part];
    // This part's share of the folder's expected messages (by its write order).
    const mine = new Set(partExp.write_order);
    const partMessages = Object.fromEntries(
      Object.entries(exp.messages).map(([topic, list]) => [topic, list.filter((e) => mine.has(`${topic}@${e.log_time}`))]),
    );
    const { streamDecoded, report } = await checkFile(path.join(folder, part), { ...partExp, messages: partMessages });
    compareMessages(`${name}/${part} (stream)`, streamDecoded, partMessages);
    reports.push(report);
    for (const [topic, list] of streamDecoded) all.set(topic, [...(all.get(topic) ?? []), ...list]);
  }
  for (const list of all.values()) list.sort((a, b) => (BigInt(a.log_time) < BigInt(b.log_time) ? -1 : 1));
  compareMessages(`${name} (all parts)`, all, exp.messages);
}
fs.rmSync(tmp, { recursive: true, force: true });

if (process.argv.includes("--report")) console.log(JSON.stringify(reports, null, 2));
console.log(
  `chunks decompressed by the command-line tools: ${cliChecked}` +
    (CLI.zstd && CLI.lz4 ? "" : ` (missing: ${Object.keys(CLI).filter((t) => !CLI[t]).join(", ")})`),
);
console.log(`${passes} passed, ${failures} failed`);
process.exit(failures === 0 ? 0 : 1);
