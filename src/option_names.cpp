#include "iilfm/option_names.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <exception>

#include "iilfm/error.hpp"

namespace iilfm {

ArucoRefine aruco_refine_named(const std::string& name) {
  if (name == "none") return ArucoRefine::kNone;
  if (name == "subpixel") return ArucoRefine::kSubpixel;
  if (name == "contour") return ArucoRefine::kContour;
  if (name == "apriltag") return ArucoRefine::kAprilTag;
  throw InputError("--aruco-refine must be none, subpixel, contour or apriltag, got '" + name +
                   "'");
}

PoseRefine pose_refine_named(const std::string& name) {
  if (name == "none") return PoseRefine::kNone;
  if (name == "points") return PoseRefine::kPoints;
  throw InputError("--pose-refine must be none or points, got '" + name + "'");
}

const char* to_string(PoseRefine refine) {
  return refine == PoseRefine::kPoints ? "points" : "none";
}

void set_collision(const std::string& name, PipelineOptions& options) {
  if (name == "nearest")
    options.projection.collision = CollisionPolicy::kNearest;
  else if (name == "mean")
    options.projection.collision = CollisionPolicy::kMean;
  else
    throw InputError("--collision must be 'mean' or 'nearest', got '" + name + "'");
}

void set_rows(const std::string& name, PipelineOptions& options) {
  if (name == "uniform")
    options.projection.rows = RowLayout::kUniform;
  else if (name == "rings")
    options.projection.rows = RowLayout::kRings;
  else if (!name.empty())
    throw InputError("--rows must be 'uniform' or 'rings', got '" + name + "'");
}

void set_lift(const std::string& name, PipelineOptions& options) {
  if (name == "paper") {
    options.lift = LiftMethod::kPaper;
    options.fit_known_size = false;  // the paper's four corners, as lifted
  } else if (name == "plane") {
    options.lift = LiftMethod::kPlane;
  } else {
    throw InputError("--lift must be 'plane' or 'paper', got '" + name + "'");
  }
}

void set_intensity_normalisation(const std::string& name, PipelineOptions& options) {
  if (name.empty()) return;
  IntensityNormalisation mode;
  if (name == "none")
    mode = IntensityNormalisation::kNone;
  else if (name == "range")
    mode = IntensityNormalisation::kRange;
  else if (name == "range-incidence")
    mode = IntensityNormalisation::kRangeIncidence;
  else
    throw InputError("--normalise-intensity must be none, range or range-incidence, got '" + name +
                     "'");
  IntensityNormalisation& current = options.preprocess.normalise.mode;
  if (current == IntensityNormalisation::kNone && mode != IntensityNormalisation::kNone)
    options.preprocess.threshold.reset();  // a fixed threshold was in unnormalised units
  current = mode;
}

void set_threshold(const std::string& text, PipelineOptions& options) {
  if (text.empty()) return;
  if (text == "otsu") {
    options.preprocess.threshold.reset();
  } else if (text == "local") {
    options.preprocess.local_threshold = true;
  } else {
    char* end = nullptr;
    const double t = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !std::isfinite(t))
      throw InputError("--threshold must be a number, 'otsu' or 'local', got '" + text + "'");
    set_given_threshold(t, options);
  }
}

void set_given_threshold(double threshold, PipelineOptions& options) {
  options.preprocess.threshold = threshold;
  options.preprocess.replace_threshold_above_all = false;
  options.retry_with_otsu = false;
  options.retry_with_local_threshold = false;
}

std::vector<int> parse_id_list(const std::string& text) {
  // Larger than any family (tagStandard52h13 has 48714 ids): a typo, not a list.
  constexpr long kMostIds = 100000;
  const auto refuse = [&](const std::string& why) {
    return InputError("--ids must be ids and ranges such as 0,3,10-19, got '" + text + "': " + why);
  };
  const auto number = [&](const std::string& word) {
    std::size_t used = 0;
    long value = -1;
    try {
      value = std::stol(word, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (word.empty() || used != word.size() || value < 0 || value >= kMostIds ||
        !std::isdigit(static_cast<unsigned char>(word[0])))
      throw refuse("'" + word + "' is not an id");
    return static_cast<int>(value);
  };
  std::vector<int> ids;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    const std::size_t dash = item.find('-');
    if (dash == std::string::npos) {
      ids.push_back(number(item));
    } else {
      const int first = number(item.substr(0, dash)), last = number(item.substr(dash + 1));
      if (last < first) throw refuse("the range '" + item + "' runs backwards");
      for (int id = first; id <= last; ++id) ids.push_back(id);
    }
    if (ids.size() > static_cast<std::size_t>(kMostIds)) throw refuse("too many ids");
    start = comma + 1;
  }
  return ids;
}

void set_known_ids(const std::vector<int>& ids, PipelineOptions& options) {
  for (const std::string& family : options.families) options.known_ids[family] = ids;
  options.only_known_ids = true;
}

}  // namespace iilfm
