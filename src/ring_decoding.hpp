// The ring-sample decoding stage (docs/pipeline.md, "Ring-sample decoding"): on images with one row
// per ring, a square marker's cells are read from the rings that crossed them (ring_cell_reader)
// and decoded with unsampled cells as erasures (cell_code_book). It checks what the detectors
// decoded from the square-pixel image, whose rows between rings are invented.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cell_code_book.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/projection.hpp"
#include "ring_cell_reader.hpp"

namespace iilfm::detail {

struct RingDecodeSettings {
  CellReadOptions read;
  // The black square is moved along the image's vertical by up to this many cells, in steps of
  // `shift_step`, to find where its fixed cells read best: between two rings an edge's place is
  // unknown, so the detector's top and bottom sides may be off by up to half a ring spacing.
  double max_shift_cells = 0.6;
  double shift_step = 0.05;
  // Candidates (quads no detector decoded) come from the binary image, where a border row no ring
  // crossed is missing: their top and bottom sides are moved independently, outwards by up to
  // `candidate_grow_cells` and inwards by up to max_shift_cells, in steps of candidate_step.
  double candidate_grow_cells = 1.5;
  double candidate_step = 0.1;
  // Candidates are read nearer the cell edges: the shift was fitted to their fixed cells.
  double candidate_central_fraction = 0.9;
  // Share of fixed cells read right somewhere on a coarse grid of placings before the full search.
  double candidate_min_coarse_agreement = 0.8;
  // A candidate still read too weakly after its measured sides is read again with its left and
  // right sides each moved by -1, 0 or +1 times this many pixels (eight more readings, which pay
  // log2 of all readings made): at 1.3-1.5 columns a cell, which columns fall in which cell flips
  // within a fraction of a pixel. Where the columns are coarse (columns_are_coarse), its top and
  // bottom sides instead. 0: not done.
  double candidate_side_step_px = 0.5;
  // ... when the first reading has at least this many chance-match bits.
  double candidate_side_min_bits = 0;
  int min_distance_margin = 2;
  // log2 of the chance that a random reading decodes (decode_cells): checking a detection.
  double min_security_bits = 10;
  // The same for quads no detector decoded, which have no decoding of their own to agree with.
  double candidate_min_security_bits = 12;
};

// What the ring samples say about one quad.
struct RingRead {
  bool read = false;  // the fixed cells read right somewhere in the shifts tried
  CellReading cells;
  DecodeResult decoded;
  double shift_top = 0, shift_bottom = 0;  // cells, down positive
  // The square's corners at that placing (projected image, in the order of the corners read).
  std::array<Vec2, 4> corners_px = {Vec2::Zero(), Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
};

// A family's code books: every code, and the codes of the ids known to be in the scene alone.
struct FamilyCodeBooks {
  std::unique_ptr<CellCodeBook> all;
  std::unique_ptr<CellCodeBook> known;  // null when no id of the family is known

  // decode_cells over every code. A reading the family's limits take, or would but for its
  // chance-match bits, with one bit more of distance to every other code than they ask, whose
  // code is a known one, is decoded over the known codes alone: a random reading has fewer
  // chances to match one of them.
  DecodeResult decode(const BitReading& reading, const DecodeLimits& limits,
                      int hypotheses = 1) const;
  // The book a reading's chance-match bits are best counted in: the known codes' when there are.
  const CellCodeBook& smallest() const { return known ? *known : *all; }
};

enum class RingVerdict {
  kConfirmed,     // the samples decode to the detection's id and rotation
  kCorrected,     // they decode safely to another id or rotation (the detection was changed)
  kContradicted,  // they disagree with the id in more bits than the family corrects
  kUndecided,     // too few samples or fixed cells
};

class RingDecoder {
 public:
  // `known_ids`: ids known to be in the scene, per family (PipelineOptions::known_ids); InputError
  // for an id outside its family.
  RingDecoder(const std::vector<std::string>& families, RingDecodeSettings settings,
              const std::map<std::string, std::vector<int>>& known_ids = {});

  bool supports(const std::string& family) const { return books_.count(family) > 0; }

  // Reads and decodes the square at `corners_px` (projected-image coordinates, any corner first).
  // `candidate`: a quad no detector decoded (settings' candidate_* apply).
  // `shifts` (a candidate's top and bottom shifts, cells, as RingRead's): read at them instead of
  // searching them (the same square read again with its left and right sides moved).
  RingRead read(const std::string& family, const std::array<Vec2, 4>& corners_px,
                const ProjectedImage& image, const cv::Mat& intensity, bool candidate = false,
                std::optional<std::pair<double, double>> shifts = std::nullopt) const;

  // Checks `d` (corners in projected-image coordinates) against the ring samples; a corrected
  // detection gets the decoded id and its corners reordered.
  RingVerdict verify(Detection& d, const ProjectedImage& image, const cv::Mat& intensity) const;

  using Quads = std::vector<std::array<Vec2, 4>>;
  // The dark squares decode_candidates reads in `detect_gray` (the detectors' binary image,
  // geometry `detect_geometry`): dark_quads, sized for the narrowest supported family and the
  // rings' spacing in `image`. The pipeline finds them while the detectors run.
  Quads candidate_quads(const cv::Mat& detect_gray, const ImageGeometry& detect_geometry,
                        const ProjectedImage& image) const;
  // Decodes the square candidates `quads` (candidate_quads of `detect_gray`) that no detector
  // decoded, read from the ring samples for every supported family. Appends detections in
  // projected-image coordinates (decision_margin = the decoding's chance-match bits, less log2 of
  // the families whose fixed cells fit the square: each is one more try). Quads whose centre
  // (projected-image coordinates) `known` says a detection already covers are not read.
  void decode_candidates(const cv::Mat& detect_gray, const ImageGeometry& detect_geometry,
                         const ProjectedImage& image, const cv::Mat& intensity, const Quads& quads,
                         std::vector<Detection>& out,
                         const std::function<bool(const Vec2&)>& known = {}) const;

  DecodeLimits limits(const std::string& family) const;

 private:
  // A candidate `first` read at `corners_px` too weakly: read again with the sides measured, then
  // moved (settings' candidate_side_step_px); `first` becomes the best reading, its chance-match
  // bits less what the extra tries cost.
  void read_weak_candidate_again(const std::string& family, const std::array<Vec2, 4>& corners_px,
                                 const ProjectedImage& image, const cv::Mat& intensity,
                                 RingRead& first) const;

  RingDecodeSettings settings_;
  std::map<std::string, FamilyCodeBooks> books_;
};

}  // namespace iilfm::detail
