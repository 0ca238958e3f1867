// The `iilfm` program as users run it: sim -> detect -> JSON, and one-line errors with exit 2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_run.hpp"
#include "iilfm/io/cloud_io.hpp"

namespace {

namespace fs = std::filesystem;

using iilfm::testing::cli_temp_dir;
using iilfm::testing::CliRun;
using iilfm::testing::run_cli;
using iilfm::testing::slurp;

// Bad input: exit 2, exactly one line on stderr that names `needle`, nothing on stdout.
void expect_input_error(const std::string& args, const std::string& needle) {
  const CliRun r = run_cli(args);
  EXPECT_EQ(r.status, 2) << args << "\n" << r.err;
  ASSERT_FALSE(r.err.empty()) << args;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line expected: " << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << args << ": " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(Cli, SimThenDetectWritesTheContractJson) {
  const fs::path d = cli_temp_dir();
  const std::string pcd = (d / "scan.pcd").string(), map = (d / "map.yaml").string(),
                    truth = (d / "truth.json").string(), json = (d / "out.json").string(),
                    png = (d / "out.png").string();
  ASSERT_EQ(run_cli("sim --scene tag-wall --frames 40 --seed 4 --out " + pcd + " --map " + map +
                    " --truth " + truth)
                .status,
            0);
  const CliRun r = run_cli("detect " + pcd + " --sensor mid40 --map " + map + " --json " + json +
                           " --image " + png);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("apriltag:tag36h11 id 0"), std::string::npos) << r.out;
  EXPECT_GT(fs::file_size(png), 1000u);

  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  const nlohmann::json t = nlohmann::json::parse(slurp(truth));
  EXPECT_EQ(j["input"]["points"], 400000);
  EXPECT_EQ(j["image"]["res_h_deg"], 0.05);
  ASSERT_EQ(j["markers"].size(), 1u);
  const auto& m = j["markers"][0];
  EXPECT_EQ(m["family"], "apriltag:tag36h11");
  EXPECT_EQ(m["id"], 0);
  ASSERT_EQ(m["corners_px"].size(), 4u);
  ASSERT_EQ(m["observed"].size(), 4u);
  ASSERT_TRUE(m["T_lidar_marker"].is_array());
  for (int k = 0; k < 4; ++k) {
    double err2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double e = m["corners_lidar"][k][a].get<double>() -
                       t["markers"][0]["corners_lidar"][k][a].get<double>();
      err2 += e * e;
    }
    EXPECT_LT(std::sqrt(err2), 0.01) << "corner " << k;
  }
  ASSERT_TRUE(j["pose"].is_object());
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(j["pose"]["xyz"][a].get<double>(), t["T_world_lidar"][a][3].get<double>(), 0.03);
  EXPECT_EQ(j["pose"]["quat_xyzw"].size(), 4u);
  EXPECT_EQ(j["pose"]["markers_used"][0], "apriltag:tag36h11/0");
  // Uncertainty: 6x6 covariance, symmetric, positive variances, and the stds it gives.
  const auto& cov = j["pose"]["covariance"];
  ASSERT_EQ(cov.size(), 6u);
  for (int r = 0; r < 6; ++r) {
    ASSERT_EQ(cov[r].size(), 6u);
    EXPECT_GT(cov[r][r].get<double>(), 0) << r;
    for (int c = 0; c < 6; ++c)
      EXPECT_NEAR(cov[r][c].get<double>(), cov[c][r].get<double>(),
                  1e-3 * std::abs(cov[r][c].get<double>()));
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(j["pose"]["std_xyz_m"][a].get<double>(), std::sqrt(cov[3 + a][3 + a].get<double>()),
                1e-6);
    // A 17 cm tag at 2 m: millimetres and tenths of a degree, not metres or nothing.
    EXPECT_GT(j["pose"]["std_xyz_m"][a].get<double>(), 1e-5);
    EXPECT_LT(j["pose"]["std_xyz_m"][a].get<double>(), 0.02);
    EXPECT_LT(j["pose"]["std_rpy_deg"][a].get<double>(), 1.0);
  }
  EXPECT_EQ(m["covariance"].size(), 6u);
  EXPECT_EQ(m["std_xyz_m"].size(), 3u);
  EXPECT_EQ(m["std_rpy_deg"].size(), 3u);
  EXPECT_FALSE(j.contains("pose_rejected"));
  for (const char* stage : {"read", "project", "preprocess", "detect", "lift", "pose", "total"})
    EXPECT_TRUE(j["timing_ms"].contains(stage)) << stage;
}

