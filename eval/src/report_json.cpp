// JSON rendering of suite results: the options, every case and every summary, SI units.
#include <nlohmann/json.hpp>

#include "iilfm/eval/report.hpp"

namespace iilfm::eval {
namespace {

using nlohmann::json;

json stat_json(const Stat& s) {
  return {{"count", s.count}, {"mean", s.mean()}, {"worst", s.worst}};
}

json case_json(std::uint64_t seed, const CaseScore& c) {
  return {{"seed", seed},
          {"visible", c.visible},
          {"detected", c.detected},
          {"false_positives", c.false_positives},
          {"wrong_ids", c.wrong_ids},
          {"corners", c.corners},
          {"corner_error_mean_m", c.corner_error_mean},
          {"corner_error_max_m", c.corner_error_max},
          {"size_error_m", c.size_error_mean},
          {"marker_poses", c.marker_poses},
          {"marker_position_error_m", c.marker_position_error_mean},
          {"marker_rotation_error_deg", c.marker_rotation_error_mean_deg},
          {"pose", c.pose},
          {"position_error_m", c.position_error},
          {"rotation_error_deg", c.rotation_error_deg},
          {"marker_position_sigma_m", c.marker_position_sigma_mean},
          {"marker_rotation_sigma_deg", c.marker_rotation_sigma_mean_deg},
          {"marker_nees", c.marker_nees_mean},
          {"position_sigma_m", c.position_sigma},
          {"rotation_sigma_deg", c.rotation_sigma_deg},
          {"pose_nees", c.pose_nees},
          {"time_ms", c.time_ms}};
}

json summary_json(const Summary& s) {
  return {{"cases", s.cases},
          {"visible", s.visible},
          {"detected", s.detected},
          {"false_positives", s.false_positives},
          {"wrong_ids", s.wrong_ids},
          {"poses", s.poses},
          {"corner_error_m", stat_json(s.corner_error)},
          {"size_error_m", stat_json(s.size_error)},
          {"marker_position_error_m", stat_json(s.marker_position)},
          {"marker_rotation_error_deg", stat_json(s.marker_rotation_deg)},
          {"position_error_m", stat_json(s.position)},
          {"rotation_error_deg", stat_json(s.rotation_deg)},
          {"time_ms", stat_json(s.time_ms)}};
}

}  // namespace

std::string to_json(const SuiteResult& suite) {
  json lifts = json::array();
  for (LiftMethod l : suite.options.lifts) lifts.push_back(lift_name(l));
  json results = json::array();
  for (const SetupResult& r : suite.results) {
    json cases = json::array();
    for (std::size_t i = 0; i < r.cases.size(); ++i)
      cases.push_back(case_json(r.seeds[i], r.cases[i]));
    const CaseSpec& spec = r.setup.spec;
    results.push_back({{"group", r.setup.group},
                       {"setup", r.setup.name},
                       {"scene", spec.scene},
                       {"sensor", spec.sensor},
                       {"frames", spec.frames},
                       {"lidar_rpy_deg",
                        {spec.lidar_rpy_deg.x(), spec.lidar_rpy_deg.y(), spec.lidar_rpy_deg.z()}},
                       {"lift", lift_name(r.lift)},
                       {"summary", summary_json(r.summary)},
                       {"cases", cases}});
    if (!r.setup.published.empty()) results.back()["published"] = r.setup.published;
  }
  const SuiteOptions& o = suite.options;
  json out = {{"suite", suite.suite},
              {"seeds", o.seeds},
              {"lifts", lifts},
              {"physics",
               {{"footprint", o.footprint},
                {"dark_dropout", o.dark_dropout},
                {"invalid_fraction", o.invalid_fraction}}},
              {"seconds", suite.seconds},
              {"results", results}};
  return out.dump(2);
}

}  // namespace iilfm::eval
