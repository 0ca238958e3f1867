// ROS 1 bag format 2.0 (http://wiki.ros.org/Bags/Format/2.0). A bag is a sequence of records, each
// a header (length-prefixed "name=value" fields, "op" giving the record kind) and a data block:
//   bag header (op 3): index_pos, conn_count, chunk_count; padded to 4096 bytes
//   chunk (op 5): compression none|bz2|lz4 and the uncompressed size; data = connection (op 7) and
//     message data (op 2: conn, time) records
//   index data (op 4), after each chunk: for one connection, (time, offset in chunk) per message
//   at index_pos: every connection record, then one chunk info (op 6) record per chunk
// The index gives each topic's messages without decompressing other chunks. When the index is
// missing or broken (a recorder that died, a truncated copy), the chunks are scanned in file order
// instead, up to the first damage.
#include <algorithm>
#include <map>
#include <set>
#include <string_view>
#include <unordered_map>

#include "byte_cursor.hpp"
#include "chunk_decompress.hpp"
#include "file_bytes.hpp"
#include "iilfm/error.hpp"
#include "ros_bags.hpp"

namespace iilfm::io {
namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
constexpr std::uint8_t kOpMessage = 0x02, kOpBagHeader = 0x03, kOpIndexData = 0x04, kOpChunk = 0x05,
                       kOpChunkInfo = 0x06, kOpConnection = 0x07;

// A problem with the bag's bytes; the message is completed with the file name by the caller.
struct Damage {
  std::string problem;
};

std::string at_byte(std::size_t offset) { return "at byte " + std::to_string(offset); }

struct Record {
  std::vector<std::pair<std::string_view, std::string_view>> fields;
  const std::uint8_t* data = nullptr;
  std::size_t data_size = 0;
  std::size_t end = 0;  // offset of the next record

  std::string_view field(std::string_view name) const {
    for (const auto& [key, value] : fields)
      if (key == name) return value;
    throw Damage{"record without '" + std::string(name) + "' field"};
  }
  bool has(std::string_view name) const {
    for (const auto& f : fields)
      if (f.first == name) return true;
    return false;
  }
  template <typename T>
  T number(std::string_view name) const {
    const std::string_view value = field(name);
    if (value.size() != sizeof(T))
      throw Damage{"field '" + std::string(name) + "' has " + std::to_string(value.size()) +
                   " bytes, expected " + std::to_string(sizeof(T))};
    T out;
    std::memcpy(&out, value.data(), sizeof(T));
    return out;
  }
  std::uint8_t op() const { return number<std::uint8_t>("op"); }
  // ROS time: uint32 seconds then uint32 nanoseconds.
  std::int64_t time_ns(std::string_view name) const {
    const std::uint64_t packed = number<std::uint64_t>(name);
    return static_cast<std::int64_t>(packed & 0xffffffffu) * 1'000'000'000 +
           static_cast<std::int64_t>(packed >> 32);
  }
};

// "name=value" fields, each prefixed by its uint32 length.
std::vector<std::pair<std::string_view, std::string_view>> parse_fields(const std::uint8_t* data,
                                                                        std::size_t size) {
  std::vector<std::pair<std::string_view, std::string_view>> fields;
  ByteCursor in(data, size);
  try {
    while (in.remaining() > 0) {
      const std::uint32_t length = in.u32();
      const std::string_view text = in.take_text(length);
      const std::size_t equals = text.find('=');
      if (equals == std::string_view::npos) throw Damage{"header field without '='"};
      fields.emplace_back(text.substr(0, equals), text.substr(equals + 1));
    }
  } catch (const ShortData&) {
    throw Damage{"header field runs past its header"};
  }
  return fields;
}

// The record at `offset` of `size` bytes; `where` names the place for messages ("" for the file,
// "in chunk at byte N" inside a chunk).
Record read_record(const std::uint8_t* base, std::size_t size, std::size_t offset,
                   const std::string& where) {
  try {
    ByteCursor in(base, size);
    in.skip(offset);
    Record record;
    const std::uint32_t header_size = in.u32();
    const std::uint8_t* header = in.take(header_size);
    record.fields = parse_fields(header, header_size);
    record.data_size = in.u32();
    record.data = in.take(record.data_size);
    record.end = in.offset();
    return record;
  } catch (const ShortData& e) {
    throw Damage{"record " + at_byte(offset) + where + " is cut off (needs " +
                 std::to_string(e.wanted) + " bytes " + at_byte(e.offset) + ", " +
                 std::to_string(size - e.offset) + " left)"};
  } catch (const Damage& e) {
    throw Damage{"record " + at_byte(offset) + where + ": " + e.problem};
  }
}

struct Connection {
  std::string topic, type, definition;
};

Connection read_connection(const Record& record) {
  Connection c;
  c.topic = printable(record.field("topic"));
  const auto fields = parse_fields(record.data, record.data_size);
  for (const auto& [key, value] : fields) {
    if (key == "type") c.type = printable(value);
    if (key == "message_definition") c.definition = std::string(value);
  }
  if (c.type.empty()) throw Damage{"connection for " + c.topic + " has no type"};
  return c;
}

struct Chunk {
  std::size_t position = 0;  // of the chunk record in the file
  std::string compression;
  std::uint32_t size = 0;  // uncompressed
  const std::uint8_t* data = nullptr;
  std::size_t data_size = 0;
};

// One message: where its record lies inside which chunk.
struct Entry {
  std::int64_t time_ns;
  std::uint32_t connection;
  std::uint32_t chunk;
  std::uint32_t offset;
};

class Ros1Bag final : public BagReader {
 public:
  explicit Ros1Bag(const std::string& path) : path_(path), file_(read_file_bytes(path)) {
    try {
      open();
    } catch (const Damage& e) {
      throw file_error(path_, e.problem);
    }
  }

