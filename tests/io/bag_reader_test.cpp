// The bag readers against recordings written by the real ROS 1 writer (uncompressed, bz2, lz4),
// Livox CustomMsg bags, and a ROS 2 sqlite3 bag: every point as written, stamps, topic listings,
// and the errors for wrong topics and non-cloud types.
#include <gtest/gtest.h>

#include <cmath>

#include "bag_test_data.hpp"
#include "iilfm/io/bag.hpp"
#include "iilfm/io/frame_source.hpp"

namespace iilfm::io {
namespace {

using nlohmann::json;

// Compares a decoded message with the script's record of it, value by value (exact).
void expect_same_cloud(const CloudMessage& got, const json& want, const std::string& what) {
  SCOPED_TRACE(what);
  const PointCloud& c = got.loaded.cloud;
  const CloudStats& s = got.loaded.stats;
  EXPECT_EQ(s.points_in_file, want["points_in_file"].get<std::size_t>());
  EXPECT_EQ(s.non_finite, want["non_finite"].get<std::size_t>());
  EXPECT_EQ(s.zero, want["zero"].get<std::size_t>());
  ASSERT_EQ(c.size(), want["x"].size());
  EXPECT_EQ(s.valid_points, c.size());
  EXPECT_EQ(got.header_stamp_ns, want["header_stamp_ns"].get<std::int64_t>());
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_EQ(c.x[i], want["x"][i].get<double>()) << "point " << i;
    EXPECT_EQ(c.y[i], want["y"][i].get<double>()) << "point " << i;
    EXPECT_EQ(c.z[i], want["z"][i].get<double>()) << "point " << i;
    EXPECT_EQ(c.intensity[i], want["intensity"][i].get<double>()) << "point " << i;
  }
  if (want["ring"].is_null()) {
    EXPECT_FALSE(c.has_ring());
  } else {
    ASSERT_EQ(c.ring.size(), c.size());
    for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(c.ring[i], want["ring"][i].get<int>());
  }
  if (want["time"].is_null()) {
    EXPECT_FALSE(c.has_time());
  } else {
    ASSERT_EQ(c.time.size(), c.size());
    for (std::size_t i = 0; i < c.size(); ++i)
      EXPECT_EQ(c.time[i], want["time"][i].get<double>()) << "point " << i;
  }
}

// Reads every point-cloud topic of `bag_path` and compares it with `expected`.
void expect_bag_matches(const std::string& bag_path, const json& expected) {
  const auto bag = open_bag(bag_path);
  EXPECT_TRUE(bag->damage().empty()) << bag->damage();
  std::size_t compared = 0;
  for (const auto& [topic, info] : expected.items()) {
    const auto listed = std::find_if(bag->topics().begin(), bag->topics().end(),
                                     [&](const BagTopic& t) { return t.name == topic; });
    ASSERT_NE(listed, bag->topics().end()) << topic;
    EXPECT_EQ(listed->type, info["type"].get<std::string>());
    EXPECT_EQ(listed->messages, info["messages"].size());
    if (!is_cloud_message_type(listed->type)) continue;
    EXPECT_EQ(listed->first_ns, info["messages"].front()["stamp_ns"].get<std::int64_t>());
    EXPECT_EQ(listed->last_ns, info["messages"].back()["stamp_ns"].get<std::int64_t>());
    bag->select(topic);
    BagMessage message;
    for (const json& want : info["messages"]) {
      ASSERT_TRUE(bag->next(message)) << topic;
      EXPECT_EQ(message.stamp_ns, want["stamp_ns"].get<std::int64_t>());
      expect_same_cloud(decode_cloud_message(message, bag_path + " " + topic), want,
                        bag_path + " " + topic);
      ++compared;
    }
    EXPECT_FALSE(bag->next(message)) << topic << ": more messages than written";
  }
  EXPECT_GT(compared, 0u);
}

class Ros1BagTest : public ::testing::TestWithParam<std::string> {};

TEST_P(Ros1BagTest, EveryLayoutReadsBackExactly) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  const json expected = testing::load_json(dir + "/expected.json");
  json clouds = json::object();
  for (const auto& [topic, info] : expected.items())
    if (topic.rfind("/points", 0) == 0 || topic == "/chatter") clouds[topic] = info;
  expect_bag_matches(dir + "/clouds_" + GetParam() + ".bag", clouds);
}