// No preset and no resolution: estimated from the cloud, said on stdout and in the JSON.
TEST(Cli, DetectWithoutASensorEstimatesTheResolution) {
  const fs::path d = cli_temp_dir();
  const std::string pcd = (d / "auto.pcd").string(), map = (d / "auto.yaml").string(),
                    json = (d / "auto.json").string();
  ASSERT_EQ(run_cli("sim --scene ccw10m --sensor ultrapuck --out " + pcd + " --map " + map).status,
            0);
  const CliRun r =
      run_cli("detect " + pcd + " --marker apriltag:tag16h5 --map " + map + " --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("resolution estimated from the cloud (ring field)"), std::string::npos)
      << r.out;
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["image"]["resolution"], "estimated (ring field)");
  EXPECT_EQ(j["image"]["rows"], "ring field");
  EXPECT_NEAR(j["image"]["res_h_deg"].get<double>(), 0.2, 0.02);
  ASSERT_EQ(j["markers"].size(), 1u);
  ASSERT_TRUE(j["pose"].is_object());
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(j["pose"]["xyz"][a].get<double>(), 0.0, 0.1);
}

TEST(Cli, IntensityOffThePresetsScaleOrMissingIsHandledAndSaid) {
  // A VLP-16 sweep written as a KITTI .bin with its intensity scaled to 0..1, as KITTI's own files
  // hold reflectance: the preset's threshold of 40 would leave no pixel white.
  const fs::path d = cli_temp_dir();
  const std::string pcd = (d / "unit.pcd").string(), bin = (d / "unit.bin").string(),
                    map = (d / "unit.yaml").string(), json = (d / "unit.json").string();
  ASSERT_EQ(run_cli("sim --scene tag-wall --sensor vlp16 --marker-size 0.6 --distance 2 --out " +
                    pcd + " --map " + map)
                .status,
            0);
  const iilfm::PointCloud cloud = iilfm::io::read_cloud(pcd).cloud;
  std::ofstream out(bin, std::ios::binary);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const float record[4] = {cloud.x[i], cloud.y[i], cloud.z[i], cloud.intensity[i] / 255.0f};
    out.write(reinterpret_cast<const char*>(record), sizeof record);
  }
  out.close();

  CliRun r = run_cli("detect " + bin + " --sensor vlp16 --map " + map + " --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("note: the threshold 40 lies above every intensity"), std::string::npos)
      << r.out;
  nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["image"]["threshold_replaced"]["given"], 40.0);
  EXPECT_LT(j["image"]["threshold_replaced"]["max_intensity"].get<double>(), 1.0);
  EXPECT_LT(j["image"]["threshold"].get<double>(), 1.0);
  ASSERT_EQ(j["markers"].size(), 1u);
  EXPECT_TRUE(j["pose"].is_object());

  // The user's own number is kept, with a warning.
  r = run_cli("detect " + bin + " --sensor vlp16 --threshold 40 --map " + map + " --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("warning: the threshold 40 lies above every intensity"), std::string::npos)
      << r.out;
  j = nlohmann::json::parse(slurp(json));
  EXPECT_FALSE(j["image"].contains("threshold_replaced"));
  EXPECT_EQ(j["markers"].size(), 0u);

  // Without intensity (every value 0): a warning, not a replaced threshold.
  const std::string dark = (d / "dark.bin").string();
  std::ofstream dark_out(dark, std::ios::binary);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const float record[4] = {cloud.x[i], cloud.y[i], cloud.z[i], 0.0f};
    dark_out.write(reinterpret_cast<const char*>(record), sizeof record);
  }
  dark_out.close();
  r = run_cli("detect " + dark + " --sensor vlp16 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("warning: every point's intensity is 0"), std::string::npos) << r.out;
  j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["image"]["no_intensity"], true);
  EXPECT_FALSE(j["image"].contains("threshold_replaced"));

  // A folder of such scans: every line says so, and the summary counts them.
  const fs::path folder = d / "unit_frames";
  fs::create_directories(folder);
  for (const char* name : {"000000.bin", "000001.bin"}) fs::copy_file(bin, folder / name);
  const std::string jsonl = (d / "unit.jsonl").string();
  r = run_cli("detect " + folder.string() + " --sensor vlp16 --map " + map + " --jsonl " + jsonl);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("note: in 2 result(s) the threshold 40 lay above every intensity"),
            std::string::npos)
      << r.out;
  std::istringstream lines(slurp(jsonl));
  int replaced = 0;
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json frame = nlohmann::json::parse(line);
    replaced += frame["image"].contains("threshold_replaced") && frame["markers"].size() == 1;
  }
  EXPECT_EQ(replaced, 2);
}

