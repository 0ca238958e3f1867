// MCAP (https://mcap.dev/spec, major version 0), the default storage of ROS 2 bags since Iron, read
// from the published specification (Debian 12 packages no MCAP library). All little-endian:
//   magic "\x89MCAP0\r\n", Header (op 0x01), data section, [summary section], Footer (0x02), magic
//   every record: uint8 op, uint64 content length, content
//   data section: Schema (0x03), Channel (0x04), Message (0x05) and Chunk (0x06: Schema, Channel
//     and Message records, compressed with lz4 or zstd or not at all) records; after each chunk a
//     Message Index (0x07) per channel: (log time, offset in the chunk) of each of its messages
//   summary: Schema and Channel copies, a Chunk Index (0x08) per chunk pointing at its message
//     indexes, Statistics (0x0B)
// With a summary that adds up, a topic's messages are found without decompressing any chunk. When
// it is missing (a recorder that died) or does not add up, the data section is scanned instead, up
// to the first damage, and everything before the damage is usable.
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string_view>

#include "byte_cursor.hpp"
#include "chunk_decompress.hpp"
#include "file_bytes.hpp"
#include "iilfm/error.hpp"
#include "ros_bags.hpp"

namespace iilfm::io {
namespace {

namespace fs = std::filesystem;

constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::uint8_t kOpHeader = 0x01, kOpFooter = 0x02, kOpSchema = 0x03, kOpChannel = 0x04,
                       kOpMessage = 0x05, kOpChunk = 0x06, kOpMessageIndex = 0x07,
                       kOpChunkIndex = 0x08, kOpStatistics = 0x0B, kOpDataEnd = 0x0F;
constexpr std::size_t kRecordPrefix = 9;                   // op and content length
constexpr std::size_t kFooterRecord = kRecordPrefix + 20;  // summary start, offset start, crc
constexpr std::size_t kMessagePrefix = 2 + 4 + 8 + 8;      // channel, sequence, two times
constexpr std::uint32_t kNoChunk = UINT32_MAX;             // a message in the data section

// A problem with a file's bytes; the caller adds the path.
struct Damage {
  std::string problem;
};

std::string at_byte(std::uint64_t offset) { return "at byte " + std::to_string(offset); }

struct Record {
  std::uint8_t op = 0;
  const std::uint8_t* content = nullptr;
  std::size_t size = 0;
  std::size_t end = 0;  // offset of the next record
};

// The record at `offset`; `where` is "" for the file or " in chunk at byte N".
Record read_record(const std::uint8_t* base, std::size_t size, std::size_t offset,
                   const std::string& where) {
  const std::size_t left = size - std::min(size, offset);
  if (left < kRecordPrefix)
    throw Damage{"record " + at_byte(offset) + where + " is cut off (needs " +
                 std::to_string(kRecordPrefix) + " bytes, " + std::to_string(left) + " left)"};
  Record r;
  r.op = base[offset];
  std::uint64_t length;
  std::memcpy(&length, base + offset + 1, sizeof length);
  if (length > left - kRecordPrefix)
    throw Damage{"record " + at_byte(offset) + where + " is cut off (declares " +
                 std::to_string(length) + " bytes, " + std::to_string(left - kRecordPrefix) +
                 " left)"};
  r.content = base + offset + kRecordPrefix;
  r.size = static_cast<std::size_t>(length);
  r.end = offset + kRecordPrefix + r.size;
  return r;
}

// Runs `parse` on a cursor over the record's content; a field running past the content is damage.
template <typename Parse>
auto parse_record(const Record& r, std::size_t offset, const std::string& where, const char* kind,
                  Parse parse) {
  try {
    ByteCursor in(r.content, r.size);
    return parse(in);
  } catch (const ShortData&) {
    throw Damage{std::string(kind) + " record " + at_byte(offset) + where + " is too short"};
  }
}

std::string_view mcap_string(ByteCursor& in) { return in.take_text(in.u32()); }

struct Schema {
  std::string name, encoding, data;
};

struct Channel {
  std::string topic, message_encoding;
  std::uint16_t schema = 0;
};

struct Chunk {
  std::size_t position = 0;  // of the chunk record in its file
  std::string compression;   // "", "lz4" or "zstd"
  std::uint64_t uncompressed_size = 0;
  std::uint32_t crc = 0;  // of the uncompressed records; 0 when the writer left it out
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

Chunk read_chunk(const Record& r, std::size_t position) {
  Chunk c = parse_record(r, position, "", "chunk", [&](ByteCursor& in) {
    Chunk chunk;
    in.skip(16);  // message start and end times
    chunk.uncompressed_size = in.u64();
    chunk.crc = in.u32();
    chunk.compression = printable(mcap_string(in));
    const std::uint64_t length = in.u64();
    if (length > in.remaining()) throw ShortData{in.offset(), static_cast<std::size_t>(length)};
    chunk.size = static_cast<std::size_t>(length);
    chunk.data = in.take(chunk.size);
    return chunk;
  });
  c.position = position;
  if (c.compression != "" && c.compression != "lz4" && c.compression != "zstd")
    throw Damage{"chunk " + at_byte(position) + " has unknown compression '" + c.compression +
                 "' (supported: lz4, zstd, none)"};
  if (c.compression.empty() && c.uncompressed_size != c.size)
    throw Damage{"uncompressed chunk " + at_byte(position) + " declares " +
                 std::to_string(c.uncompressed_size) + " bytes but holds " +
                 std::to_string(c.size)};
  return c;
}

// One message: its log time, global channel, file, chunk (kNoChunk: in the data section) and the
// offset of its record in the chunk's records (or the file).
struct Entry {
  std::int64_t time_ns;
  std::uint32_t channel;
  std::uint32_t file;
  std::uint32_t chunk;
  std::uint64_t offset;
};

struct McapFile {
  std::string path;
  FileBytes bytes;
  std::string profile, library;
  bool indexed = false;
  std::vector<Chunk> chunks;
  std::map<std::uint16_t, Schema> schemas;
  std::map<std::uint16_t, std::uint32_t> channels;  // the file's channel ids to global ones
};

class McapBag final : public BagReader {
 public:
  McapBag(std::string path, const std::vector<std::string>& files) : path_(std::move(path)) {
    if (files.empty()) throw file_error(path_, "no .mcap files in this ROS 2 bag");
    for (const std::string& file : files) open_file(file);
    build_topics();
  }

