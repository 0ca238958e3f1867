// The ring-sample decoding stage (docs/pipeline.md, "Ring-sample decoding"): on images with one row
// per ring, a square marker's cells are read from the rings that crossed them (ring_cell_reader)
// and decoded with unsampled cells as erasures (cell_code_book). It checks what the detectors
// decoded from the square-pixel image, whose rows between rings are invented.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
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
  int min_distance_margin = 2;
  double min_security_bits = 10;
};

// What the ring samples say about one quad.
struct RingRead {
  bool read = false;  // the fixed cells read right somewhere in the shifts tried
  CellReading cells;
  DecodeResult decoded;
  double shift_cells = 0;
};

enum class RingVerdict {
  kConfirmed,     // the samples decode to the detection's id and rotation
  kCorrected,     // they decode safely to another id or rotation (the detection was changed)
  kContradicted,  // they disagree with the id in more bits than the family corrects
  kUndecided,     // too few samples or fixed cells
};

class RingDecoder {
 public:
  RingDecoder(const std::vector<std::string>& families, RingDecodeSettings settings);

  bool supports(const std::string& family) const { return books_.count(family) > 0; }

  // Reads and decodes the square at `corners_px` (projected-image coordinates, any corner first).
  RingRead read(const std::string& family, const std::array<Vec2, 4>& corners_px,
                const ProjectedImage& image, const cv::Mat& intensity) const;

  // Checks `d` (corners in projected-image coordinates) against the ring samples; a corrected
  // detection gets the decoded id and its corners reordered.
  RingVerdict verify(Detection& d, const ProjectedImage& image, const cv::Mat& intensity) const;

  DecodeLimits limits(const std::string& family) const;

 private:
  RingDecodeSettings settings_;
  std::map<std::string, std::unique_ptr<CellCodeBook>> books_;
};

}  // namespace iilfm::detail
