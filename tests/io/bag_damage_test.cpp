// Damaged recordings: bags cut at many offsets and chunks with flipped bytes. Every message before
// the damage must come out intact, then a one-line InputError naming the file and the problem.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "bag_test_data.hpp"
#include "iilfm/io/bag.hpp"

namespace iilfm::io {
namespace {

using nlohmann::json;

// Messages of `topic` delivered before the reader stopped; `error` gets the InputError text ("" at
// a clean end). Each delivered message is checked against the expected points.
std::size_t read_until_damage(BagReader& bag, const std::string& topic, const json& expected,
                              std::string& error) {
  std::size_t delivered = 0;
  error.clear();
  try {
    bag.select(topic);
    BagMessage message;
    while (bag.next(message)) {
      const CloudMessage cloud = decode_cloud_message(message, bag.path());
      const json& want = expected[topic]["messages"][delivered];
      EXPECT_EQ(cloud.header_stamp_ns, want["header_stamp_ns"].get<std::int64_t>());
      EXPECT_EQ(cloud.loaded.cloud.size(), want["x"].size());
      if (cloud.loaded.cloud.size() == want["x"].size() && !want["x"].empty()) {
        EXPECT_EQ(cloud.loaded.cloud.x.back(), want["x"].back().get<double>());
      }
      ++delivered;
    }
  } catch (const InputError& e) {
    error = e.what();
  }
  return delivered;
}

// Where the third chunk record's "compression=" field starts in a bag's bytes (npos: none).
std::size_t third_chunk(const std::string& bytes, const std::string& compression) {
  std::size_t at = 0;
  for (int i = 0; i < 3; ++i) at = bytes.find("compression=" + compression, at + 1);
  return at;
}

// Reads every topic of the damaged bag at `path`; each error must be one line naming `path`, the
// chunk and `problem`. Returns how many topics stopped on an error; `delivered` counts messages.
std::size_t chunk_errors(BagReader& bag, const std::string& path, const json& expected,
                         const std::string& problem, std::size_t& delivered) {
  std::size_t errors = 0;
  for (const char* topic : {"/points_be", "/points_f64", "/points_padded", "/points_sparse"}) {
    std::string error;
    delivered += read_until_damage(bag, topic, expected, error);
    if (error.empty()) continue;
    ++errors;
    EXPECT_EQ(error.rfind(path + ": chunk at byte ", 0), 0u) << error;
    EXPECT_NE(error.find(problem), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos);
  }
  return errors;
}

class TruncatedBagTest : public ::testing::TestWithParam<std::string> {};

TEST_P(TruncatedBagTest, FramesBeforeTheCutSurviveThenOneLineError) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  const json expected = testing::load_json(dir + "/expected.json");
  const std::string whole = testing::file_bytes(dir + "/clouds_" + GetParam() + ".bag");
  testing::TempDir out;
  const std::string topic = "/points_padded";
  std::size_t previous = 0, partial_cuts = 0;
  for (const double fraction : {0.001, 0.01, 0.15, 0.3, 0.45, 0.6, 0.75, 0.9, 0.97, 0.995}) {
    const std::size_t cut = static_cast<std::size_t>(whole.size() * fraction);
    SCOPED_TRACE("cut at byte " + std::to_string(cut) + " of " + std::to_string(whole.size()));
    const std::string path = out.file("cut_" + std::to_string(cut) + ".bag");
    testing::write_bytes(path, whole.substr(0, cut));
    std::unique_ptr<BagReader> bag;
    try {
      bag = open_bag(path);
    } catch (const InputError& e) {
      // Only a cut inside the bag header may stop the reader from opening.
      EXPECT_LT(cut, 4200u);
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos);
      continue;
    }
    EXPECT_NE(bag->format().find("index missing or damaged"), std::string::npos);
    std::string error;
    const std::size_t delivered = read_until_damage(*bag, topic, expected, error);
    // Whatever the cut, the damage is reported, never a silent short recording.
    EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
    EXPECT_TRUE(error.find("cut off") != std::string::npos ||
                error.find("truncated") != std::string::npos ||
                error.find("ends early") != std::string::npos)
        << error;
    EXPECT_EQ(error.find('\n'), std::string::npos);
    EXPECT_GE(delivered, previous) << "a longer file gave fewer messages";
    previous = delivered;
    if (delivered > 0 && delivered < 3) ++partial_cuts;
  }
  EXPECT_GT(partial_cuts, 0u) << "no cut fell between messages: the test checks too little";
}