  const std::string& path() const override { return path_; }
  std::string format() const override {
    std::set<std::string> compressions, profiles;
    std::size_t chunks = 0;
    bool indexed = true;
    for (const McapFile& f : files_) {
      for (const Chunk& c : f.chunks)
        compressions.insert(c.compression.empty() ? "none" : c.compression);
      chunks += f.chunks.size();
      profiles.insert(f.profile.empty() ? "no profile" : f.profile + " profile");
      indexed = indexed && f.indexed;
    }
    const auto list = [](const std::set<std::string>& items) {
      std::string out;
      for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
      return out;
    };
    std::string text = "MCAP (" + list(profiles) + "), ";
    if (files_.size() > 1) text += std::to_string(files_.size()) + " files, ";
    text += std::to_string(chunks) + " chunks";
    if (!compressions.empty()) text += " (" + list(compressions) + ")";
    return text + (indexed ? ", indexed" : ", summary missing or incomplete: data scanned");
  }
  const std::vector<BagTopic>& topics() const override { return topics_; }
  const std::string& damage() const override { return damage_; }

  void select(const std::string& topic) override {
    std::set<std::uint32_t> ids;
    for (std::uint32_t id = 0; id < channels_.size(); ++id)
      if (channels_[id].topic == topic) ids.insert(id);
    if (ids.empty()) throw no_topic_error(path_, topic, damage_, topics_);
    for (const std::uint32_t id : ids) {
      const std::string& encoding = channels_[id].message_encoding;
      if (encoding != "cdr" && encoding != "ros1")
        throw file_error(path_, "topic " + topic + " uses message encoding '" + encoding +
                                    "' (supported: cdr, ros1)");
    }
    selected_ = in_time_order(entries_, ids, &Entry::channel);
    next_ = 0;
  }