TEST(Cli, PrintAboveThePresetsThresholdIsFoundAtOtsusAndSaid) {
  // Ink returning 60 and paper 200 (a print both of whose returns lie above the VLP-16 preset's
  // 40): nothing at 40, the marker at Otsu's threshold.
  const fs::path d = cli_temp_dir();
  const std::string scene = (d / "bright_ink.yaml").string(), pcd = (d / "bright.pcd").string(),
                    map = (d / "bright_map.yaml").string(), json = (d / "bright.json").string();
  std::ofstream(scene) << "lidar: {sensor: vlp16}\n"
                          "print: {white: 200, black: 60}\n"
                          "walls:\n"
                          "  - {centre: [2, 0, 0], rpy_deg: [90, 0, -90], width: 6, height: 3}\n"
                          "markers:\n"
                          "  - {family: apriltag:tag36h11, id: 3, size: 0.6, on_wall: 0, "
                          "at: [0, 0.2]}\n";
  ASSERT_EQ(run_cli("sim --scene-file " + scene + " --out " + pcd + " --map " + map).status, 0);
  CliRun r = run_cli("detect " + pcd + " --sensor vlp16 --map " + map + " --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("note: the sensor preset's threshold 40 found no marker; Otsu's threshold"),
            std::string::npos)
      << r.out;
  nlohmann::json j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j["markers"].size(), 1u);
  EXPECT_EQ(j["markers"][0]["id"], 3);
  EXPECT_TRUE(j["pose"].is_object());
  EXPECT_EQ(j["image"]["threshold_retry"]["fixed"], 40.0);
  EXPECT_EQ(j["image"]["threshold_retry"]["found"], 1);
  EXPECT_EQ(j["image"]["threshold_retry"]["otsu"], j["image"]["threshold"]);

  // The user's own 40 is kept: no marker, no retry.
  r = run_cli("detect " + pcd + " --sensor vlp16 --threshold 40 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["markers"].size(), 0u);
  EXPECT_FALSE(j["image"].contains("threshold_retry"));

  // A folder of such scans: the summary counts them.
  const fs::path folder = d / "bright_frames";
  fs::create_directories(folder);
  for (const char* name : {"000000.pcd", "000001.pcd"}) fs::copy_file(pcd, folder / name);
  r = run_cli("detect " + folder.string() + " --sensor vlp16 --map " + map + " --jsonl " +
              (d / "bright.jsonl").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("note: in 2 result(s) the sensor preset's threshold 40 found no marker"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("markers in 2, LiDAR pose in 2"), std::string::npos) << r.out;
}

TEST(Cli, IdsReportOnlyTheMarkersGiven) {
  const fs::path d = cli_temp_dir();
  const std::string pcd = (d / "ids.pcd").string(), json = (d / "ids.json").string();
  ASSERT_EQ(run_cli("sim --scene tag-wall --frames 20 --out " + pcd).status, 0);  // tag36h11 id 0
  CliRun r = run_cli("detect " + pcd + " --sensor mid40 --ids 0,5-7 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["markers"].size(), 1u);
  EXPECT_FALSE(j.contains("markers_not_reported"));
  r = run_cli("detect " + pcd + " --sensor mid40 --ids 1-3,7 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["markers"].size(), 0u);
  EXPECT_EQ(j.value("markers_not_reported", 0), 1);
  EXPECT_NE(r.out.find("0 marker(s) (and 1 of ids not given with --ids, not reported)"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(j["image"].contains("threshold_retry"));
  expect_input_error("detect " + pcd + " --sensor mid40 --ids 3-1", "--ids");
  expect_input_error("detect " + pcd + " --sensor mid40 --ids 0,,2", "--ids");
  expect_input_error("detect " + pcd + " --sensor mid40 --ids zero", "--ids");
  expect_input_error("detect " + pcd + " --sensor mid40 --ids 587",
                     "marker id 587 is not in apriltag:tag36h11 (ids 0..586)");
}

TEST(Cli, SpinningPresetTakesTheColumnsOfTheCloudsMode) {
  // The simulated OS1-128 runs 2048 columns, its preset assumes 1024 (the sensor's default mode).
  // A 40 cm tag at 7 m: found in the cloud's 2048 columns, lost when they are merged in pairs.
  const fs::path d = cli_temp_dir();
  const std::string pcd = (d / "os2048.pcd").string(), json = (d / "os2048.json").string();
  ASSERT_EQ(run_cli("sim --scene tag-wall --sensor os1-128 --marker-size 0.4 --distance 7 --seed 4 "
                    "--footprint --lidar-rpy 0 0.801243 -1.309219 --out " +
                    pcd)
                .status,
            0);
  const CliRun r = run_cli("detect " + pcd + " --sensor os1-128 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("columns from the cloud: 2048"), std::string::npos) << r.out;
  nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["image"]["resolution"], "preset os1-128, columns from the cloud (2048)");
  EXPECT_DOUBLE_EQ(j["image"]["res_h_deg"].get<double>(), 360.0 / 2048);
  ASSERT_EQ(j["markers"].size(), 1u);
  EXPECT_EQ(j["markers"][0]["id"], 0);

  const CliRun given =
      run_cli("detect " + pcd + " --sensor os1-128 --res-h 0.3515625 --json " + json);
  ASSERT_EQ(given.status, 0) << given.err;
  EXPECT_EQ(given.out.find("columns from the cloud"), std::string::npos) << given.out;
  j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["image"]["resolution"], "preset os1-128");
  EXPECT_TRUE(j["markers"].empty());
}

TEST(Cli, NoMapMeansPoseNullWithAReason) {
  const fs::path d = cli_temp_dir();
  const std::string pcd = (d / "nomap.pcd").string(), json = (d / "nomap.json").string();
  ASSERT_EQ(run_cli("sim --scene tag-wall --frames 20 --out " + pcd).status, 0);
  ASSERT_EQ(run_cli("detect " + pcd + " --sensor mid40 -q --json " + json).status, 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_TRUE(j["pose"].is_null());
  EXPECT_EQ(j["pose_missing_reason"], "no marker map given");
  EXPECT_TRUE(j["markers"][0]["T_lidar_marker"].is_null());  // size unknown without map or flag
}

// A pose that misses the configured quality is refused: pose null and the reason, never a pose
// that cannot be backed.
TEST(Cli, PoseOverTheResidualBoundIsRefused) {
  const fs::path d = cli_temp_dir();
  const std::string pcd = (d / "strict.pcd").string(), map = (d / "strict.yaml").string(),
                    json = (d / "strict.json").string();
  ASSERT_EQ(
      run_cli("sim --scene tag-wall --frames 20 --seed 2 --out " + pcd + " --map " + map).status,
      0);
  CliRun r = run_cli("detect " + pcd + " --sensor mid40 --map " + map +
                     " --max-pose-rms 0.000001 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("LiDAR pose: refused (corner RMS residual"), std::string::npos) << r.out;
  nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_TRUE(j["pose"].is_null());
  const std::string reason = j["pose_rejected"]["reason"];
  EXPECT_NE(reason.find("exceeds the bound 0.001 mm"), std::string::npos) << reason;
  EXPECT_EQ(j["pose_missing_reason"], reason);
  ASSERT_EQ(j["markers"].size(), 1u);  // the detection itself is still reported

  r = run_cli("detect " + pcd + " --sensor mid40 --map " + map +
              " --min-pose-corners 5 -q --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(slurp(json));
  EXPECT_TRUE(j["pose"].is_null());
  EXPECT_NE(j["pose_rejected"]["reason"].get<std::string>().find("need 5"), std::string::npos);
  expect_input_error("detect " + pcd + " --sensor mid40 --max-pose-rms -1", "--max-pose-rms");

  // The refinement with the plane points: one marker, the same pose within a millimetre.
  r = run_cli("detect " + pcd + " --sensor mid40 --map " + map + " -q --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json kabsch = nlohmann::json::parse(slurp(json));
  r = run_cli("detect " + pcd + " --sensor mid40 --map " + map +
              " --pose-refine points -q --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(slurp(json));
  ASSERT_FALSE(j["pose"].is_null());
  ASSERT_FALSE(kabsch["pose"].is_null());
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(j["pose"]["xyz"][a].get<double>(), kabsch["pose"]["xyz"][a].get<double>(), 0.001);
  expect_input_error("detect " + pcd + " --sensor mid40 --map " + map + " --pose-refine best",
                     "--pose-refine must be none or points, got 'best'");
}

TEST(Cli, BadInputGivesOneLineAndExitTwo) {
  const fs::path d = cli_temp_dir();
  expect_input_error("detect /nonexistent/scan.pcd --sensor mid40", "/nonexistent/scan.pcd");

  const fs::path truncated = d / "truncated.pcd";
  std::ofstream(truncated) << "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
                              "COUNT 1 1 1 1\nWIDTH 100\nHEIGHT 1\nPOINTS 100\nDATA binary\nabc";
  expect_input_error("detect " + truncated.string() + " --sensor mid40", truncated.string());

  const fs::path garbage = d / "garbage.pcd";
  std::ofstream(garbage) << "this is not a point cloud\n";
  expect_input_error("detect " + garbage.string() + " --sensor mid40", garbage.string());

  const fs::path empty = d / "empty.pcd";
  std::ofstream(empty) << "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
                          "COUNT 1 1 1 1\nWIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA ascii\n";
  expect_input_error("detect " + empty.string() + " --sensor mid40", "no valid points");

  const fs::path nans = d / "nans.pcd";
  std::ofstream(nans) << "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
                         "COUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n"
                         "nan nan nan 1\n0 0 0 5\n";
  expect_input_error("detect " + nans.string() + " --sensor mid40", "1 non-finite, 1 zero");

  const std::string good = (d / "good.pcd").string();
  ASSERT_EQ(run_cli("sim --scene tag-wall --frames 5 --out " + good).status, 0);
  expect_input_error("detect " + good + " --sensor mid40 --marker apriltag:tag99h9", "tag99h9");
  expect_input_error("detect " + good + " --sensor mid40 --marker tag36h11", "apriltag:tag36h11");
  expect_input_error("detect " + good + " --sensor nosuch", "unknown sensor preset 'nosuch'");
  const fs::path tiny = d / "tiny.pcd";
  std::ofstream(tiny)
      << "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
         "COUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 0 0 5\n1 1 0 5\n";
  expect_input_error("detect " + tiny.string(), tiny.string() + ": too few points");
  expect_input_error("detect " + good + " --sensor mid40 --threshold abc", "--threshold");
  expect_input_error("detect " + good + " --sensor mid40 --lift magic", "--lift");

  const fs::path bad_map = d / "bad_map.yaml";
  std::ofstream(bad_map) << "markers:\n  - {family: apriltag:tag36h11, id: 2, corners: "
                            "[[0,0,0],[1,0,0],[1,1,0]]}\n";
  expect_input_error("detect " + good + " --sensor mid40 --map " + bad_map.string(), "marker #1");
  expect_input_error("detect " + good + " --sensor mid40 --no-such-flag", "--no-such-flag");
  expect_input_error("sim --sensor nosuch --out " + (d / "x.pcd").string(), "nosuch");
}

TEST(Cli, SensorsListsThePresets) {
  const CliRun r = run_cli("sensors");
  EXPECT_EQ(r.status, 0);
  for (const char* name : {"mid40", "vlp16", "vlp32c", "ultrapuck"})
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
  // What the pipeline does with each preset's intensity: the Livox presets retry locally, the
  // Ouster presets normalise for range and incidence.
  const auto line_of = [&](const std::string& name) {
    const std::size_t at = r.out.find("\n" + name + " ");
    return at == std::string::npos ? std::string()
                                   : r.out.substr(at + 1, r.out.find('\n', at + 1) - at - 1);
  };
  EXPECT_NE(line_of("mid40").find(" none "), std::string::npos) << line_of("mid40");
  EXPECT_NE(line_of("mid40").find(" 40+local "), std::string::npos) << line_of("mid40");
  EXPECT_NE(line_of("vlp16").find(" 40 "), std::string::npos) << line_of("vlp16");
  EXPECT_EQ(line_of("vlp16").find("+local"), std::string::npos) << line_of("vlp16");
  EXPECT_NE(line_of("os1-64").find(" range-incidence "), std::string::npos) << line_of("os1-64");
}

}  // namespace

// "-" sends a text result to stdout for a pipe; the human report moves to stderr so stdout holds
// the result alone. Same result as the file.
TEST(Cli, DashWritesTheResultToStdoutAndTheReportToStderr) {
  const fs::path d = cli_temp_dir();
  const std::string sample = std::string(IILFM_SOURCE_DIR) + "/data/sample/mid40_tag_wall.pcd";
  const std::string json = (d / "dash.json").string();
  const CliRun to_file = run_cli("detect " + sample + " --sensor mid40 --json " + json);
  ASSERT_EQ(to_file.status, 0) << to_file.err;
  const CliRun piped = run_cli("detect " + sample + " --sensor mid40 --json -");
  ASSERT_EQ(piped.status, 0) << piped.err;
  const nlohmann::json from_stdout = nlohmann::json::parse(piped.out);  // nothing else on stdout
  nlohmann::json from_file = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(from_stdout["markers"], from_file["markers"]);
  EXPECT_NE(piped.err.find("apriltag:tag36h11 id 0"), std::string::npos) << piped.err;
  EXPECT_FALSE(fs::exists("-"));

  // A recording: one JSON line per frame on stdout, the closing summary on stderr.
  const std::string mcap = std::string(IILFM_SOURCE_DIR) + "/tests/data/mcap/points_zstd.mcap";
  const CliRun lines = run_cli("detect " + mcap + " --topic /points --res-h 1 --res-v 1 --jsonl -");
  ASSERT_EQ(lines.status, 0) << lines.err;
  std::istringstream in(lines.out);
  std::string line;
  int count = 0;
  while (std::getline(in, line)) {
    EXPECT_EQ(nlohmann::json::parse(line)["frame"], count) << line;
    ++count;
  }
  EXPECT_EQ(count, 5);
  EXPECT_NE(lines.err.find("5 frames from"), std::string::npos) << lines.err;

  expect_input_error("detect " + sample + " --jsonl - --tum -", "only one output can be stdout");
  expect_input_error("detect " + sample + " --json - --image -",
                     "--image -: only --json, --jsonl and --tum write to stdout");
}

// --image writes PNG, or JPEG for a .jpg path; another extension is refused before any output.
TEST(Cli, ImageIsPngOrJpegByItsExtension) {
  const fs::path d = cli_temp_dir();
  const std::string sample = std::string(IILFM_SOURCE_DIR) + "/data/sample/mid40_tag_wall.pcd";
  for (const std::string name : {"overlay.png", "overlay.JPG"}) {
    const std::string path = (d / name).string();
    const CliRun r = run_cli("detect " + sample + " --sensor mid40 -q --image " + path);
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string bytes = slurp(path);
    ASSERT_GT(bytes.size(), 1000u);
    if (name == "overlay.png") {
      EXPECT_EQ(bytes.substr(1, 3), "PNG");
    } else {
      EXPECT_EQ(static_cast<unsigned char>(bytes[0]), 0xFF);  // JPEG start of image
      EXPECT_EQ(static_cast<unsigned char>(bytes[1]), 0xD8);
    }
  }
  const std::string json = (d / "not_written.json").string();
  expect_input_error("detect " + sample + " --sensor mid40 --json " + json + " --image " +
                         (d / "overlay.bmp").string(),
                     "use a .png or .jpg path");
  EXPECT_FALSE(fs::exists(json));
}
