// Writes small ROS 2 style MCAP test recordings with the official MCAP
// TypeScript writer (@mcap/core), plus expected.json describing their content.
//
// Usage: node make_fixtures.mjs <output folder>
//        (from this folder: node make_fixtures.mjs ../../data/mcap)

import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

import { McapWriter, LIBRARY_IDENTIFIER } from "@mcap/core";
import { CdrWriter } from "@foxglove/cdr";
import zstd from "@foxglove/wasm-zstd";
import lz4js from "lz4js";

// Installed version of a dependency (read from node_modules, since some
// packages do not export their package.json).
const HERE = path.dirname(fileURLToPath(import.meta.url));
function installedVersion(pkg) {
  const file = path.join(HERE, "node_modules", pkg, "package.json");
  return JSON.parse(fs.readFileSync(file, "utf8")).version;
}

// ---------------------------------------------------------------------------
// Schemas: ROS 2 .msg text, dependencies appended after a line of 80 '='
// and a "MSG: package/Type" line (the concatenated form rosbag2 stores).

const SEP = "=".repeat(80) + "\n";

const HEADER_DEPS =
  SEP +
  "MSG: std_msgs/Header\n" +
  "builtin_interfaces/Time stamp\n" +
  "string frame_id\n" +
  SEP +
  "MSG: builtin_interfaces/Time\n" +
  "int32 sec\n" +
  "uint32 nanosec\n";

const POINTCLOUD2_MSG =
  "std_msgs/Header header\n" +
  "uint32 height\n" +
  "uint32 width\n" +
  "PointField[] fields\n" +
  "bool is_bigendian\n" +
  "uint32 point_step\n" +
  "uint32 row_step\n" +
  "uint8[] data\n" +
  "bool is_dense\n" +
  HEADER_DEPS +
  SEP +
  "MSG: sensor_msgs/PointField\n" +
  "uint8 INT8 = 1\n" +
  "uint8 UINT8 = 2\n" +
  "uint8 INT16 = 3\n" +
  "uint8 UINT16 = 4\n" +
  "uint8 INT32 = 5\n" +
  "uint8 UINT32 = 6\n" +
  "uint8 FLOAT32 = 7\n" +
  "uint8 FLOAT64 = 8\n" +
  "string name\n" +
  "uint32 offset\n" +
  "uint8 datatype\n" +
  "uint32 count\n";

const STRING_MSG = "string data\n";

const LIVOX_MSG =
  "std_msgs/Header header\n" +
  "uint64 timebase\n" +
  "uint32 point_num\n" +
  "uint8 lidar_id\n" +
  "uint8[3] rsvd\n" +
  "CustomPoint[] points\n" +
  HEADER_DEPS +
  SEP +
  "MSG: livox_ros_driver2/CustomPoint\n" +
  "uint32 offset_time\n" +
  "float32 x\n" +
  "float32 y\n" +
  "float32 z\n" +
  "uint8 reflectivity\n" +
  "uint8 tag\n" +
  "uint8 line\n";

// ---------------------------------------------------------------------------
// Message content (plain JS objects), shared by the encoder and expected.json.

const FLOAT32 = 7;
const UINT16 = 4;
const POINT_FIELDS = [
  { name: "x", offset: 0, datatype: FLOAT32, count: 1 },
  { name: "y", offset: 4, datatype: FLOAT32, count: 1 },
  { name: "z", offset: 8, datatype: FLOAT32, count: 1 },
  { name: "intensity", offset: 12, datatype: FLOAT32, count: 1 },
  { name: "ring", offset: 16, datatype: UINT16, count: 1 },
  { name: "time", offset: 20, datatype: FLOAT32, count: 1 },
];
const POINT_STEP = 24;
const PAD_BYTE = 0xab; // fills bytes 18-19 of every point (after "ring")

const NS = 1_000_000_000n;