  bool next(BagMessage& message) override {
    if (next_ >= selected_.size()) {
      if (!damage_.empty()) throw file_error(path_, damage_);
      return false;
    }
    const Entry& e = *selected_[next_++];
    McapFile& file = files_[e.file];
    try {
      const auto [data, size] = records_of(e.file, e.chunk);
      const std::string where =
          e.chunk == kNoChunk ? "" : " in chunk " + at_byte(file.chunks[e.chunk].position);
      const Record r = read_record(data, size, static_cast<std::size_t>(e.offset), where);
      const std::uint16_t channel =
          r.op == kOpMessage && r.size >= kMessagePrefix
              ? static_cast<std::uint16_t>(r.content[0] | (r.content[1] << 8))
              : 0;
      if (r.op != kOpMessage || r.size < kMessagePrefix || file.channels.count(channel) == 0 ||
          file.channels.at(channel) != e.channel)
        throw Damage{"index points " + at_byte(e.offset) + where +
                     " to something that is not that message"};
      message.data = r.content + kMessagePrefix;
      message.size = r.size - kMessagePrefix;
      message.stamp_ns = e.time_ns;
      const Channel& c = channels_[e.channel];
      message.type = type_of(file, c);
      message.encoding =
          c.message_encoding == "ros1" ? MessageEncoding::kRos1 : MessageEncoding::kCdr;
    } catch (const Damage& d) {
      throw file_error(path_, in_file(file, d.problem));
    }
    return true;
  }

 private:
  // Problems name the file when the bag is a folder of several.
  std::string in_file(const McapFile& file, const std::string& problem) const {
    return file.path == path_ ? problem : fs::path(file.path).filename().string() + ": " + problem;
  }

  static std::string type_of(const McapFile& file, const Channel& c) {
    const auto schema = file.schemas.find(c.schema);
    return schema == file.schemas.end() ? std::string() : schema->second.name;
  }

  void open_file(const std::string& path) {
    const auto file_index = static_cast<std::uint32_t>(files_.size());
    files_.push_back(McapFile{path, read_file_bytes(path), {}, {}, false, {}, {}, {}});
    McapFile& file = files_.back();
    const std::uint8_t* bytes = file.bytes.begin();
    const std::size_t size = file.bytes.size();
    if (size < sizeof kMagic || std::memcmp(bytes, kMagic, 5) != 0)
      throw file_error(path, "not an MCAP file (no MCAP magic at the start)");
    if (std::memcmp(bytes, kMagic, sizeof kMagic) != 0)
      throw file_error(path, "MCAP major version '" + printable(std::string(1, char(bytes[5]))) +
                                 "' is not supported (only 0)");
    std::size_t first_record = 0;
    try {
      const Record header = read_record(bytes, size, sizeof kMagic, "");
      if (header.op != kOpHeader) throw Damage{"first record is not the MCAP header"};
      parse_record(header, sizeof kMagic, "", "header", [&](ByteCursor& in) {
        file.profile = printable(mcap_string(in));
        file.library = printable(mcap_string(in));
        return 0;
      });
      first_record = header.end;
    } catch (const Damage& d) {
      throw file_error(path, d.problem);
    }
    const std::size_t entries_before = entries_.size(), channels_before = channels_.size();
    try {
      file.indexed = read_summary(file_index);
    } catch (const Damage&) {
      file.indexed = false;  // the scan finds and reports the damage where it lies
    }
    if (!file.indexed) {
      entries_.resize(entries_before);
      channels_.resize(channels_before);
      file.chunks.clear();
      file.schemas.clear();
      file.channels.clear();
      const std::string problem = scan(file_index, first_record);
      if (!problem.empty() && damage_.empty()) damage_ = in_file(file, problem);
    }
  }