  const std::string& path() const override { return path_; }
  std::string format() const override {
    std::set<std::string> kinds;
    for (const Chunk& c : chunks_) kinds.insert(c.compression);
    std::string compressions;
    for (const std::string& k : kinds) compressions += (compressions.empty() ? "" : ", ") + k;
    return "ROS 1 bag v2.0, " + std::to_string(chunks_.size()) + " chunks" +
           (compressions.empty() ? "" : " (" + compressions + ")") +
           (indexed_ ? ", indexed" : ", index missing or damaged: chunks scanned");
  }
  const std::vector<BagTopic>& topics() const override { return topics_; }
  const std::string& damage() const override { return damage_; }

  void select(const std::string& topic) override {
    std::set<std::uint32_t> ids;
    for (const auto& [id, c] : connections_)
      if (c.topic == topic) ids.insert(id);
    if (ids.empty()) throw no_topic_error(path_, topic, damage_, topics_);
    selected_ = in_time_order(entries_, ids, &Entry::connection);
    next_ = 0;
  }

  bool next(BagMessage& message) override {
    if (next_ >= selected_.size()) {
      if (!damage_.empty()) throw file_error(path_, damage_);
      return false;
    }
    const Entry& e = *selected_[next_++];
    try {
      const auto [data, size] = chunk_data(e.chunk);
      const std::string where = " in chunk " + at_byte(chunks_[e.chunk].position);
      const Record record = read_record(data, size, e.offset, where);
      if (record.op() != kOpMessage || record.number<std::uint32_t>("conn") != e.connection)
        throw Damage{"index points " + at_byte(e.offset) + where +
                     " to something that is not that message"};
      message.data = record.data;
      message.size = record.data_size;
      message.stamp_ns = e.time_ns;
      message.type = connections_.at(e.connection).type;
      message.encoding = MessageEncoding::kRos1;
    } catch (const Damage& d) {
      throw file_error(path_, d.problem);
    }
    return true;
  }