// PointCloud2 message k (k = 0..4): 4 + k points.
function pointCloudContent(k) {
  const n = 4 + k;
  const points = [];
  for (let j = 0; j < n; j++) {
    points.push({
      x: Math.fround(1 + k + 0.25 * j),
      y: Math.fround(-0.5 * j),
      z: Math.fround(0.125 * (j + 1)),
      intensity: Math.fround(10 * k + j),
      ring: j % 16,
      time: Math.fround(0.001 * j),
    });
  }
  const logTime = BigInt(100 + k) * NS + 500_000_000n + 1_000_000n;
  return {
    k,
    logTime,
    publishTime: logTime,
    sequence: k,
    stamp: { sec: 100 + k, nanosec: 500_000_000 },
    frame_id: "lidar",
    height: 1,
    width: n,
    is_bigendian: false,
    point_step: POINT_STEP,
    row_step: POINT_STEP * n,
    is_dense: true,
    points,
  };
}

// std_msgs/String message k, logged 0.501 s before PointCloud2 message k.
function chatterContent(k) {
  const logTime = BigInt(100 + k) * NS;
  return { k, logTime, publishTime: logTime, sequence: k, data: `hello ${k}` };
}

// Livox CustomMsg message m (m = 0, 1): 3 points.
function livoxContent(m) {
  const points = [];
  for (let j = 0; j < 3; j++) {
    points.push({
      offset_time: 1000 * j,
      x: Math.fround(5 + m + j),
      y: Math.fround(0.5 * j),
      z: Math.fround(-0.25 * j),
      reflectivity: 20 * j + m,
      tag: 0x10,
      line: j,
    });
  }
  const logTime = BigInt(200 + m) * NS;
  return {
    m,
    logTime,
    publishTime: logTime,
    sequence: m,
    stamp: { sec: 200 + m, nanosec: 0 },
    frame_id: "livox_frame",
    timebase: BigInt(200 + m) * NS,
    point_num: 3,
    lidar_id: 1,
    rsvd: [0, 0, 0],
    points,
  };
}

// ---------------------------------------------------------------------------
// CDR encoders. CdrWriter() defaults to CDR little-endian: it starts with the
// encapsulation header 00 01 00 00 and aligns relative to the byte after it.

function writeHeader(w, msg) {
  w.int32(msg.stamp.sec);
  w.uint32(msg.stamp.nanosec);
  w.string(msg.frame_id);
}

function encodePointCloud2(msg) {
  // Packed point buffer: little-endian, 24 bytes per point.
  const data = new Uint8Array(msg.points.length * POINT_STEP);
  const view = new DataView(data.buffer);
  msg.points.forEach((p, j) => {
    const o = j * POINT_STEP;
    view.setFloat32(o + 0, p.x, true);
    view.setFloat32(o + 4, p.y, true);
    view.setFloat32(o + 8, p.z, true);
    view.setFloat32(o + 12, p.intensity, true);
    view.setUint16(o + 16, p.ring, true);
    view.setUint8(o + 18, PAD_BYTE);
    view.setUint8(o + 19, PAD_BYTE);
    view.setFloat32(o + 20, p.time, true);
  });

  const w = new CdrWriter();
  writeHeader(w, msg);
  w.uint32(msg.height);
  w.uint32(msg.width);
  w.sequenceLength(POINT_FIELDS.length);
  for (const f of POINT_FIELDS) {
    w.string(f.name);
    w.uint32(f.offset);
    w.uint8(f.datatype);
    w.uint32(f.count);
  }
  w.uint8(msg.is_bigendian ? 1 : 0); // bool is one byte
  w.uint32(msg.point_step);
  w.uint32(msg.row_step);
  w.uint8Array(data, true); // uint32 length, then the bytes
  w.uint8(msg.is_dense ? 1 : 0);
  return w.data;
}

function encodeString(msg) {
  const w = new CdrWriter();
  w.string(msg.data);
  return w.data;
}

function encodeLivox(msg) {
  const w = new CdrWriter();
  writeHeader(w, msg);
  w.uint64(msg.timebase); // aligned to 8 by CdrWriter
  w.uint32(msg.point_num);
  w.uint8(msg.lidar_id);
  w.uint8Array(msg.rsvd, false); // fixed-size array: no length prefix
  w.sequenceLength(msg.points.length);
  for (const p of msg.points) {
    w.uint32(p.offset_time);
    w.float32(p.x);
    w.float32(p.y);
    w.float32(p.z);
    w.uint8(p.reflectivity);
    w.uint8(p.tag);
    w.uint8(p.line);
  }
  return w.data;
}

