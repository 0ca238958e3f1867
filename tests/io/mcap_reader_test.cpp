// The MCAP reader against recordings written by the official MCAP writer (@mcap/core, see
// tests/data/mcap/README.md): zstd, lz4 and uncompressed chunks, messages outside chunks, a file
// without a summary, a rosbag2 folder split in two files and Livox CustomMsg. Every point as
// written, in log-time order although the writer stored message 3 before 2. Then damaged copies:
// cut files, corrupt chunks, a broken summary, foreign files.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "bag_test_data.hpp"
#include "iilfm/io/bag.hpp"
#include "iilfm/io/frame_source.hpp"

namespace iilfm::io {
namespace {

using nlohmann::json;

std::string data_dir() { return std::string(IILFM_SOURCE_DIR) + "/tests/data/mcap"; }

const json& expected_files() {
  static const json files = testing::load_json(data_dir() + "/expected.json")["files"];
  return files;
}

std::int64_t ns(const json& text) { return std::stoll(text.get<std::string>()); }

// Reads `topic` to its end, checking every message against the writer's record of it; returns how
// many came out. `error` gets the InputError text that stopped it ("" at a clean end).
std::size_t read_topic(BagReader& bag, const std::string& topic, const json& want,
                       std::string& error) {
  std::size_t delivered = 0;
  error.clear();
  try {
    bag.select(topic);
    BagMessage message;
    while (bag.next(message)) {
      SCOPED_TRACE(topic + " message " + std::to_string(delivered));
      if (delivered >= want.size()) {
        ADD_FAILURE() << "more messages than written";
        break;
      }
      const json& w = want[delivered];
      EXPECT_EQ(message.stamp_ns, ns(w["log_time"]));
      EXPECT_EQ(message.encoding, MessageEncoding::kCdr);
      if (is_cloud_message_type(message.type)) {
        const CloudMessage cloud = decode_cloud_message(message, bag.path());
        EXPECT_EQ(cloud.header_stamp_ns, w["stamp"]["sec"].get<std::int64_t>() * 1'000'000'000 +
                                             w["stamp"]["nanosec"].get<std::int64_t>());
        const PointCloud& c = cloud.loaded.cloud;
        const json& points = w["points"];
        EXPECT_EQ(cloud.loaded.stats.points_in_file, points.size());
        EXPECT_EQ(c.size(), points.size());
        const bool livox = w.contains("timebase");
        for (std::size_t i = 0; i < std::min(c.size(), points.size()); ++i) {
          const json& p = points[i];
          EXPECT_EQ(c.x[i], p[0].get<float>()) << "point " << i;
          EXPECT_EQ(c.y[i], p[1].get<float>()) << "point " << i;
          EXPECT_EQ(c.z[i], p[2].get<float>()) << "point " << i;
          EXPECT_EQ(c.intensity[i], p[3].get<float>()) << "point " << i;
          if (!c.has_ring() || !c.has_time()) {
            ADD_FAILURE() << "no ring or time column";
            break;
          }
          // Livox: ring = line, time = (timebase + offset_time) in seconds.
          EXPECT_EQ(c.ring[i], livox ? p[5].get<int>() : p[4].get<int>()) << "point " << i;
          const double time =
              livox ? static_cast<double>(ns(w["timebase"]) + p[6].get<std::int64_t>()) * 1e-9
                    : p[5].get<float>();
          EXPECT_DOUBLE_EQ(c.time[i], time) << "point " << i;
        }
      } else {
        EXPECT_EQ(message.type, "std_msgs/msg/String");
      }
      ++delivered;
    }
  } catch (const InputError& e) {
    error = e.what();
  }
  return delivered;
}

class McapFixtureTest : public ::testing::TestWithParam<std::string> {};

TEST_P(McapFixtureTest, TopicsAndEveryPointAsWrittenInLogTimeOrder) {
  const json& want = expected_files()[GetParam()];
  const auto bag = open_bag(data_dir() + "/" + GetParam());
  EXPECT_TRUE(bag->damage().empty()) << bag->damage();
  const std::string format = bag->format();
  EXPECT_EQ(format.rfind("MCAP (ros2 profile)", 0), 0u) << format;
  // With a summary and chunks the indexes find the messages; otherwise the data section is read.
  const bool indexed =
      GetParam() != "points_unchunked.mcap" && GetParam() != "points_no_summary.mcap";
  EXPECT_EQ(format.find("indexed") != std::string::npos, indexed) << format;

  ASSERT_EQ(bag->topics().size(), want["topics"].size());
  for (std::size_t t = 0; t < want["topics"].size(); ++t) {
    const json& topic = want["topics"][t];
    const BagTopic& got = bag->topics()[t];  // both sorted by name
    const std::string name = topic["name"].get<std::string>();
    EXPECT_EQ(got.name, name);
    EXPECT_EQ(got.type, topic["type"].get<std::string>());
    EXPECT_EQ(got.messages, topic["message_count"].get<std::size_t>());
    const json& messages = want["messages"][name];
    EXPECT_EQ(got.first_ns, ns(messages.front()["log_time"]));
    EXPECT_EQ(got.last_ns, ns(messages.back()["log_time"]));

    std::string error;
    EXPECT_EQ(read_topic(*bag, name, messages, error), messages.size());
    EXPECT_EQ(error, "");
  }
}

INSTANTIATE_TEST_SUITE_P(Files, McapFixtureTest,
                         ::testing::Values("points_zstd.mcap", "points_lz4.mcap",
                                           "points_uncompressed.mcap", "points_unchunked.mcap",
                                           "points_no_summary.mcap", "livox.mcap", "ros2_folder"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

TEST(McapBag, SplitFolderIsOneRecordingAndFramesCarryTheHeaderStamps) {
  const std::string folder = data_dir() + "/ros2_folder";
  ASSERT_TRUE(is_bag_path(folder));
  EXPECT_NE(open_bag(folder)->format().find("2 files"), std::string::npos);
  const auto frames = open_frame_source(folder, "/points");
  Frame frame;
  std::vector<double> stamps;
  while (frames->next(frame)) stamps.push_back(frame.stamp_s);
  EXPECT_EQ(stamps, (std::vector<double>{100.5, 101.5, 102.5, 103.5, 104.5}));
}

// The first message of `topic` in `file`, its bytes copied.
std::pair<BagMessage, std::vector<std::uint8_t>> first_message(const std::string& file,
                                                               const std::string& topic) {
  const auto bag = open_bag(data_dir() + "/" + file);
  bag->select(topic);
  BagMessage message;
  EXPECT_TRUE(bag->next(message));
  std::vector<std::uint8_t> bytes(message.data, message.data + message.size);
  return {message, bytes};
}

TEST(McapBag, LivoxLayoutUnderEveryDriversTypeName) {
  auto [message, bytes] = first_message("livox.mcap", "/livox/lidar");
  message.data = bytes.data();
  const CloudMessage want = decode_cloud_message(message, "livox");
  ASSERT_EQ(want.loaded.cloud.size(), 3u);
  for (const char* type : {"livox_interfaces/msg/CustomMsg", "livox_ros_driver/msg/CustomMsg"}) {
    message.type = type;
    ASSERT_TRUE(is_cloud_message_type(type));
    const CloudMessage got = decode_cloud_message(message, type);
    EXPECT_EQ(got.loaded.cloud.x, want.loaded.cloud.x) << type;
    EXPECT_EQ(got.loaded.cloud.time, want.loaded.cloud.time) << type;
  }
}

TEST(McapBag, PointCloud2UnderALivoxNameIsRefusedNotDecodedAsGarbage) {
  auto [message, bytes] = first_message("points_zstd.mcap", "/points");
  message.data = bytes.data();
  message.type = "livox_ros_driver2/msg/CustomMsg";
  EXPECT_INPUT_ERROR(decode_cloud_message(message, "rec.mcap: /points message 0"),
                     "rec.mcap: /points message 0", "not a Livox CustomMsg layout");
}

// ---- damage ----

std::string fixture_bytes(const std::string& name) {
  return testing::file_bytes(data_dir() + "/" + name);
}

// Offsets of the records with `op` in the data section, walked as the specification lays it out
// (8 magic bytes, then op, uint64 length, content).
std::vector<std::size_t> records_with_op(const std::string& bytes, std::uint8_t op) {
  std::vector<std::size_t> found;
  for (std::size_t at = 8; at + 9 <= bytes.size();) {
    std::uint64_t length;
    std::memcpy(&length, bytes.data() + at + 1, 8);
    if (static_cast<std::uint8_t>(bytes[at]) == op) found.push_back(at);
    if (static_cast<std::uint8_t>(bytes[at]) == 0x0F) break;  // data end
    at += 9 + length;
  }
  return found;
}

void expect_one_line_about(const std::string& error, const std::string& path,
                           const std::string& problem) {
  EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
  EXPECT_NE(error.find(problem), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

class TruncatedMcapTest : public ::testing::TestWithParam<std::string> {};

TEST_P(TruncatedMcapTest, MessagesBeforeTheCutSurviveThenOneLineError) {
  const std::string whole = fixture_bytes(GetParam());
  const json& want = expected_files()[GetParam()]["messages"]["/points"];
  // The end of the data section's Data End record (op, length, 4-byte CRC).
  const std::vector<std::size_t> data_ends = records_with_op(whole, 0x0F);
  ASSERT_EQ(data_ends.size(), 1u);
  const std::size_t data_end = data_ends[0] + 9 + 4;
  testing::TempDir out;
  std::size_t previous = 0, partial_cuts = 0;
  for (const double fraction : {0.01, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.97, 0.995}) {
    const auto cut = static_cast<std::size_t>(static_cast<double>(whole.size()) * fraction);
    SCOPED_TRACE("cut at byte " + std::to_string(cut) + " of " + std::to_string(whole.size()));
    const std::string path = out.file("cut_" + std::to_string(cut) + ".mcap");
    testing::write_bytes(path, whole.substr(0, cut));
    std::unique_ptr<BagReader> bag;
    try {
      bag = open_bag(path);
    } catch (const InputError& e) {
      EXPECT_LT(cut, 60u) << "only a cut in the magic or header may stop the open: " << e.what();
      expect_one_line_about(e.what(), path, "");
      continue;
    }
    EXPECT_NE(bag->format().find("data scanned"), std::string::npos) << bag->format();
    std::string error;
    // Messages come out in log-time order; the file stores 3 before 2, so a cut between them
    // gives 0, 1, 3 from the scan. Compare by log time instead of position.
    std::size_t delivered = 0;
    try {
      bag->select("/points");  // fails when the cut comes before the channel's record
      BagMessage message;
      while (bag->next(message)) {
        const CloudMessage cloud = decode_cloud_message(message, path);
        bool known = false;
        for (const json& w : want)
          if (ns(w["log_time"]) == message.stamp_ns) {
            known = true;
            EXPECT_EQ(cloud.loaded.cloud.size(), w["points"].size());
          }
        EXPECT_TRUE(known) << message.stamp_ns;
        ++delivered;
      }
    } catch (const InputError& e) {
      error = e.what();
    }
    if (cut >= data_end) {
      // Only the summary is cut off: every message is there, and the scan finds them all.
      EXPECT_EQ(error, "");
      EXPECT_EQ(delivered, want.size());
    } else {
      // Whatever the cut, the damage is reported, never a silent short recording.
      EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
      EXPECT_TRUE(error.find("cut off") != std::string::npos ||
                  error.find("truncated") != std::string::npos)
          << error;
      EXPECT_EQ(error.find('\n'), std::string::npos);
    }
    EXPECT_GE(delivered, previous) << "a longer file gave fewer messages";
    previous = delivered;
    if (delivered > 0 && delivered < want.size()) ++partial_cuts;
  }
  EXPECT_GT(partial_cuts, 0u) << "no cut fell between messages: the test checks too little";
}

INSTANTIATE_TEST_SUITE_P(Layouts, TruncatedMcapTest,
                         ::testing::Values("points_zstd.mcap", "points_lz4.mcap",
                                           "points_uncompressed.mcap", "points_unchunked.mcap"),
                         [](const auto& info) {
                           return info.param.substr(0, info.param.find('.'));
                         });

// Flips bytes in the middle of the second chunk's records. The index is intact, so the other
// chunks still read; the damaged one gives a one-line error naming the chunk.
void expect_corrupt_second_chunk_reported(const std::string& name, const std::string& problem) {
  std::string bytes = fixture_bytes(name);
  const std::vector<std::size_t> chunks = records_with_op(bytes, 0x06);
  ASSERT_EQ(chunks.size(), 3u);
  const std::size_t middle = (chunks[1] + chunks[2]) / 2;
  for (std::size_t i = middle; i < middle + 8; ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  testing::TempDir out;
  const std::string path = out.file("corrupt.mcap");
  testing::write_bytes(path, bytes);
  const auto bag = open_bag(path);
  EXPECT_NE(bag->format().find("indexed"), std::string::npos);
  std::string error;
  const std::size_t delivered =
      read_topic(*bag, "/points", expected_files()[name]["messages"]["/points"], error);
  EXPECT_GT(delivered, 0u);
  EXPECT_LT(delivered, 5u);
  expect_one_line_about(error, path, "chunk at byte " + std::to_string(chunks[1]) + ": " + problem);
}

// The codec may or may not notice (these frames carry no checksum); the chunk's CRC does.
TEST(McapDamage, CorruptZstdChunk) { expect_corrupt_second_chunk_reported("points_zstd.mcap", ""); }
TEST(McapDamage, CorruptLz4Chunk) { expect_corrupt_second_chunk_reported("points_lz4.mcap", ""); }
// An uncompressed chunk has no codec to notice: its CRC does.
TEST(McapDamage, CorruptUncompressedChunkFailsItsCrc) {
  expect_corrupt_second_chunk_reported("points_uncompressed.mcap", "CRC");
}

TEST(McapDamage, BrokenSummaryFallsBackToReadingTheData) {
  std::string bytes = fixture_bytes("points_zstd.mcap");
  // Point the footer's summary start past the end of the file.
  const std::size_t footer = bytes.size() - 8 - 29;
  ASSERT_EQ(static_cast<std::uint8_t>(bytes[footer]), 0x02);
  const std::uint64_t beyond = bytes.size() * 2;
  std::memcpy(bytes.data() + footer + 9, &beyond, 8);
  testing::TempDir out;
  const std::string path = out.file("summary.mcap");
  testing::write_bytes(path, bytes);
  const auto bag = open_bag(path);
  EXPECT_NE(bag->format().find("data scanned"), std::string::npos) << bag->format();
  EXPECT_TRUE(bag->damage().empty()) << bag->damage();
  std::string error;
  EXPECT_EQ(read_topic(*bag, "/points", expected_files()["points_zstd.mcap"]["messages"]["/points"],
                       error),
            5u);
  EXPECT_EQ(error, "");
}

TEST(McapDamage, ChunkDeclaringMoreBytesThanItsDataIsReportedNotAllocated) {
  std::string bytes = fixture_bytes("points_zstd.mcap");
  const std::vector<std::size_t> chunks = records_with_op(bytes, 0x06);
  ASSERT_EQ(chunks.size(), 3u);
  // Content: start time, end time, then the uncompressed size.
  const std::uint64_t huge = std::uint64_t{1} << 40;
  std::memcpy(bytes.data() + chunks[0] + 9 + 16, &huge, 8);
  testing::TempDir out;
  const std::string path = out.file("size.mcap");
  testing::write_bytes(path, bytes);
  const auto bag = open_bag(path);
  std::string error;
  read_topic(*bag, "/points", expected_files()["points_zstd.mcap"]["messages"]["/points"], error);
  expect_one_line_about(error, path, "chunk at byte " + std::to_string(chunks[0]));
}

TEST(McapBag, WithoutATopicItsOnlyPointCloudTopicIsRead) {
  const std::string path = data_dir() + "/points_zstd.mcap";  // also holds /chatter
  const std::unique_ptr<FrameSource> chosen = open_frame_source(path, "");
  const std::unique_ptr<FrameSource> named = open_frame_source(path, "/points");
  EXPECT_EQ(chosen->name(), path + ":/points");
  EXPECT_EQ(chosen->total(), 5u);
  Frame a, b;
  std::size_t frames = 0;
  while (named->next(b)) {
    ASSERT_TRUE(chosen->next(a));
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(a.stamp_s, b.stamp_s);
    ASSERT_EQ(a.loaded.cloud.size(), b.loaded.cloud.size());
    for (std::size_t i = 0; i < a.loaded.cloud.size(); ++i)
      EXPECT_EQ(a.loaded.cloud.x[i], b.loaded.cloud.x[i]);
    ++frames;
  }
  EXPECT_FALSE(chosen->next(a));
  EXPECT_EQ(frames, 5u);
}

TEST(McapBag, WithoutAPointCloudTopicTheErrorListsTheTopics) {
  testing::TempDir out;
  // The fixture's PointCloud2 schema renamed to a type of the same length that no decoder takes.
  std::string bytes = fixture_bytes("points_unchunked.mcap");
  const std::string cloud = "sensor_msgs/msg/PointCloud2", other = "sensor_msgs/msg/PointCloud9";
  for (std::size_t at = bytes.find(cloud); at != std::string::npos; at = bytes.find(cloud, at + 1))
    bytes.replace(at, cloud.size(), other);
  const std::string path = out.file("no_clouds.mcap");
  testing::write_bytes(path, bytes);
  EXPECT_INPUT_ERROR(open_frame_source(path, ""), path,
                     "the bag has no point cloud topic (topics: /chatter [std_msgs/msg/String], "
                     "/points [sensor_msgs/msg/PointCloud9])");
}

TEST(McapDamage, ForeignFilesAndUnsupportedContent) {
  testing::TempDir out;
  const std::string not_mcap = out.file("cloud.mcap");
  testing::write_bytes(not_mcap, "# .PCD v0.7 - Point Cloud Data file format\n");
  EXPECT_INPUT_ERROR(open_bag(not_mcap), not_mcap, "not an MCAP file");

  std::string bytes = fixture_bytes("points_zstd.mcap");
  bytes[5] = '1';
  const std::string future = out.file("future.mcap");
  testing::write_bytes(future, bytes);
  EXPECT_INPUT_ERROR(open_bag(future), future, "MCAP major version '1' is not supported");

  // Messages in another encoding than CDR or ROS 1: refused when the topic is chosen.
  bytes = fixture_bytes("points_unchunked.mcap");
  const std::string cdr(
      "\x03\x00\x00\x00"
      "cdr",
      7),
      xml("\x03\x00\x00\x00"
          "xml",
          7);
  for (std::size_t at = bytes.find(cdr); at != std::string::npos; at = bytes.find(cdr, at + 1))
    bytes.replace(at, cdr.size(), xml);
  const std::string encoded = out.file("xml.mcap");
  testing::write_bytes(encoded, bytes);
  const auto bag = open_bag(encoded);
  EXPECT_INPUT_ERROR(bag->select("/points"), encoded,
                     "message encoding 'xml' (supported: cdr, ros1)");
  EXPECT_INPUT_ERROR(bag->select("/nothing"), encoded, "no topic '/nothing'");
}

}  // namespace
}  // namespace iilfm::io