 private:
  void open() {
    if (file_.size() < kMagic.size() ||
        std::string_view(reinterpret_cast<const char*>(file_.begin()), kMagic.size()) != kMagic) {
      const std::string_view start(reinterpret_cast<const char*>(file_.begin()),
                                   std::min<std::size_t>(file_.size(), 12));
      if (start.substr(0, 9) == "#ROSBAG V")
        throw Damage{"ROS bag version " + std::string(start.substr(9, 3)) +
                     " is not supported (only 2.0)"};
      throw Damage{"not a ROS 1 bag (no '#ROSBAG V2.0' line at the start)"};
    }
    const Record header = read_record(file_.begin(), file_.size(), kMagic.size(), "");
    if (header.op() != kOpBagHeader) throw Damage{"first record is not the bag header"};
    const std::uint64_t index_pos = header.number<std::uint64_t>("index_pos");
    const std::uint32_t conn_count = header.number<std::uint32_t>("conn_count");
    const std::uint32_t chunk_count = header.number<std::uint32_t>("chunk_count");
    first_record_ = header.end;
    indexed_ = false;
    if (index_pos != 0 && index_pos < file_.size()) {
      try {
        read_index(index_pos, conn_count, chunk_count);
        indexed_ = true;
      } catch (const Damage&) {
        // Fall through to the scan, which finds and reports the damage where it lies.
      }
    }
    if (!indexed_) {
      connections_.clear();
      chunks_.clear();
      entries_.clear();
      scan();
      if (damage_.empty() && index_pos > file_.size())
        damage_ = "file ends " + at_byte(file_.size()) + " before its index " + at_byte(index_pos) +
                  " (truncated)";
    }
    build_topics();
  }

  Chunk chunk_at(const Record& record, std::size_t position) const {
    Chunk chunk;
    chunk.position = position;
    chunk.compression = std::string(record.field("compression"));
    chunk.size = record.number<std::uint32_t>("size");
    chunk.data = record.data;
    chunk.data_size = record.data_size;
    if (chunk.compression != "none" && chunk.compression != "bz2" && chunk.compression != "lz4")
      throw Damage{"chunk " + at_byte(position) + " has unknown compression '" + chunk.compression +
                   "'"};
    if (chunk.compression == "none" && chunk.size != chunk.data_size)
      throw Damage{"uncompressed chunk " + at_byte(position) + " declares " +
                   std::to_string(chunk.size) + " bytes but holds " +
                   std::to_string(chunk.data_size)};
    return chunk;
  }

  void read_index(std::uint64_t index_pos, std::uint32_t conn_count, std::uint32_t chunk_count) {
    std::size_t offset = index_pos;
    for (std::uint32_t i = 0; i < conn_count; ++i) {
      const Record r = read_record(file_.begin(), file_.size(), offset, "");
      if (r.op() != kOpConnection) throw Damage{"index: expected a connection record"};
      connections_[r.number<std::uint32_t>("conn")] = read_connection(r);
      offset = r.end;
    }
    for (std::uint32_t i = 0; i < chunk_count; ++i) {
      const Record info = read_record(file_.begin(), file_.size(), offset, "");
      if (info.op() != kOpChunkInfo) throw Damage{"index: expected a chunk info record"};
      offset = info.end;
      const std::uint64_t position = info.number<std::uint64_t>("chunk_pos");
      if (position >= file_.size()) throw Damage{"index: chunk beyond the end of the file"};
      const Record chunk_record = read_record(file_.begin(), file_.size(), position, "");
      if (chunk_record.op() != kOpChunk) throw Damage{"index: chunk_pos is not a chunk"};
      const auto chunk_index = static_cast<std::uint32_t>(chunks_.size());
      chunks_.push_back(chunk_at(chunk_record, position));
      // The chunk's index data records follow it directly.
      std::size_t at = chunk_record.end;
      while (at < index_pos) {
        const Record index = read_record(file_.begin(), file_.size(), at, "");
        if (index.op() != kOpIndexData) break;
        read_index_data(index, chunk_index);
        at = index.end;
      }
    }
  }

