// The paper's released implementation approach, rebuilt from its described steps so iilfm can be
// timed against it on the same scans in the same run: two PCL range images (range, and intensity
// folded into the coordinates), a colour map of the intensity image converted to gray, the naive
// threshold, then the same libapriltag call iilfm makes. Built only when PCL is installed.
#pragma once

#include <memory>
#include <string>

#include "iilfm/types.hpp"

namespace iilfm::bench {

struct BaselineOptions {
  float res_h_deg = 0.05f, res_v_deg = 0.05f;  // angular resolution of both range images
  // Angular window around the sensor's x axis that PCL allocates before cropping: the sensor's
  // field of view (PCL's default, the whole sphere, costs 26 Mpixels at 0.05 deg).
  float max_angle_width_deg = 360.0f, max_angle_height_deg = 180.0f;
  float threshold = 40.0f;  // naive threshold in the cloud's intensity units
  std::string family = "tag36h11";
};

class PaperBaseline {
 public:
  explicit PaperBaseline(BaselineOptions options);
  ~PaperBaseline();
  PaperBaseline(const PaperBaseline&) = delete;
  PaperBaseline& operator=(const PaperBaseline&) = delete;

  // Runs every step on `cloud`; returns the number of markers AprilTag reports.
  int detect(const PointCloud& cloud);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace iilfm::bench