  // Schema and Channel records, from the summary or the data section. A channel whose id the file
  // already knows is a repeat (writers repeat them in the summary and in every chunk).
  void add_schema(McapFile& file, const Record& r, std::size_t offset, const std::string& where) {
    parse_record(r, offset, where, "schema", [&](ByteCursor& in) {
      const std::uint16_t id = in.read<std::uint16_t>();
      Schema s;
      s.name = printable(mcap_string(in));
      s.encoding = printable(mcap_string(in));
      s.data = std::string(mcap_string(in));
      if (id != 0) file.schemas.emplace(id, std::move(s));  // id 0 is "no schema"
      return 0;
    });
  }

  void add_channel(std::uint32_t file_index, const Record& r, std::size_t offset,
                   const std::string& where) {
    McapFile& file = files_[file_index];
    parse_record(r, offset, where, "channel", [&](ByteCursor& in) {
      const std::uint16_t id = in.read<std::uint16_t>();
      Channel c;
      c.schema = in.read<std::uint16_t>();
      c.topic = printable(mcap_string(in));
      c.message_encoding = printable(mcap_string(in));
      // The metadata map (uint32 byte length, then pairs) is not needed.
      if (file.channels.count(id) == 0) {
        file.channels[id] = static_cast<std::uint32_t>(channels_.size());
        channels_.push_back(std::move(c));
      }
      return 0;
    });
  }

  std::uint32_t global_channel(const McapFile& file, std::uint16_t id, const std::string& what) {
    const auto found = file.channels.find(id);
    if (found == file.channels.end())
      throw Damage{what + " on unknown channel " + std::to_string(id)};
    return found->second;
  }

  // Reads the summary's chunk indexes and the message indexes they point to. False when the file
  // has no summary or the summary cannot list every message; Damage when it is inconsistent.
  bool read_summary(std::uint32_t file_index) {
    McapFile& file = files_[file_index];
    const std::uint8_t* bytes = file.bytes.begin();
    const std::size_t size = file.bytes.size();
    if (size < 2 * sizeof kMagic + kFooterRecord ||
        std::memcmp(bytes + size - sizeof kMagic, kMagic, sizeof kMagic) != 0)
      return false;
    const std::size_t footer_at = size - sizeof kMagic - kFooterRecord;
    const Record footer = read_record(bytes, size, footer_at, "");
    if (footer.op != kOpFooter || footer.size != kFooterRecord - kRecordPrefix) return false;
    std::uint64_t summary_start, offsets_start;
    std::memcpy(&summary_start, footer.content, 8);
    std::memcpy(&offsets_start, footer.content + 8, 8);
    if (summary_start == 0) return false;
    const std::size_t summary_end = offsets_start != 0 ? offsets_start : footer_at;
    if (summary_start > summary_end || summary_end > footer_at)
      throw Damage{"footer points outside the file"};

    std::vector<std::pair<std::size_t, Record>> chunk_indexes;
    std::uint64_t declared_messages = 0;
    bool have_statistics = false;
    for (std::size_t at = summary_start; at < summary_end;) {
      const Record r = read_record(bytes, summary_end, at, "");
      if (r.op == kOpSchema) add_schema(file, r, at, "");
      if (r.op == kOpChannel) add_channel(file_index, r, at, "");
      if (r.op == kOpChunkIndex) chunk_indexes.emplace_back(at, r);
      if (r.op == kOpStatistics) {
        declared_messages =
            parse_record(r, at, "", "statistics", [](ByteCursor& in) { return in.u64(); });
        have_statistics = true;
      }
      at = r.end;
    }
    if (chunk_indexes.empty()) return have_statistics && declared_messages == 0;

    std::size_t listed = 0;
    for (const auto& [at, index] : chunk_indexes) {
      const auto [chunk_at, index_offsets] =
          parse_record(index, at, "", "chunk index", [&](ByteCursor& in) {
            in.skip(16);  // message start and end times
            const std::uint64_t position = in.u64();
            in.skip(8);  // chunk length
            const std::uint32_t map_bytes = in.u32();
            ByteCursor map(in.take(map_bytes), map_bytes);
            std::vector<std::pair<std::uint16_t, std::uint64_t>> offsets;
            while (map.remaining() > 0) {
              const auto channel = map.read<std::uint16_t>();
              offsets.emplace_back(channel, map.u64());
            }
            return std::make_pair(position, offsets);
          });
      // A writer may leave the message indexes out: then only a scan finds the messages.
      if (index_offsets.empty()) return false;
      if (chunk_at >= size) throw Damage{"chunk index points beyond the end of the file"};
      const Record chunk_record = read_record(bytes, size, chunk_at, "");
      if (chunk_record.op != kOpChunk) throw Damage{"chunk index points to something not a chunk"};
      const auto chunk = static_cast<std::uint32_t>(file.chunks.size());
      file.chunks.push_back(read_chunk(chunk_record, chunk_at));
      for (const auto& [channel_id, offset] : index_offsets) {
        if (offset >= size) throw Damage{"message index beyond the end of the file"};
        const Record r = read_record(bytes, size, offset, "");
        if (r.op != kOpMessageIndex)
          throw Damage{"chunk index points to something not a message index"};
        listed += read_message_index(file_index, chunk, r, offset, channel_id);
      }
    }
    return !have_statistics || listed == declared_messages;
  }

