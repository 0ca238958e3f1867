// The suites' set-ups and their renderings: Markdown tables for the docs and JSON for tools.
#include "iilfm/eval/report.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "iilfm/error.hpp"

namespace iilfm::eval {
namespace {

TEST(Suites, PaperSuiteRebuildsTablesOneToThree) {
  const std::vector<SuiteSetup> paper = named_suite("paper");
  ASSERT_EQ(paper.size(), 11u);  // 3 distances x 2 frame counts, 4 turns, ccw10m
  EXPECT_EQ(paper[0].spec.scene_params.distance_m.value(), 2.0);
  EXPECT_EQ(paper[1].spec.frames, 100);
  EXPECT_EQ(paper[5].spec.scene_params.distance_m.value(), 4.0);
  EXPECT_DOUBLE_EQ(paper[6].spec.lidar_rpy_deg.y(), -15);  // pitch
  EXPECT_DOUBLE_EQ(paper[9].spec.lidar_rpy_deg.z(), 15);   // yaw
  EXPECT_EQ(paper[10].spec.scene, "ccw10m");
  EXPECT_EQ(named_suite("quick").size(), 3u);
  EXPECT_THROW(named_suite("full"), InputError);
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
