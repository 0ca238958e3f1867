// Point-cloud messages: sensor_msgs/PointCloud2 and Livox CustomMsg, in the ROS 1 serialization
// (little-endian, packed, uint32 lengths) and in CDR (ROS 2: a 4-byte encapsulation header, then
// every value aligned to its size counted from the end of that header, strings NUL-terminated).
#include <algorithm>
#include <iterator>
#include <string_view>

#include "byte_cursor.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/bag.hpp"
#include "packed_points.hpp"
#include "pcd_header.hpp"
#include "point_filter.hpp"

namespace iilfm::io {
namespace {

constexpr std::string_view kPointCloud2[] = {"sensor_msgs/PointCloud2",
                                             "sensor_msgs/msg/PointCloud2"};
// One layout under five names: livox_ros_driver (ROS 1, and ROS 1 bags converted to ROS 2),
// livox_ros_driver2 (ROS 1 and 2) and livox_ros2_driver's livox_interfaces.
constexpr std::string_view kLivox[] = {
    "livox_ros_driver/CustomMsg", "livox_ros_driver2/CustomMsg", "livox_ros_driver/msg/CustomMsg",
    "livox_ros_driver2/msg/CustomMsg", "livox_interfaces/msg/CustomMsg"};

template <std::size_t N>
bool one_of(const std::string& type, const std::string_view (&names)[N]) {
  return std::find(std::begin(names), std::end(names), type) != std::end(names);
}

// Reads one message's values in either serialization: the two differ only in alignment, string
// terminators and the byte order chosen by the CDR header.
class MessageCursor {
 public:
  explicit MessageCursor(const BagMessage& m) : cursor_(m.data, m.size) {
    if (m.encoding == MessageEncoding::kCdr) {
      cdr_ = true;
      const std::uint8_t* header = cursor_.take(4);
      if (header[0] != 0 || header[1] > 1) throw BadMessage{"unknown CDR encapsulation"};
      big_endian_ = header[1] == 0;
      cursor_.set_big_endian(big_endian_);
      origin_ = 4;
    }
  }
  struct BadMessage {
    std::string problem;
  };

  std::uint8_t u8() { return cursor_.u8(); }
  std::uint32_t u32() { return aligned<std::uint32_t>(); }
  std::uint64_t u64() { return aligned<std::uint64_t>(); }
  std::string string() {
    const std::uint32_t length = u32();
    std::string_view text = cursor_.take_text(length);
    if (cdr_ && !text.empty() && text.back() == '\0') text.remove_suffix(1);
    return std::string(text);
  }
  // std_msgs/Header: ROS 1 has a sequence number before the stamp; both end with frame_id.
  std::int64_t header_stamp_ns() {
    if (!cdr_) u32();  // seq
    const std::int64_t sec = static_cast<std::int32_t>(u32());
    const std::int64_t nsec = u32();
    string();  // frame_id
    return sec * 1'000'000'000 + nsec;
  }
  // A uint8 sequence: its length, then the bytes.
  std::pair<const std::uint8_t*, std::size_t> bytes() {
    const std::uint32_t length = u32();
    return {cursor_.take(length), length};
  }
  void align(std::size_t n) {
    if (cdr_) cursor_.align(n, origin_);
  }
  const std::uint8_t* take(std::size_t n) { return cursor_.take(n); }
  std::size_t offset() const { return cursor_.offset(); }
  std::size_t remaining() const { return cursor_.remaining(); }
  bool cdr() const { return cdr_; }
  bool big_endian() const { return big_endian_; }

 private:
  template <typename T>
  T aligned() {
    align(sizeof(T));
    return cursor_.read<T>();
  }