// ---------------------------------------------------------------------------
// Chunk compressors for McapWriter's compressChunk option.

const ZSTD_LEVEL = 3;
function compressZstd(chunkData) {
  // One zstd frame (ZSTD_compress), content size stored in the frame header.
  return { compression: "zstd", compressedData: new Uint8Array(zstd.compress(chunkData, ZSTD_LEVEL)) };
}
function compressLz4(chunkData) {
  // lz4js.compress writes the LZ4 *frame* format (magic 04 22 4D 18).
  return { compression: "lz4", compressedData: Uint8Array.from(lz4js.compress(chunkData)) };
}

// ---------------------------------------------------------------------------
// Writer plumbing.

// In-memory IWritable: McapWriter only needs write() and position().
class MemoryWritable {
  #parts = [];
  #size = 0n;
  async write(buffer) {
    this.#parts.push(Uint8Array.from(buffer)); // copy: the writer reuses its buffer
    this.#size += BigInt(buffer.byteLength);
  }
  position() {
    return this.#size;
  }
  bytes() {
    return Buffer.concat(this.#parts);
  }
}

// Option sets. Anything not given takes McapWriter's default (all indexes,
// statistics, repeated schemas/channels and summary offsets on; chunks on).
const CHUNK_SIZE = 600; // bytes of uncompressed chunk content before a chunk is closed
const OPTIONS = {
  zstd: { useChunks: true, chunkSize: CHUNK_SIZE, compressChunk: compressZstd },
  lz4: { useChunks: true, chunkSize: CHUNK_SIZE, compressChunk: compressLz4 },
  uncompressed: { useChunks: true, chunkSize: CHUNK_SIZE }, // no compressChunk: compression ""
  unchunked: { useChunks: false },
  noSummary: {
    useChunks: true,
    chunkSize: CHUNK_SIZE,
    compressChunk: compressZstd,
    useStatistics: false,
    useSummaryOffsets: false,
    repeatSchemas: false,
    repeatChannels: false,
    useAttachmentIndex: false,
    useMetadataIndex: false,
    useMessageIndex: false,
    useChunkIndex: false,
  },
};

// Readable description of an option set for the README / report.
function describeOptions(opts) {
  const out = {};
  for (const [key, value] of Object.entries(opts)) {
    out[key] = typeof value === "function" ? value.name : value;
  }
  return out;
}

// Topic definitions: schema + channel for each topic.
const TOPICS = {
  "/chatter": {
    schemaName: "std_msgs/msg/String",
    schemaText: STRING_MSG,
    encode: encodeString,
  },
  "/points": {
    schemaName: "sensor_msgs/msg/PointCloud2",
    schemaText: POINTCLOUD2_MSG,
    encode: encodePointCloud2,
  },
  "/livox/lidar": {
    schemaName: "livox_ros_driver2/msg/CustomMsg",
    schemaText: LIVOX_MSG,
    encode: encodeLivox,
  },
};

// Writes one MCAP file. `plan` is the list of {topic, msg} in write order.
// Schemas and channels are registered in order of the topics' first use.
async function writeMcap(filePath, options, plan) {
  const writable = new MemoryWritable();
  const writer = new McapWriter({ writable, ...options });
  await writer.start({ profile: "ros2", library: LIBRARY_IDENTIFIER });

  const channelIds = new Map();
  for (const { topic } of plan) {
    if (channelIds.has(topic)) continue;
    const t = TOPICS[topic];
    const schemaId = await writer.registerSchema({
      name: t.schemaName,
      encoding: "ros2msg",
      data: new TextEncoder().encode(t.schemaText),
    });
    const channelId = await writer.registerChannel({
      topic,
      schemaId,
      messageEncoding: "cdr",
      metadata: new Map(),
    });
    channelIds.set(topic, channelId);
  }

  for (const { topic, msg } of plan) {
    await writer.addMessage({
      channelId: channelIds.get(topic),
      sequence: msg.sequence,
      logTime: msg.logTime,
      publishTime: msg.publishTime,
      data: TOPICS[topic].encode(msg),
    });
  }
  await writer.end();

  const bytes = writable.bytes();
  fs.writeFileSync(filePath, bytes);
  return { size: bytes.length, layout: describeLayout(options, bytes) };
}

// Facts about the written file for expected.json: chunking, compression,
// summary, and the number of Chunk records (counted by walking the top-level
// records: opcode u8, length u64, body).
function describeLayout(options, bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let chunkCount = 0;
  let summaryStart = null;
  for (let pos = 8; pos < bytes.length - 8; ) {
    const opcode = view.getUint8(pos);
    const length = Number(view.getBigUint64(pos + 1, true));
    if (opcode === 0x06) chunkCount++; // Chunk
    if (opcode === 0x02) summaryStart = view.getBigUint64(pos + 9, true).toString(); // Footer
    pos += 9 + length;
  }
  const compressed = options.compressChunk ? options.compressChunk(new Uint8Array(1)).compression : "";
  return {
    chunked: options.useChunks !== false,
    compression: options.useChunks === false ? null : compressed,
    chunk_count: chunkCount,
    has_summary: summaryStart !== "0",
    footer_summary_start: summaryStart,
  };
}

// ---------------------------------------------------------------------------
// expected.json helpers. Points are listed as rows whose columns are given
// once at the top of the file; every float is a float32 value (Math.fround).

const POINTS_COLUMNS = ["x", "y", "z", "intensity", "ring", "time"];
// Livox per-point time is timebase (per message) + offset_time.
const LIVOX_COLUMNS = ["x", "y", "z", "reflectivity", "tag", "line", "offset_time"];

function expectedMessage(topic, msg) {
  const e = {
    log_time: msg.logTime.toString(),
    publish_time: msg.publishTime.toString(),
    sequence: msg.sequence,
  };
  if (topic === "/chatter") {
    e.data = msg.data;
    return e;
  }
  e.stamp = { sec: msg.stamp.sec, nanosec: msg.stamp.nanosec };
  e.frame_id = msg.frame_id;
  if (topic === "/points") {
    Object.assign(e, {
      height: msg.height,
      width: msg.width,
      is_bigendian: msg.is_bigendian,
      point_step: msg.point_step,
      row_step: msg.row_step,
      is_dense: msg.is_dense,
      points: msg.points.map((p) => POINTS_COLUMNS.map((c) => p[c])),
    });
  } else {
    Object.assign(e, {
      timebase: msg.timebase.toString(),
      point_num: msg.point_num,
      lidar_id: msg.lidar_id,
      rsvd: msg.rsvd,
      points: msg.points.map((p) => LIVOX_COLUMNS.map((c) => p[c])),
    });
  }
  // Size of the serialized message, then the points last.
  const { points, ...head } = e;
  return { ...head, cdr_size: TOPICS[topic].encode(msg).length, points };
}

// Content summary of a plan: topics and messages sorted by log time.
function expectedContent(plan) {
  const topics = [];
  const messages = {};
  for (const { topic, msg } of plan) {
    if (!messages[topic]) {
      messages[topic] = [];
      topics.push({
        name: topic,
        type: TOPICS[topic].schemaName,
        schema_encoding: "ros2msg",
        message_encoding: "cdr",
        message_count: 0,
      });
    }
    messages[topic].push(msg);
    topics.find((t) => t.name === topic).message_count++;
  }
  const out = { topics, messages: {} };
  for (const [topic, msgs] of Object.entries(messages)) {
    msgs.sort((a, b) => (a.logTime < b.logTime ? -1 : a.logTime > b.logTime ? 1 : 0));
    out.messages[topic] = msgs.map((m) => expectedMessage(topic, m));
  }
  const all = plan.map((p) => p.msg.logTime).sort((a, b) => (a < b ? -1 : a > b ? 1 : 0));
  out.message_count = plan.length;
  out.message_start_time = all[0].toString();
  out.message_end_time = all[all.length - 1].toString();
  // Order in which addMessage() was called: "topic@log_time" strings.
  out.write_order = plan.map((p) => `${p.topic}@${p.msg.logTime}`);
  return out;
}

// JSON with 2-space indentation, kept small: an object or array that holds
// only plain values (a point, a stamp) is written on one line, and such short
// entries are packed together on lines of up to ~120 characters.
function compactJson(value, indent = "") {
  const isLeaf = (v) => v === null || typeof v !== "object";
  const isFlat = (v) => isLeaf(v) || Object.values(v).every(isLeaf);
  const flat = (v) => {
    if (isLeaf(v)) return JSON.stringify(v);
    if (Array.isArray(v)) return "[" + v.map((x) => JSON.stringify(x)).join(", ") + "]";
    return "{" + Object.entries(v).map(([k, x]) => `${JSON.stringify(k)}: ${JSON.stringify(x)}`).join(", ") + "}";
  };
  if (isFlat(value)) return flat(value);

  const array = Array.isArray(value);
  const entries = array ? value.map((v) => [null, v]) : Object.entries(value);
  const inner = indent + "  ";
  const key = (k) => (k === null ? "" : JSON.stringify(k) + ": ");
  const lines = [];
  let line = "";
  for (const [k, v] of entries) {
    if (isFlat(v) && !(array && !isLeaf(v) && !Array.isArray(v))) {
      // Pack short plain entries; array items that are objects get a line each.
      const piece = key(k) + flat(v);
      if (line && line.length + piece.length > 120) {
        lines.push(line);
        line = "";
      }
      line = line ? `${line}, ${piece}` : piece;
    } else {
      if (line) lines.push(line);
      line = "";
      lines.push(key(k) + (isFlat(v) ? flat(v) : compactJson(v, inner)));
    }
  }
  if (line) lines.push(line);
  const [open, close] = array ? ["[", "]"] : ["{", "}"];
  return `${open}\n${lines.map((l) => inner + l).join(",\n")}\n${indent}${close}`;
}

// ---------------------------------------------------------------------------
// rosbag2 metadata.yaml (format version 5) for the split folder.

function metadataYaml(files) {
  const all = files.flatMap((f) => f.plan);
  const times = all.map((p) => p.msg.logTime);
  const start = times.reduce((a, b) => (b < a ? b : a));
  const end = times.reduce((a, b) => (b > a ? b : a));
  const counts = new Map();
  for (const { topic } of all) counts.set(topic, (counts.get(topic) ?? 0) + 1);

  const lines = [
    "rosbag2_bagfile_information:",
    "  version: 5",
    "  storage_identifier: mcap",
    "  duration:",
    `    nanoseconds: ${end - start}`,
    "  starting_time:",
    `    nanoseconds_since_epoch: ${start}`,
    `  message_count: ${all.length}`,
    "  topics_with_message_count:",
  ];
  for (const [topic, count] of counts) {
    lines.push(
      "    - topic_metadata:",
      `        name: ${topic}`,
      `        type: ${TOPICS[topic].schemaName}`,
      "        serialization_format: cdr",
      '        offered_qos_profiles: ""',
      `      message_count: ${count}`,
    );
  }
  lines.push('  compression_format: ""', '  compression_mode: ""', "  relative_file_paths:");
  for (const f of files) lines.push(`    - ${f.name}`);
  lines.push("  files:");
  for (const f of files) {
    const ft = f.plan.map((p) => p.msg.logTime);
    const fs0 = ft.reduce((a, b) => (b < a ? b : a));
    const fs1 = ft.reduce((a, b) => (b > a ? b : a));
    lines.push(
      `    - path: ${f.name}`,
      "      starting_time:",
      `        nanoseconds_since_epoch: ${fs0}`,
      "      duration:",
      `        nanoseconds: ${fs1 - fs0}`,
      `      message_count: ${f.plan.length}`,
    );
  }
  return lines.join("\n") + "\n";
}

// ---------------------------------------------------------------------------

async function main() {
  const outDir = process.argv[2];
  if (!outDir) {
    console.error("usage: node make_fixtures.mjs <output folder>");
    process.exit(2);
  }
  fs.mkdirSync(outDir, { recursive: true });
  await zstd.isLoaded;

  // Content A: k written in the order 0, 1, 3, 2, 4; for each k the /chatter
  // message goes first, then the /points message.
  const WRITE_ORDER = [0, 1, 3, 2, 4];
  const planFor = (ks) =>
    WRITE_ORDER.filter((k) => ks.includes(k)).flatMap((k) => [
      { topic: "/chatter", msg: chatterContent(k) },
      { topic: "/points", msg: pointCloudContent(k) },
    ]);
  const planA = planFor([0, 1, 2, 3, 4]);
  const planLivox = [0, 1].map((m) => ({ topic: "/livox/lidar", msg: livoxContent(m) }));

  const singleFiles = [
    ["points_zstd.mcap", OPTIONS.zstd, planA],
    ["points_lz4.mcap", OPTIONS.lz4, planA],
    ["points_uncompressed.mcap", OPTIONS.uncompressed, planA],
    ["points_unchunked.mcap", OPTIONS.unchunked, planA],
    ["points_no_summary.mcap", OPTIONS.noSummary, planA],
    ["livox.mcap", OPTIONS.zstd, planLivox],
  ];

  const expected = {
    generator: "tests/tools/mcap_fixtures/make_fixtures.mjs",
    writer: LIBRARY_IDENTIFIER,
    packages: {
      "@mcap/core": installedVersion("@mcap/core"),
      "@foxglove/cdr": installedVersion("@foxglove/cdr"),
      "@foxglove/wasm-zstd": installedVersion("@foxglove/wasm-zstd"),
      lz4js: installedVersion("lz4js"),
    },
    // Shared by every file: PointCloud2 field layout and the point row columns.
    points_fields: POINT_FIELDS,
    points_padding: { bytes: [18, 19], value: PAD_BYTE },
    points_columns: POINTS_COLUMNS,
    livox_columns: LIVOX_COLUMNS,
    files: {},
  };

  for (const [name, options, plan] of singleFiles) {
    const { size, layout } = await writeMcap(path.join(outDir, name), options, plan);
    expected.files[name] = {
      kind: "file",
      writer_options: describeOptions(options),
      layout,
      ...expectedContent(plan),
    };
    console.log(`${name}: ${size} bytes`);
  }

  // rosbag2-style split folder: k = 0, 1, 2 in _0, k = 3, 4 in _1.
  const folder = path.join(outDir, "ros2_folder");
  fs.mkdirSync(folder, { recursive: true });
  const parts = [
    { name: "ros2_folder_0.mcap", plan: planFor([0, 1, 2]) },
    { name: "ros2_folder_1.mcap", plan: planFor([3, 4]) },
  ];
  for (const part of parts) {
    const { size, layout } = await writeMcap(path.join(folder, part.name), OPTIONS.zstd, part.plan);
    part.layout = layout;
    console.log(`ros2_folder/${part.name}: ${size} bytes`);
  }
  fs.writeFileSync(path.join(folder, "metadata.yaml"), metadataYaml(parts));
  expected.files["ros2_folder"] = {
    kind: "rosbag2_folder",
    writer_options: describeOptions(OPTIONS.zstd),
    relative_file_paths: parts.map((p) => p.name),
    // Per part: topics, counts, time range and write order (messages are listed once, below).
    parts: Object.fromEntries(
      parts.map((p) => {
        const { messages, ...rest } = expectedContent(p.plan);
        return [p.name, { layout: p.layout, ...rest }];
      }),
    ),
    ...expectedContent(parts.flatMap((p) => p.plan)),
  };
  // The folder's combined write order is not meaningful; keep it per part.
  delete expected.files["ros2_folder"].write_order;

  fs.writeFileSync(path.join(outDir, "expected.json"), compactJson(expected) + "\n");
  console.log("expected.json written");
}

await main();
