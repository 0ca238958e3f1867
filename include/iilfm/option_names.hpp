// Option values by name, as `iilfm detect` and the Python module take them, with one error
// message each, so both front ends accept the same words and say the same thing.
#pragma once

#include <string>
#include <vector>

#include "iilfm/pipeline.hpp"

namespace iilfm {

// "none", "subpixel", "contour", "apriltag".
ArucoRefine aruco_refine_named(const std::string& name);

// --pose-refine: "none" (the Kabsch pose of the corners) or "points" (then refined with the
// marker-plane points), and its name back.
PoseRefine pose_refine_named(const std::string& name);
const char* to_string(PoseRefine refine);

// --collision: "mean" or "nearest".
void set_collision(const std::string& name, PipelineOptions& options);

// --rows: "uniform" or "rings"; empty keeps the current layout.
void set_rows(const std::string& name, PipelineOptions& options);

// --lift: "plane" or "paper" (the paper's four corners as lifted, no known-size square).
void set_lift(const std::string& name, PipelineOptions& options);

// --normalise-intensity: "none", "range" or "range-incidence"; empty keeps the current mode.
// Switching normalisation on also switches a fixed threshold (a preset's, in the sensor's own
// units) to Otsu's; a --threshold applied afterwards is taken in normalised units.
void set_intensity_normalisation(const std::string& name, PipelineOptions& options);

// --threshold as text: a number in intensity units, "otsu" or "local" (local mean where the image
// has contrast, the preset's or Otsu's threshold elsewhere); empty keeps the current one.
void set_threshold(const std::string& text, PipelineOptions& options);

// A fixed threshold the user gives (--threshold T, Python threshold=T): kept as given, never
// replaced by Otsu's above every intensity nor retried at Otsu's when it finds nothing.
void set_given_threshold(double threshold, PipelineOptions& options);

// --ids as text: ids and ranges, "0,3,10-19"; InputError naming --ids for anything else.
std::vector<int> parse_id_list(const std::string& text);

// --ids, Python ids=: the markers in the scene are `ids` of every family in options.families
// (set those first). Only they are reported, and ring-sample decoding reads them from fewer ring
// samples (PipelineOptions::known_ids, only_known_ids).
void set_known_ids(const std::vector<int>& ids, PipelineOptions& options);

}  // namespace iilfm