INSTANTIATE_TEST_SUITE_P(Compressions, Ros1BagTest, ::testing::Values("none", "bz2", "lz4"));

TEST(Ros1Bag, FormatNamesTheChunkCompression) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  EXPECT_NE(open_bag(dir + "/clouds_bz2.bag")->format().find("(bz2), indexed"), std::string::npos);
  EXPECT_NE(open_bag(dir + "/clouds_lz4.bag")->format().find("(lz4), indexed"), std::string::npos);
}

TEST(Ros1Bag, LivoxCustomMessagesBothDrivers) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  const json expected = testing::load_json(dir + "/expected.json");
  json livox = json::object();
  for (const char* topic : {"/livox/lidar", "/livox2"}) livox[topic] = expected[topic];
  expect_bag_matches(dir + "/livox.bag", livox);
}

TEST(Ros2Bag, SqliteFolderAndSingleFileReadBackExactly) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  const json expected = testing::load_json(dir + "/expected_ros2.json");
  expect_bag_matches(dir + "/ros2_bag", expected);
  expect_bag_matches(dir + "/ros2_bag/ros2_bag_0.db3", expected);
}

TEST(BagErrors, WrongTopicListsTheTopicsThatExist) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  for (const std::string& path : {dir + "/clouds_lz4.bag", dir + "/ros2_bag"}) {
    const auto bag = open_bag(path);
    EXPECT_INPUT_ERROR(bag->select("/velodyne_points"), path, "no topic '/velodyne_points'");
    EXPECT_INPUT_ERROR(bag->select("/velodyne_points"), path, "/points_padded [sensor_msgs/");
  }
}

TEST(BagErrors, TopicThatIsNotAPointCloud) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string path = testing::test_bags_dir() + "/clouds_none.bag";
  EXPECT_INPUT_ERROR(open_frame_source(path, "/chatter"), path,
                     "topic /chatter has type std_msgs/String, not a point cloud");
  const auto bag = open_bag(path);
  bag->select("/chatter");
  BagMessage message;
  ASSERT_TRUE(bag->next(message));
  EXPECT_INPUT_ERROR(decode_cloud_message(message, path + ": /chatter"), path,
                     "std_msgs/String is not a point cloud");
}

TEST(BagErrors, BagWithSeveralCloudTopicsAndNoTopicNamesThem) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string path = testing::test_bags_dir() + "/livox.bag";
  EXPECT_INPUT_ERROR(open_frame_source(path, ""), path,
                     "the bag has several point cloud topics: choose one with --topic "
                     "(/livox/lidar, /livox2)");
}

TEST(BagErrors, NotABag) {
  testing::TempDir dir;
  const std::string path = dir.file("scan.bag");
  testing::write_bytes(path, "# .PCD v0.7\n");
  EXPECT_INPUT_ERROR(open_bag(path), path, "not a ROS 1 bag");
  const std::string db = dir.file("scan.db3");
  testing::write_bytes(db, std::string(4096, 'x'));
  EXPECT_INPUT_ERROR(open_bag(db), db, "not a ROS 2 sqlite3 bag");
}

TEST(BagFrames, StampsComeFromTheMessageHeader) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  const json expected = testing::load_json(dir + "/expected.json");
  const auto source = open_frame_source(dir + "/clouds_bz2.bag", "/points_f64");
  EXPECT_EQ(source->total(), 3u);
  Frame frame;
  for (std::size_t i = 0; i < 3; ++i) {
    ASSERT_TRUE(source->next(frame));
    EXPECT_EQ(frame.index, i);
    const auto ns = expected["/points_f64"]["messages"][i]["header_stamp_ns"].get<std::int64_t>();
    EXPECT_NEAR(frame.stamp_s, ns * 1e-9, 1e-6);
    EXPECT_EQ(frame.loaded.cloud.size(), expected["/points_f64"]["messages"][i]["x"].size());
  }
  EXPECT_FALSE(source->next(frame));
}

}  // namespace
}  // namespace iilfm::io
