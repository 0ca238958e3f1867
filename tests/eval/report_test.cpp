// The suites' set-ups and their renderings: Markdown tables for the docs and JSON for tools.
#include "iilfm/eval/report.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "iilfm/error.hpp"

namespace iilfm::eval {
namespace {

TEST(Suites, PaperSuiteRebuildsTablesOneToThree) {
  const std::vector<SuiteSetup> paper = named_suite("paper");
  ASSERT_GE(paper.size(), 11u);  // 3 distances x 2 frame counts, 4 turns, ccw10m, then ArUco
  EXPECT_EQ(paper[0].spec.scene_params.distance_m.value(), 2.0);
  EXPECT_EQ(paper[1].spec.frames, 100);
  EXPECT_EQ(paper[5].spec.scene_params.distance_m.value(), 4.0);
  EXPECT_DOUBLE_EQ(paper[6].spec.lidar_rpy_deg.y(), -15);  // pitch
  EXPECT_DOUBLE_EQ(paper[9].spec.lidar_rpy_deg.z(), 15);   // yaw
  EXPECT_EQ(paper[10].spec.scene, "ccw10m");
  EXPECT_EQ(named_suite("quick").size(), 4u);
  EXPECT_THROW(named_suite("full"), InputError);
}

// The ArUco cases: the paper's VLP-16 with a 40 cm original ArUco (three distances, and the
// Hi-Res at two), and the grid's 16 cm DICT_4X4_50 on a Mid-40; the quick suite keeps the latter.
TEST(Suites, PaperSuiteHasTheArucoCases) {
  const std::vector<SuiteSetup> paper = named_suite("paper");
  ASSERT_EQ(paper.size(), 17u);
  for (std::size_t i = 11; i < 16; ++i) {
    EXPECT_EQ(paper[i].spec.scene_params.family.value(), "aruco:DICT_ARUCO_ORIGINAL");
    EXPECT_DOUBLE_EQ(paper[i].spec.scene_params.marker_size_m.value(), 0.4);
    EXPECT_EQ(paper[i].spec.frames, 1);
    EXPECT_FALSE(paper[i].published.empty());
  }
  EXPECT_EQ(paper[11].spec.sensor, "vlp16");
  EXPECT_EQ(paper[15].spec.sensor, "vlp16-hires");
  EXPECT_EQ(paper[16].spec.scene_params.family.value(), "aruco:DICT_4X4_50");
  EXPECT_EQ(named_suite("quick")[3].name, paper[16].name);
}

SuiteResult fake_result() {
  SuiteResult suite;
  suite.suite = "quick";
  suite.options.seeds = {1, 2};
  SetupResult r;
  r.setup = named_suite("quick")[0];
  r.seeds = {1, 2};
  CaseScore a, b;
  a.visible = b.visible = 1;
  a.detected = 1;
  a.corners = 4;
  a.corner_error_mean = 0.001;
  a.corner_error_max = 0.002;
  a.pose = true;
  a.position_error = 0.005;
  a.rotation_error_deg = 0.2;
  b.false_positives = 1;
  r.cases = {a, b};
  r.summary = summarize(r.cases);
  suite.results = {r};
  return suite;
}

TEST(Report, SummaryTakesMeansOverTheCasesThatHaveTheFigure) {
  const Summary s = fake_result().results[0].summary;
  EXPECT_EQ(s.cases, 2);
  EXPECT_EQ(s.detected, 1);
  EXPECT_EQ(s.visible, 2);
  EXPECT_EQ(s.false_positives, 1);
  EXPECT_EQ(s.poses, 1);
  EXPECT_DOUBLE_EQ(s.corner_error.mean(), 0.001);
  EXPECT_DOUBLE_EQ(s.corner_error.worst, 0.002);
  EXPECT_DOUBLE_EQ(s.position.mean(), 0.005);
}

TEST(Report, MarkdownHasOneRowPerSetupAndLift) {
  const std::string md = to_markdown(fake_result());
  EXPECT_NE(md.find("seeds 1-2"), std::string::npos) << md;
  EXPECT_NE(md.find("**Table 1"), std::string::npos) << md;
  EXPECT_NE(md.find("| Mid-40, 2 m, 40 frames | plane | 1/2 | 1 / 0 | 1.0 (2.0) | - | - | "
                    "5.0 (5.0) | 0.20 (0.20) |"),
            std::string::npos)
      << md;
}

TEST(Report, PublishedNoteFollowsItsGroupsTable) {
  SuiteResult suite = fake_result();
  SetupResult aruco = suite.results[0];
  aruco.setup = named_suite("quick")[3];
  suite.results.push_back(aruco);
  const std::string md = to_markdown(suite);
  const std::size_t table = md.find("**ArUco: Mid-40"), note = md.find("Paper (Fig. 8(a)");
  ASSERT_NE(table, std::string::npos) << md;
  ASSERT_NE(note, std::string::npos) << md;
  EXPECT_LT(table, note);
  EXPECT_EQ(md.find("Paper ("), note);  // Table 1 has no note
}

TEST(Report, JsonHoldsEveryCaseInSIUnits) {
  const nlohmann::json j = nlohmann::json::parse(to_json(fake_result()));
  EXPECT_EQ(j["suite"], "quick");
  ASSERT_EQ(j["results"].size(), 1u);
  const nlohmann::json& r = j["results"][0];
  EXPECT_EQ(r["lift"], "plane");
  EXPECT_EQ(r["sensor"], "mid40");
  ASSERT_EQ(r["cases"].size(), 2u);
  EXPECT_EQ(r["cases"][1]["seed"], 2);
  EXPECT_DOUBLE_EQ(r["summary"]["position_error_m"]["mean"].get<double>(), 0.005);
  EXPECT_EQ(r["summary"]["false_positives"], 1);
}

}  // namespace
}  // namespace iilfm::eval