  ByteCursor cursor_;
  bool cdr_ = false;
  bool big_endian_ = false;
  std::size_t origin_ = 0;
};

ScalarType pointfield_type(std::uint8_t datatype, const std::string& field,
                           const std::string& context) {
  switch (datatype) {
    case 1:
      return ScalarType::kI8;
    case 2:
      return ScalarType::kU8;
    case 3:
      return ScalarType::kI16;
    case 4:
      return ScalarType::kU16;
    case 5:
      return ScalarType::kI32;
    case 6:
      return ScalarType::kU32;
    case 7:
      return ScalarType::kF32;
    case 8:
      return ScalarType::kF64;
  }
  throw InputError(context + ": PointCloud2 field '" + quote_for_message(field) +
                   "' has unknown datatype " + std::to_string(datatype));
}

std::string field_list(const std::vector<PackedField>& fields) {
  std::string names;
  for (const PackedField& f : fields)
    names += (names.empty() ? "" : ", ") + quote_for_message(f.name);
  return names.empty() ? "none" : names;
}

CloudMessage decode_pointcloud2(MessageCursor& in, const std::string& context) {
  CloudMessage out;
  out.header_stamp_ns = in.header_stamp_ns();
  const std::uint64_t height = in.u32(), width = in.u32();
  const std::uint32_t field_count = in.u32();
  std::vector<PackedField> fields;
  for (std::uint32_t i = 0; i < field_count; ++i) {
    PackedField f;
    f.name = in.string();
    f.offset = in.u32();
    const std::uint8_t datatype = in.u8();
    in.u32();  // count: element 0 is used
    f.type = pointfield_type(datatype, f.name, context);
    fields.push_back(std::move(f));
  }
  const bool big_endian = in.u8() != 0;
  const std::uint64_t point_step = in.u32(), row_step = in.u32();
  const auto [data, data_size] = in.bytes();
  in.u8();  // is_dense: every point is checked anyway

  const PackedRoles roles = find_packed_roles(fields);
  if (!roles.has_xyz())
    throw InputError(context +
                     ": PointCloud2 has no x, y, z fields (fields: " + field_list(fields) + ")");
  for (const PackedField& f : fields) {
    if (f.offset + scalar_size(f.type) > point_step)
      throw InputError(context + ": PointCloud2 field '" + quote_for_message(f.name) +
                       "' at offset " + std::to_string(f.offset) + " does not fit in point_step " +
                       std::to_string(point_step));
  }
  const std::uint64_t points = width * height;  // both < 2^32: no overflow
  if (points == 0) return out;
  if (row_step < width * point_step)
    throw InputError(context + ": PointCloud2 row_step " + std::to_string(row_step) +
                     " is shorter than width * point_step " + std::to_string(width * point_step));
  const std::uint64_t needed = (height - 1) * row_step + width * point_step;
  if (needed > data_size)
    throw InputError(context + ": PointCloud2 data holds " + std::to_string(data_size) +
                     " bytes, " + std::to_string(height) + "x" + std::to_string(width) +
                     " points need " + std::to_string(needed));
  if (row_step == width * point_step) {
    decode_packed_records(data, points, point_step, fields, roles, big_endian, out.loaded);
  } else {
    for (std::uint64_t r = 0; r < height; ++r)
      decode_packed_records(data + r * row_step, width, point_step, fields, roles, big_endian,
                            out.loaded);
  }
  return out;
}

// livox_ros_driver(2)/CustomMsg: a header, the nanosecond timebase, then CustomPoint records
// (offset_time uint32, x y z float32, reflectivity tag line uint8).
CloudMessage decode_livox(MessageCursor& in) {
  CloudMessage out;
  out.header_stamp_ns = in.header_stamp_ns();
  const std::uint64_t timebase = in.u64();
  in.u32();    // point_num: the array length below is what counts
  in.take(4);  // lidar_id, rsvd[3]
  const std::size_t n = in.u32();
  if (in.big_endian()) throw MessageCursor::BadMessage{"big-endian CDR is not supported"};
  // CDR aligns each record's uint32 to 4 bytes: 19 bytes of values, 20 per record.
  const std::size_t record = in.cdr() ? 20 : 19;
  const std::size_t last = n == 0 ? 0 : 19;
  const std::uint8_t* points = n == 0 ? nullptr : in.take((n - 1) * record + last);
  // The points end the message (CDR may pad it to 4 bytes): more bytes mean another type under
  // this name, whose points would be garbage.
  if (in.remaining() > (in.cdr() ? 3u : 0u))
    throw MessageCursor::BadMessage{std::to_string(in.remaining()) +
                                    " bytes after the last point: not a Livox CustomMsg layout"};
  LoadedCloud& loaded = out.loaded;
  loaded.stats.points_in_file = n;
  loaded.cloud.reserve(n, true, true);
  for (std::size_t done = 0; done < n; done += kDecodeBlockPoints) {
    const std::size_t count = std::min(kDecodeBlockPoints, n - done);
    const std::size_t slot = grow_columns(loaded.cloud, count, true, true);
    PointCloud& c = loaded.cloud;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint8_t* p = points + (done + i) * record;
      std::uint32_t offset_time;
      std::memcpy(&offset_time, p, 4);
      std::memcpy(&c.x[slot + i], p + 4, 4);
      std::memcpy(&c.y[slot + i], p + 8, 4);
      std::memcpy(&c.z[slot + i], p + 12, 4);
      c.intensity[slot + i] = p[16];
      c.ring[slot + i] = p[18];
      c.time[slot + i] = static_cast<double>(timebase + offset_time) * 1e-9;
    }
    drop_invalid_points(c, slot, loaded.stats);
  }
  return out;
}

}  // namespace

bool is_cloud_message_type(const std::string& type) {
  return one_of(type, kPointCloud2) || one_of(type, kLivox);
}

std::string cloud_message_types() {
  return "sensor_msgs/PointCloud2, livox_ros_driver/CustomMsg, livox_ros_driver2/CustomMsg, "
         "livox_interfaces/msg/CustomMsg";
}

CloudMessage decode_cloud_message(const BagMessage& message, const std::string& context) {
  if (!is_cloud_message_type(message.type))
    throw InputError(context + ": type " + message.type +
                     " is not a point cloud (supported: " + cloud_message_types() + ")");
  const char* what = one_of(message.type, kPointCloud2) ? "PointCloud2" : "CustomMsg";
  try {
    MessageCursor in(message);
    if (one_of(message.type, kPointCloud2)) return decode_pointcloud2(in, context);
    return decode_livox(in);
  } catch (const ShortData& e) {
    throw InputError(context + ": " + what + " message of " + std::to_string(message.size) +
                     " bytes is truncated (needs " + std::to_string(e.wanted) +
                     " bytes at offset " + std::to_string(e.offset) + ")");
  } catch (const MessageCursor::BadMessage& e) {
    throw InputError(context + ": " + what + ": " + e.problem);
  }
}

}  // namespace iilfm::io
