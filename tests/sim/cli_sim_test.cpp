// `iilfm sim` switches as users type them: the physics options, every sensor, bad values.
// Runs the built program; skipped when the test runs without it.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "iilfm/io/cloud_io.hpp"
#include "iilfm/sim/sim.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm::sim {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int status = -1;
  std::string out, err;
};

fs::path temp_dir() { return iilfm::testing::process_scratch_dir(); }

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CliRun run_sim(const std::string& args) {
  const fs::path out = temp_dir() / "stdout.txt", err = temp_dir() / "stderr.txt";
  const std::string command = std::string(IILFM_CLI_PATH) + " sim " + args + " >" + out.string() +
                              " 2>" + err.string() + " </dev/null";
  const int raw = std::system(command.c_str());
  CliRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

class SimCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(IILFM_CLI_PATH)) GTEST_SKIP() << "iilfm not built: " << IILFM_CLI_PATH;
  }
  std::string pcd(const std::string& name) { return (temp_dir() / (name + ".pcd")).string(); }
};

// Returns of the tag-wall marker (LiDAR 2 m in front, so the marker spans |y|, |z - 0| < 0.086).
std::vector<float> marker_intensities(const PointCloud& c) {
  std::vector<float> v;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (std::abs(c.y[i]) < 0.08 && std::abs(c.z[i]) < 0.08) v.push_back(c.intensity[i]);
  }
  return v;
}

int grey_count(const std::vector<float>& values) {
  int n = 0;
  for (float v : values) n += v > 10.5f && v < 119.5f;
  return n;
}

TEST_F(SimCli, HelpListsEverySensorAndScene) {
  const CliRun r = run_sim("--help");
  EXPECT_EQ(r.status, 0);
  for (const std::string& name : sensor_model_names()) {
    EXPECT_NE(r.out.find(name), std::string::npos) << name << "\n" << r.out;
  }
  for (const std::string& name : named_scene_names()) {
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
  }
  for (const char* flag : {"--footprint", "--dark-dropout", "--invalid-fraction", "--invalid-as",
                           "--min-range", "--footprint-samples"}) {
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  }
}

TEST_F(SimCli, FootprintMakesGreyEdgesAndDarkDropoutLosesBlackReturns) {
  const std::string quiet = "--frames 10 --range-sigma 0 --intensity-sigma 0 --out ";
  ASSERT_EQ(run_sim(quiet + pcd("sharp")).status, 0);
  ASSERT_EQ(run_sim("--footprint " + quiet + pcd("blurred")).status, 0);
  ASSERT_EQ(run_sim("--dark-dropout 1 " + quiet + pcd("dropped")).status, 0);
  const std::vector<float> sharp = marker_intensities(io::read_pcd(pcd("sharp")).cloud);
  const std::vector<float> blurred = marker_intensities(io::read_pcd(pcd("blurred")).cloud);
  const std::vector<float> dropped = marker_intensities(io::read_pcd(pcd("dropped")).cloud);
  ASSERT_EQ(sharp.size(), blurred.size());
  EXPECT_EQ(grey_count(sharp), 0);
  EXPECT_GT(grey_count(blurred), static_cast<int>(sharp.size() / 20));
  // Without the footprint a return is all black or all white: p = 1 drops every black one.
  int black = 0;
  for (float v : sharp) black += v < 11;
  EXPECT_GT(black, 300);
  EXPECT_EQ(dropped.size(), sharp.size() - black);
  for (float v : dropped) EXPECT_FLOAT_EQ(v, 120);
}

TEST_F(SimCli, InvalidPointsAreWrittenAsNanOrZero) {
  const std::string base = "--sensor vlp16 --invalid-fraction 0.25 --out ";
  ASSERT_EQ(run_sim(base + pcd("nan")).status, 0);
  ASSERT_EQ(run_sim("--invalid-as zero " + base + pcd("zero")).status, 0);
  const io::LoadedCloud nan = io::read_pcd(pcd("nan")), zero = io::read_pcd(pcd("zero"));
  // 16 x 1800 beams, a quarter of them invalid (binomial sigma ~ 73).
  EXPECT_NEAR(static_cast<double>(nan.stats.non_finite), 7200, 400);
  EXPECT_EQ(nan.stats.zero, 0u);
  EXPECT_EQ(zero.stats.zero, nan.stats.non_finite);  // same seed, same beams
  EXPECT_EQ(zero.stats.non_finite, 0u);
}