  std::size_t read_message_index(std::uint32_t file_index, std::uint32_t chunk, const Record& r,
                                 std::size_t offset, std::uint16_t channel_id) {
    McapFile& file = files_[file_index];
    return parse_record(r, offset, "", "message index", [&](ByteCursor& in) {
      if (in.read<std::uint16_t>() != channel_id)
        throw Damage{"message index " + at_byte(offset) +
                     " is not for the channel its chunk index names"};
      const std::uint32_t channel =
          global_channel(file, channel_id, "message index " + at_byte(offset));
      const std::uint32_t length = in.u32();
      if (length % 16 != 0)
        throw Damage{"message index " + at_byte(offset) + " has a partial entry"};
      ByteCursor list(in.take(length), length);
      const std::uint64_t chunk_size = file.chunks[chunk].uncompressed_size;
      for (std::uint32_t i = 0; i < length / 16; ++i) {
        const std::uint64_t time = list.u64(), at = list.u64();
        if (at >= chunk_size)
          throw Damage{"message index " + at_byte(offset) + " points beyond its chunk"};
        entries_.push_back({static_cast<std::int64_t>(time), channel, file_index, chunk, at});
      }
      return static_cast<std::size_t>(length / 16);
    });
  }

  // Walks the data section from `offset`; returns the first damage ("" when the data section ends
  // as it should) and keeps every message before it.
  std::string scan(std::uint32_t file_index, std::size_t offset) {
    McapFile& file = files_[file_index];
    const std::uint8_t* bytes = file.bytes.begin();
    const std::size_t size = file.bytes.size();
    try {
      while (offset < size) {
        const Record r = read_record(bytes, size, offset, "");
        if (r.op == kOpDataEnd || r.op == kOpFooter) return {};
        if (r.op == kOpSchema) add_schema(file, r, offset, "");
        if (r.op == kOpChannel) add_channel(file_index, r, offset, "");
        if (r.op == kOpMessage) add_message(file_index, kNoChunk, r, offset, "");
        if (r.op == kOpChunk) {
          const auto chunk = static_cast<std::uint32_t>(file.chunks.size());
          file.chunks.push_back(read_chunk(r, offset));
          scan_chunk(file_index, chunk);
        }
        // Other records (indexes, attachments, metadata, unknown ops) are skipped, as the
        // specification asks of readers.
        offset = r.end;
      }
      return "file ends " + at_byte(size) + " before its data end record (truncated)";
    } catch (const Damage& d) {
      return d.problem;
    }
  }

  void add_message(std::uint32_t file_index, std::uint32_t chunk, const Record& r,
                   std::size_t offset, const std::string& where) {
    const auto [channel_id, time] = parse_record(r, offset, where, "message", [](ByteCursor& in) {
      const auto channel = in.read<std::uint16_t>();
      in.skip(4);  // sequence
      return std::make_pair(channel, in.u64());
    });
    const std::uint32_t channel =
        global_channel(files_[file_index], channel_id, "message " + at_byte(offset) + where);
    entries_.push_back({static_cast<std::int64_t>(time), channel, file_index, chunk, offset});
  }