INSTANTIATE_TEST_SUITE_P(Compressions, TruncatedBagTest, ::testing::Values("none", "bz2", "lz4"));

class CorruptChunkTest : public ::testing::TestWithParam<std::string> {};

TEST_P(CorruptChunkTest, FlippedBytesInACompressedChunkAreReported) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  const json expected = testing::load_json(dir + "/expected.json");
  std::string bytes = testing::file_bytes(dir + "/clouds_" + GetParam() + ".bag");
  // The third chunk record: its compressed data starts a few dozen bytes after this field.
  const std::size_t at = third_chunk(bytes, GetParam());
  ASSERT_NE(at, std::string::npos);
  for (std::size_t i = at + 200; i < at + 216; ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  testing::TempDir out;
  const std::string path = out.file("corrupt.bag");
  testing::write_bytes(path, bytes);

  const auto bag = open_bag(path);  // the index is intact
  std::size_t delivered = 0;
  EXPECT_GT(chunk_errors(*bag, path, expected, "corrupt", delivered), 0u);
  EXPECT_GT(delivered, 0u);  // the other chunks still read
}

INSTANTIATE_TEST_SUITE_P(Compressions, CorruptChunkTest, ::testing::Values("bz2", "lz4"));

// A chunk header's uncompressed size is a number from the file: a damaged one (found by fuzzing: it
// declared gigabytes) must give a one-line error, not an allocation of that size.
class ChunkSizeTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ChunkSizeTest, DeclaredSizeThatTheDataDoesNotMatchIsReported) {
  SKIP_WITHOUT_ROS_PYTHON();
  const std::string dir = testing::test_bags_dir();
  const json expected = testing::load_json(dir + "/expected.json");
  const std::string original = testing::file_bytes(dir + "/clouds_" + GetParam() + ".bag");
  const std::size_t at = third_chunk(original, GetParam());
  ASSERT_NE(at, std::string::npos);
  const std::size_t size_field = original.find("size=", at);
  ASSERT_LT(size_field, at + 64);
  std::uint32_t declared = 0;
  std::memcpy(&declared, original.data() + size_field + 5, sizeof declared);
  for (const std::uint32_t wrong : {0xf0000000u, declared + 1000u, declared - 1000u}) {
    SCOPED_TRACE("declared " + std::to_string(wrong) + " instead of " + std::to_string(declared));
    std::string bytes = original;
    std::memcpy(bytes.data() + size_field + 5, &wrong, sizeof wrong);
    testing::TempDir out;
    const std::string path = out.file("size.bag");
    testing::write_bytes(path, bytes);
    const auto bag = open_bag(path);
    std::size_t delivered = 0;
    EXPECT_GT(
        chunk_errors(*bag, path, expected, std::to_string(wrong) + " bytes declared", delivered),
        0u);
  }
}

INSTANTIATE_TEST_SUITE_P(Compressions, ChunkSizeTest, ::testing::Values("bz2", "lz4"));

}  // namespace
}  // namespace iilfm::io

namespace iilfm::io {
namespace {

// A connection header whose field length runs past the record (found by fuzzing): damage, not a
// crash.
TEST(BagDamage, ConnectionFieldLengthPastItsRecord) {
  SKIP_WITHOUT_ROS_PYTHON();
  std::string bytes = testing::file_bytes(testing::test_bags_dir() + "/clouds_none.bag");
  std::size_t at = 0, changed = 0;
  while ((at = bytes.find("md5sum=", at + 1)) != std::string::npos) {
    const std::uint32_t huge = 0xfffff000u;
    std::memcpy(&bytes[at - 4], &huge, 4);
    ++changed;
  }
  ASSERT_GT(changed, 0u);
  testing::TempDir out;
  const std::string path = out.file("bad_connection.bag");
  testing::write_bytes(path, bytes);
  std::unique_ptr<BagReader> bag;
  ASSERT_NO_THROW(bag = open_bag(path));
  EXPECT_NE(bag->damage().find("header field runs past its header"), std::string::npos)
      << bag->damage();
  EXPECT_INPUT_ERROR(bag->select("/points_padded"), path, "runs past");
}

}  // namespace
}  // namespace iilfm::io