TEST_F(SimCli, MinRangeDropsCloseReturnsAndHidesTheMarker) {
  const fs::path truth = temp_dir() / "min_range.json";
  // The wall is 2 m ahead and 2.12 m at the cone's rim: 2.05 m cuts out its centre and the tag.
  ASSERT_EQ(run_sim("--frames 2 --min-range 2.05 --truth " + truth.string() + " --out " +
                    pcd("min_range"))
                .status,
            0);
  const PointCloud c = io::read_pcd(pcd("min_range")).cloud;
  ASSERT_GT(c.size(), 1000u);  // the wall's outer ring still returns
  ASSERT_LT(c.size(), 15000u);
  for (std::size_t i = 0; i < c.size(); ++i) ASSERT_GE(c.point(i).norm(), 2.05 - 1e-5);
  EXPECT_FALSE(read_ground_truth_json(truth.string()).markers.front().visible);
}

TEST_F(SimCli, EverySensorRuns) {
  for (const std::string& name : sensor_model_names()) {
    if (name == "os1-128") continue;  // 262k beams a sweep: covered by the library tests
    const CliRun r = run_sim("--sensor " + name + " --frames 1 --out " + pcd(name));
    EXPECT_EQ(r.status, 0) << name << ": " << r.err;
    EXPECT_NE(r.out.find(name), std::string::npos) << r.out;
  }
}

TEST_F(SimCli, BadPhysicsValuesExitWithStatus2AndNameTheSwitch) {
  const std::string out = " --out " + pcd("bad");
  for (const char* args : {"--dark-dropout 1.5", "--invalid-fraction -0.1", "--invalid-as inf",
                           "--min-range -1", "--footprint-samples 0", "--intensity-sigma -2"}) {
    const CliRun r = run_sim(args + out);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    const std::string flag = std::string(args).substr(0, std::string(args).find(' '));
    EXPECT_NE(r.err.find(flag), std::string::npos) << args << ": " << r.err;
  }
}

TEST_F(SimCli, SceneFileRunsTheShippedRoomAndRejectsNamedSceneSwitches) {
  const std::string room = std::string(IILFM_SOURCE_DIR) + "/data/scenes/room.yaml";
  const CliRun r = run_sim("--scene-file " + room + " --frames 2 --out " + pcd("room"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("avia"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("4/4 markers visible"), std::string::npos) << r.out;
  EXPECT_EQ(io::read_pcd(pcd("room")).cloud.size(), 48000u);  // a closed room: every beam returns

  const CliRun distance = run_sim("--scene-file " + room + " --distance 3 --out " + pcd("x"));
  EXPECT_EQ(distance.status, 2);
  EXPECT_NE(distance.err.find("--distance does not apply with --scene-file"), std::string::npos)
      << distance.err;
  const fs::path bad = temp_dir() / "bad_scene.yaml";
  std::ofstream(bad) << "lidar: {sensor: mid40}\nwalls: [{centre: [1, 2], width: 1, height: 1}]\n";
  const CliRun broken = run_sim("--scene-file " + bad.string() + " --out " + pcd("x"));
  EXPECT_EQ(broken.status, 2);
  EXPECT_NE(broken.err.find(bad.string() + ": walls[0]: 'centre' must be a list of 3 numbers"),
            std::string::npos)
      << broken.err;
}

TEST_F(SimCli, VelocitySwitchesSkewTheCloud) {
  // Driving at the tag wall at 5 m/s for 0.1 s: the last points read the wall 0.5 m closer.
  ASSERT_EQ(run_sim("--sensor vlp16 --range-sigma 0 --velocity 5 0 0 --angular-velocity 0 0 0 "
                    "--out " +
                    pcd("moving"))
                .status,
            0);
  const PointCloud c = io::read_pcd(pcd("moving")).cloud;
  int on_wall = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (std::abs(c.y[i]) > 0.5 || std::abs(c.z[i]) > 0.3) continue;  // the wall ahead
    EXPECT_NEAR(c.x[i], 2 - 5 * c.time[i], 1e-4) << i;
    ++on_wall;
  }
  EXPECT_GT(on_wall, 10);
  const CliRun bad = run_sim("--velocity 1 nan 0 --out " + pcd("x"));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--velocity"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace iilfm::sim
