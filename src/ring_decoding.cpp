#include "ring_decoding.hpp"

#include <algorithm>
#include <cmath>

namespace iilfm::detail {

RingDecoder::RingDecoder(const std::vector<std::string>& families, RingDecodeSettings settings)
    : settings_(settings) {
  for (const std::string& family : families) {
    if (books_.count(family)) continue;
    std::unique_ptr<CellCodeBook> book = CellCodeBook::for_family(family);
    if (book) books_.emplace(family, std::move(book));
  }
}

DecodeLimits RingDecoder::limits(const std::string& family) const {
  const CellCodeBook& book = *books_.at(family);
  DecodeLimits limits;
  limits.max_errors = std::max(0, (book.min_distance() - 1) / 2);
  limits.min_distance_margin = settings_.min_distance_margin;
  limits.min_security_bits = settings_.min_security_bits;
  return limits;
}

RingRead RingDecoder::read(const std::string& family, const std::array<Vec2, 4>& corners_px,
                           const ProjectedImage& image, const cv::Mat& intensity) const {
  RingRead out;
  const auto it = books_.find(family);
  if (it == books_.end()) return out;
  const CellCodeBook& book = *it->second;
  const MarkerSamples samples(corners_px, image, intensity, book);
  if (samples.empty()) return out;
  // The shift is chosen on the fixed cells alone (the middle of the best-reading run), so the
  // data bits are decoded once and no code gets several tries.
  std::vector<MarkerSamples::Placed> placed;
  const int steps = static_cast<int>(std::lround(settings_.max_shift_cells / settings_.shift_step));
  double best_agreement = -1;
  std::vector<double> best_shifts;
  for (int s = -steps; s <= steps; ++s) {
    const double shift = s * settings_.shift_step;
    samples.place(shift, placed);
    const CellReading cells = read_cells(placed, book, settings_.read);
    if (!cells.levels_ok) continue;
    const double agreement = static_cast<double>(cells.fixed_agreeing) / cells.fixed_cells;
    if (agreement > best_agreement + 1e-9) {
      best_agreement = agreement;
      best_shifts.clear();
    }
    if (agreement > best_agreement - 1e-9) best_shifts.push_back(shift);
  }
  if (best_shifts.empty()) return out;
  out.shift_cells = best_shifts[best_shifts.size() / 2];
  samples.place(out.shift_cells, placed);
  out.cells = read_cells(placed, book, settings_.read);
  out.read = true;
  out.decoded = decode_cells(book, out.cells.bits, limits(family));
  return out;
}

RingVerdict RingDecoder::verify(Detection& d, const ProjectedImage& image,
                                const cv::Mat& intensity) const {
  if (!supports(d.family) || d.corners_px.size() != 4) return RingVerdict::kUndecided;
  const std::array<Vec2, 4> corners = {d.corners_px[0], d.corners_px[1], d.corners_px[2],
                                       d.corners_px[3]};
  const RingRead r = read(d.family, corners, image, intensity);
  if (!r.read) return RingVerdict::kUndecided;
  const DecodeResult& decoded = r.decoded;
  if (decoded.accepted && decoded.id == d.id && decoded.quarter_turns == 0)
    return RingVerdict::kConfirmed;
  if (decoded.accepted) {
    // The samples name another id (or turn): corner q of the quad is the print's top-left.
    d.id = decoded.id;
    d.hamming = decoded.errors;
    std::rotate(d.corners_px.begin(), d.corners_px.begin() + decoded.quarter_turns,
                d.corners_px.end());
    return RingVerdict::kCorrected;
  }
  const int errors = errors_against(*books_.at(d.family), r.cells.bits, d.id);
  return errors > limits(d.family).max_errors ? RingVerdict::kContradicted
                                              : RingVerdict::kUndecided;
}

}  // namespace iilfm::detail
