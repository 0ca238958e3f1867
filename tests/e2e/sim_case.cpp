#include "sim_case.hpp"

#include <cmath>

#include "iilfm/sensor.hpp"

namespace iilfm::testing {

MarkerMap map_of(const sim::Scene& scene) {
  MarkerMap map;
  for (const sim::MarkerSpec& m : scene.markers) {
    MapMarker mm;
    mm.family = m.family;
    mm.id = m.id;
    mm.corners_world = sim::marker_corners_world(m);
    map.add(mm);
  }
  return map;
}

CaseErrors run_sim_case(const CaseSetup& setup) {
  const sim::SceneSetup scene = sim::named_scene(setup.scene);
  sim::SimOptions sim_options;
  sim_options.T_world_lidar = scene.T_world_lidar;
  sim_options.frames = setup.frames;
  sim_options.seed = setup.seed;
  const sim::SimResult sim =
      sim::simulate(scene.scene, sim::sensor_model(setup.sensor), sim_options);

  PipelineOptions options;
  const SensorPreset& preset = find_sensor_preset(setup.sensor);
  options.projection.res_h_deg = preset.res_h_deg;
  options.projection.res_v_deg = preset.res_v_deg;
  options.preprocess.threshold = preset.threshold;
  options.families = {scene.scene.markers.front().family};
  options.map = map_of(scene.scene);
  options.lift = setup.lift;
  Pipeline pipeline(options);
  const FrameResult& result = pipeline.process(sim.cloud);

  CaseErrors e;
  e.detections = static_cast<int>(result.markers.size());
  e.total_ms = result.times_ms.total();
  const sim::MarkerTruth& truth = sim.truth.markers.front();
  for (const MarkerResult& m : result.markers) {
    const bool known = options.map->find(m.detection.family, m.detection.id) != nullptr;
    if (!known) ++e.wrong;
    if (m.detection.family != truth.family || m.detection.id != truth.id) continue;
    e.found = true;
    int n = 0;
    for (int k = 0; k < 4; ++k) {
      if (!m.corners[k].valid()) continue;
      const double err = (m.corners[k].point - truth.corners_lidar[k]).norm();
      e.mean_corner_error += err;
      e.max_corner_error = std::max(e.max_corner_error, err);
      ++n;
    }
    if (n > 0) e.mean_corner_error /= n;
  }
  if (result.pose) {
    e.pose = true;
    const Isometry3& est = result.pose->T_world_lidar;
    const Isometry3& gt = sim.truth.T_world_lidar;
    e.position_error = (est.translation() - gt.translation()).norm();
    e.rotation_error_deg =
        Eigen::AngleAxisd(est.linear().transpose() * gt.linear()).angle() * 180 / M_PI;
  }
  return e;
}

}  // namespace iilfm::testing