  void read_index_data(const Record& index, std::uint32_t chunk) {
    if (index.number<std::uint32_t>("ver") != 1) throw Damage{"index data version is not 1"};
    const std::uint32_t connection = index.number<std::uint32_t>("conn");
    const std::uint32_t count = index.number<std::uint32_t>("count");
    if (!connections_.count(connection)) throw Damage{"index data for an unknown connection"};
    if (static_cast<std::uint64_t>(count) * 12 != index.data_size)
      throw Damage{"index data size does not match its count"};
    ByteCursor in(index.data, index.data_size);
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::int64_t sec = in.u32(), nsec = in.u32();
      const std::uint32_t offset = in.u32();
      if (offset >= chunks_[chunk].size) throw Damage{"index data offset beyond its chunk"};
      entries_.push_back({sec * 1'000'000'000 + nsec, connection, chunk, offset});
    }
  }

  // Walks every record from the first after the bag header; stops at the first damage and keeps
  // what came before it.
  void scan() {
    std::size_t offset = first_record_;
    try {
      while (offset < file_.size()) {
        const Record r = read_record(file_.begin(), file_.size(), offset, "");
        const std::uint8_t op = r.op();
        if (op == kOpChunk) {
          const auto chunk_index = static_cast<std::uint32_t>(chunks_.size());
          chunks_.push_back(chunk_at(r, offset));
          scan_chunk(chunk_index);
        } else if (op == kOpConnection) {
          const std::uint32_t id = r.number<std::uint32_t>("conn");
          if (!connections_.count(id)) connections_[id] = read_connection(r);
        } else if (op != kOpIndexData && op != kOpChunkInfo) {
          throw Damage{"record " + at_byte(offset) + " has unknown op " + std::to_string(op)};
        }
        offset = r.end;
      }
    } catch (const Damage& e) {
      damage_ = e.problem;
    }
  }

  void scan_chunk(std::uint32_t chunk_index) {
    const auto [data, size] = chunk_data(chunk_index);
    const std::string where = " in chunk " + at_byte(chunks_[chunk_index].position);
    std::vector<Entry> found;
    std::size_t offset = 0;
    while (offset < size) {
      const Record r = read_record(data, size, offset, where);
      const std::uint8_t op = r.op();
      if (op == kOpConnection) {
        const std::uint32_t id = r.number<std::uint32_t>("conn");
        if (!connections_.count(id)) connections_[id] = read_connection(r);
      } else if (op == kOpMessage) {
        const std::uint32_t id = r.number<std::uint32_t>("conn");
        if (!connections_.count(id))
          throw Damage{"message " + at_byte(offset) + where + " on an unknown connection"};
        found.push_back({r.time_ns("time"), id, chunk_index, static_cast<std::uint32_t>(offset)});
      } else {
        throw Damage{"record " + at_byte(offset) + where + " has unexpected op " +
                     std::to_string(op)};
      }
      offset = r.end;
    }
    // A chunk counts only when all of it reads.
    entries_.insert(entries_.end(), found.begin(), found.end());
  }

  // The chunk's records, decompressed once and kept until another chunk is needed.
  std::pair<const std::uint8_t*, std::size_t> chunk_data(std::uint32_t index) {
    const Chunk& chunk = chunks_[index];
    if (chunk.compression == "none") return {chunk.data, chunk.data_size};
    if (cached_chunk_ != index) {
      cached_chunk_ = UINT32_MAX;
      const std::string problem =
          chunk.compression == "bz2"
              ? decompress_bz2(chunk.data, chunk.data_size, chunk.size, buffer_)
              : decompress_lz4_frame(chunk.data, chunk.data_size, chunk.size, buffer_);
      if (!problem.empty()) throw Damage{"chunk " + at_byte(chunk.position) + ": " + problem};
      cached_chunk_ = index;
    }
    return {buffer_.data(), buffer_.size()};
  }

  void build_topics() {
    std::unordered_map<std::string, std::size_t> by_name;
    for (const auto& [id, c] : connections_) {
      if (by_name.count(c.topic)) continue;
      by_name[c.topic] = topics_.size();
      BagTopic t;
      t.name = c.topic;
      t.type = c.type;
      t.definition = c.definition;
      topics_.push_back(std::move(t));
    }
    for (const Entry& e : entries_)
      count_message(topics_[by_name.at(connections_.at(e.connection).topic)], e.time_ns);
    std::sort(topics_.begin(), topics_.end(),
              [](const BagTopic& a, const BagTopic& b) { return a.name < b.name; });
  }

  std::string path_;
  FileBytes file_;
  std::size_t first_record_ = 0;
  bool indexed_ = false;
  std::map<std::uint32_t, Connection> connections_;
  std::vector<Chunk> chunks_;
  std::vector<Entry> entries_;
  std::vector<BagTopic> topics_;
  std::string damage_;
  std::vector<const Entry*> selected_;
  std::size_t next_ = 0;
  std::uint32_t cached_chunk_ = UINT32_MAX;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace

std::unique_ptr<BagReader> open_ros1_bag(const std::string& path) {
  return std::make_unique<Ros1Bag>(path);
}

}  // namespace iilfm::io