  void scan_chunk(std::uint32_t file_index, std::uint32_t chunk) {
    const std::size_t entries_before = entries_.size();
    const auto [data, size] = records_of(file_index, chunk);
    const std::string where = " in chunk " + at_byte(files_[file_index].chunks[chunk].position);
    try {
      for (std::size_t offset = 0; offset < size;) {
        const Record r = read_record(data, size, offset, where);
        if (r.op == kOpSchema) add_schema(files_[file_index], r, offset, where);
        if (r.op == kOpChannel) add_channel(file_index, r, offset, where);
        if (r.op == kOpMessage) add_message(file_index, chunk, r, offset, where);
        offset = r.end;
      }
    } catch (const Damage&) {
      entries_.resize(entries_before);  // a chunk counts only when all of it reads
      throw;
    }
  }

  // The records of a chunk (decompressed and checked once, kept while the next messages come from
  // it), or the whole file for messages in the data section.
  std::pair<const std::uint8_t*, std::size_t> records_of(std::uint32_t file_index,
                                                         std::uint32_t chunk_index) {
    const McapFile& file = files_[file_index];
    if (chunk_index == kNoChunk) return {file.bytes.begin(), file.bytes.size()};
    const Chunk& chunk = file.chunks[chunk_index];
    if (cached_file_ == file_index && cached_chunk_ == chunk_index)
      return {cached_data_, static_cast<std::size_t>(chunk.uncompressed_size)};
    cached_chunk_ = kNoChunk;
    const std::uint8_t* data = chunk.data;
    if (!chunk.compression.empty()) {
      if (chunk.uncompressed_size > std::numeric_limits<std::size_t>::max() / 2)
        throw Damage{"chunk " + at_byte(chunk.position) + " declares an impossible size"};
      const auto expected = static_cast<std::size_t>(chunk.uncompressed_size);
      const std::string problem =
          chunk.compression == "lz4"
              ? decompress_lz4_frame(chunk.data, chunk.size, expected, buffer_)
              : decompress_zstd(chunk.data, chunk.size, expected, buffer_);
      if (!problem.empty()) throw Damage{"chunk " + at_byte(chunk.position) + ": " + problem};
      data = buffer_.data();
    }
    const auto size = static_cast<std::size_t>(chunk.uncompressed_size);
    if (chunk.crc != 0 && crc32_z(0, data, size) != chunk.crc)
      throw Damage{"chunk " + at_byte(chunk.position) + ": CRC of its records does not match"};
    cached_file_ = file_index;
    cached_chunk_ = chunk_index;
    cached_data_ = data;
    return {data, size};
  }

  void build_topics() {
    std::map<std::string, std::size_t> by_name;
    for (const McapFile& file : files_) {
      for (const auto& [id, global] : file.channels) {
        const Channel& c = channels_[global];
        if (by_name.count(c.topic)) continue;
        by_name[c.topic] = topics_.size();
        BagTopic t;
        t.name = c.topic;
        t.type = type_of(file, c);
        const auto schema = file.schemas.find(c.schema);
        if (schema != file.schemas.end() && schema->second.encoding == "ros1msg")
          t.definition = schema->second.data;
        topics_.push_back(std::move(t));
      }
    }
    for (const Entry& e : entries_)
      count_message(topics_[by_name.at(channels_[e.channel].topic)], e.time_ns);
    std::sort(topics_.begin(), topics_.end(),
              [](const BagTopic& a, const BagTopic& b) { return a.name < b.name; });
  }

  std::string path_;
  std::vector<McapFile> files_;
  std::vector<Channel> channels_;
  std::vector<Entry> entries_;
  std::vector<BagTopic> topics_;
  std::string damage_;
  std::vector<const Entry*> selected_;
  std::size_t next_ = 0;
  std::uint32_t cached_file_ = kNoChunk, cached_chunk_ = kNoChunk;
  const std::uint8_t* cached_data_ = nullptr;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace

std::unique_ptr<BagReader> open_mcap_bag(const std::string& path,
                                         const std::vector<std::string>& files) {
  return std::make_unique<McapBag>(path, files);
}

}  // namespace iilfm::io
