#include "ring_decoding.hpp"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>
#include <utility>

#include "candidate_sides.hpp"
#include "convex_polygon.hpp"
#include "dark_quads.hpp"
#include "detectors/aruco_detector.hpp"
#include "iilfm/square_pixels.hpp"
#include "ring_row_alignment.hpp"
#include "seam_detection.hpp"

namespace iilfm::detail {

namespace {

// Coarse placings of a candidate within this share of fixed cells of the best are searched finely.
constexpr double kCoarseTolerance = 0.1;
// Share of the tied placings' accepted decodings a candidate's decoding must have.
constexpr double kMinTiedShare = 0.4;
// Where no tied placing of a candidate decodes, the placings within this share of fixed cells of
// the best vote too. Sparse rings read a placing's few fixed cells right by luck: an OS1-64's 1 m
// tag at 14 m had 43 placings tied at 24-30 fixed cells all read right, none decoding, while
// placings reading 44 of 46 read id 0 from 20 bits with no error. 0.1 found fewer markers of the
// spinning-sensor grids than 0.05 (the choice among more readings is paid for).
constexpr double kNearTolerance = 0.05;

// Where the rings are sparse, the fixed cells fit a whole patch of a candidate's placings equally
// well (100-150 of them for a 40 cm tag36h11 at 1.5 m on a VLP-16, whose rings cross one cell row
// each: either side may lie anywhere between two rings), and those placings read different codes.
// Every tied placing votes with its reading:
// - when the middle one decodes, its reading must be the most common one and hold a good share of
//   the accepted ones. A dictionary whose every row is one of a few words (ArUco's original) turns
//   a row read one ring off into another valid id with no error to show for it (measured: 40 cm
//   ARUCO_ORIGINAL at 2 m on a VLP-16 Hi-Res, id 100 read as 84 at the tied placings' mean in 1
//   of 10 scans, where the ties read 84 in a fifth of their decodings; right readings held 45-86 %
//   of them);
// - when it does not (its rows read one ring off), the most common accepted reading is taken on
//   the same terms;
// - either reading is then taken from the placing where it decodes most securely when that beats
//   the middle's own decoding. Choosing among the ties' readings is that many tries at a chance
//   match: its security bits pay log2 of the number of distinct readings (measured: the two
//   VLP-16 scans above had 30-odd, where 34 of 142 placings read the right id with no error and
//   the middle one read 4 errors).
// Where none of the tied placings decodes, the near-best ones (kNearTolerance) vote the same way.
void resolve_tied_placings(const FamilyCodeBooks& books, const MarkerSamples& samples,
                           const CellReadOptions& read_options,
                           const std::vector<std::pair<double, double>>& tied,
                           const DecodeLimits& limits, double min_security_bits, RingRead& out) {
  struct Reading {
    CellReading cells;
    const DecodeResult* decoded = nullptr;  // shared by the placings that read the same bits
    std::pair<double, double> placing;
  };
  const CellCodeBook& book = *books.all;
  using Bits = std::pair<std::uint64_t, std::uint64_t>;  // (white & known, known)
  const auto bits_of = [](const CellReading& c) {
    return Bits{c.bits.white & c.bits.known, c.bits.known};
  };
  MarkerSamples::Scratch scratch;
  std::vector<Reading> readings;
  readings.reserve(tied.size());
  std::map<Bits, DecodeResult> decodings;  // one per distinct reading
  int most_known = 0;
  for (const auto& [t, b] : tied) {
    Reading r{samples.read(t, b, book, read_options, scratch), nullptr, {t, b}};
    decodings.emplace(bits_of(r.cells), DecodeResult{});
    most_known =
        std::max(most_known, static_cast<int>(std::bitset<64>(r.cells.bits.known).count()));
    readings.push_back(std::move(r));
  }
  // Without the middle's decoding, a choice among the readings must still leave enough
  // chance-match bits with no error at all; a hopeless one is not decoded (on a VLP-16 recording
  // of a 17 cm tag at 1 m, 68 ties with 21 distinct readings of at most 24 known bits, every
  // frame).
  const int hypotheses = static_cast<int>(decodings.size());
  if (!out.decoded.accepted &&
      chance_match_bits(books.smallest(), most_known, 0, hypotheses) < min_security_bits)
    return;
  for (auto& [bits, decoded] : decodings)
    decoded = books.decode(BitReading{bits.first, bits.second}, limits);
  std::map<std::pair<int, int>, int> votes;
  int accepted = 0;
  for (Reading& r : readings) {
    r.decoded = &decodings.at(bits_of(r.cells));
    if (!r.decoded->accepted) continue;
    ++accepted;
    ++votes[{r.decoded->id, r.decoded->quarter_turns}];
  }
  // The reading to keep: the middle one's when it decodes, else the most common accepted one.
  std::pair<int, int> chosen{out.decoded.id, out.decoded.quarter_turns};
  if (!out.decoded.accepted) {
    int most = 0;
    for (const auto& [reading, count] : votes)
      if (count > most) {
        most = count;
        chosen = reading;
      }
    if (most == 0) return;
  }
  const int own = votes[chosen];
  int strongest_other = 0;
  for (const auto& [reading, count] : votes)
    if (reading != chosen) strongest_other = std::max(strongest_other, count);
  if (own <= strongest_other || own < kMinTiedShare * accepted) {
    out.decoded.accepted = false;
    return;
  }
  // The placing where the chosen reading decodes best, the choice paid for, when that beats the
  // middle's own decoding (which may decode from too few bits: 22 of a 40 cm tag36h11 at 2.5 m on
  // a VLP-16 Hi-Res, where other tied placings read the same id from 34).
  const Reading* strongest = nullptr;
  for (const Reading& r : readings)
    if (r.decoded->accepted && std::make_pair(r.decoded->id, r.decoded->quarter_turns) == chosen &&
        (!strongest || r.decoded->security_bits > strongest->decoded->security_bits))
      strongest = &r;
  if (!strongest) return;  // own > 0 above: not reached
  const DecodeResult paid = books.decode(strongest->cells.bits, limits, hypotheses);
  if (out.decoded.accepted && paid.security_bits <= out.decoded.security_bits) return;
  out.cells = strongest->cells;
  out.shift_top = strongest->placing.first;
  out.shift_bottom = strongest->placing.second;
  out.decoded = paid;
}

}  // namespace

DecodeResult FamilyCodeBooks::decode(const BitReading& reading, const DecodeLimits& limits,
                                     int hypotheses) const {
  DecodeResult result = decode_cells(*all, reading, limits, hypotheses);
  // Only a reading the family's own limits take, or would but for its chance-match bits, that
  // lies three bits (one more than the default margin) further from every other code than from
  // its nearest: a marker of an id not known must misread three bits more than this reading has
  // errors to pass for a known one. Nearer by one bit or two was not enough: codes of the original
  // ArUco dictionary read from 15-20 bits lie two bits from several others, and one marker read
  // as a mapped id (VLP-16 Hi-Res, a grid at 5 m whose map listed 5 of its 35 ids; one wrong id
  // among 538 found). The reading's own distance to the other codes, not the worst one its errors
  // allow (2 t + 3 to the nearest code): that refused right readings with an error that lay as
  // clear of every other code (an OS1-64's 40 cm tag at 5 m, one error in 22 bits).
  const bool clear_of_others =
      result.errors <= limits.max_errors &&
      result.errors + limits.min_distance_margin + 1 <= result.reading_to_next;
  // A reading the family's limits accept already is counted among the known codes too when it
  // is a known id: a candidate asks for more chance-match bits than the limits do.
  if (!known || !clear_of_others) return result;
  const DecodeResult among_known = decode_cells(*known, reading, limits, hypotheses);
  if (among_known.accepted && among_known.id == result.id &&
      among_known.quarter_turns == result.quarter_turns)
    return among_known;
  return result;
}

RingDecoder::RingDecoder(const std::vector<std::string>& families, RingDecodeSettings settings,
                         const std::map<std::string, std::vector<int>>& known_ids)
    : settings_(settings) {
  for (const std::string& family : families) {
    if (books_.count(family)) continue;
    std::unique_ptr<CellCodeBook> book = CellCodeBook::for_family(family);
    if (!book) continue;
    FamilyCodeBooks books;
    const auto known = known_ids.find(family);
    if (known != known_ids.end() && !known->second.empty())
      books.known = std::make_unique<CellCodeBook>(book->restricted_to(known->second));
    books.all = std::move(book);
    books_.emplace(family, std::move(books));
  }
}

DecodeLimits RingDecoder::limits(const std::string& family) const {
  const CellCodeBook& book = *books_.at(family).all;
  DecodeLimits limits;
  limits.max_errors = std::max(0, (book.min_distance() - 1) / 2);
  limits.min_distance_margin = settings_.min_distance_margin;
  limits.min_security_bits = settings_.min_security_bits;
  return limits;
}

RingRead RingDecoder::read(const std::string& family, const std::array<Vec2, 4>& corners_px,
                           const ProjectedImage& image, const cv::Mat& intensity, bool candidate,
                           std::optional<std::pair<double, double>> shifts) const {
  RingRead out;
  const auto it = books_.find(family);
  if (it == books_.end()) return out;
  const FamilyCodeBooks& books = it->second;
  const CellCodeBook& book = *books.all;
  const MarkerSamples samples(corners_px, image, intensity, book);
  if (samples.empty()) return out;
  CellReadOptions read_options = settings_.read;
  if (candidate) read_options.central_fraction = settings_.candidate_central_fraction;
  // The sides' places are chosen on the fixed cells alone (the middle of the best-reading ones),
  // so the data bits are decoded once and no code gets several tries.
  const double step = candidate ? settings_.candidate_step : settings_.shift_step;
  const double grow = candidate ? settings_.candidate_grow_cells : settings_.max_shift_cells;
  const int inward = static_cast<int>(std::lround(settings_.max_shift_cells / step));
  const int outward = static_cast<int>(std::lround(grow / step));
  MarkerSamples::Scratch scratch;
  // A re-reading's one placing: `shifts`, in steps.
  std::optional<std::pair<int, int>> kept;
  if (candidate && shifts)
    kept = {std::clamp(static_cast<int>(std::lround(shifts->first / step)), -outward, inward),
            std::clamp(static_cast<int>(std::lround(shifts->second / step)), -inward, outward)};
  // The search reads only the samples that can fall in a fixed cell at one of its placings (the
  // same agreements from a fraction of the samples). A detection's placings move the square as a
  // whole; a candidate's move its top side by -outward..inward steps and its bottom side by
  // -inward..outward.
  const MarkerSamples searched =
      kept        ? samples.fixed_cell_samples({kept->first * step, kept->first * step},
                                               {kept->second * step, kept->second * step}, book,
                                               read_options.central_fraction)
      : candidate ? samples.fixed_cell_samples({-outward * step, inward * step},
                                               {-inward * step, outward * step}, book,
                                               read_options.central_fraction)
                  : samples.fixed_cell_samples(-outward * step, inward * step, book,
                                               read_options.central_fraction);
  const auto agreement_at = [&](double t, double b) {
    return searched.fixed_agreement(t, b, book, read_options, scratch);
  };
  const int span = inward + outward + 1;
  // Placings to try: every one for a detection (b == t), for a candidate those near the best of
  // a coarse look.
  std::vector<char> wanted(static_cast<std::size_t>(span) * span, candidate ? 0 : 1);
  const auto index = [&](int t, int b) {
    return static_cast<std::size_t>(t + outward) * span + static_cast<std::size_t>(b + inward);
  };
  // The coarse look's agreements, kept for the finer search (NaN: not read yet).
  std::vector<double> known(candidate ? wanted.size() : 0, std::nan(""));
  if (kept) {
    wanted[index(kept->first, kept->second)] = 1;
  } else if (candidate) {
    // Most candidates are clutter: a coarse look (every third placing) must already find the
    // fixed cells mostly right before the finer search, which then looks only around the coarse
    // placings that read nearly as well as the best (agreement changes by a few fixed cells from
    // one placing to the next, so the best fine placing lies next to a near-best coarse one).
    constexpr int kCoarse = 3;
    std::vector<std::tuple<int, int, double>> coarse;
    double coarse_best = -1;
    for (int t = -outward; t <= inward; t += kCoarse) {
      for (int b = -inward; b <= outward; b += kCoarse) {
        const double agreement = agreement_at(t * step, b * step);
        known[index(t, b)] = agreement;
        coarse.emplace_back(t, b, agreement);
        coarse_best = std::max(coarse_best, agreement);
      }
    }
    if (coarse_best < settings_.candidate_min_coarse_agreement) return out;
    for (const auto& [t, b, agreement] : coarse) {
      if (agreement < coarse_best - kCoarseTolerance) continue;
      for (int dt = -kCoarse + 1; dt < kCoarse; ++dt)
        for (int db = -kCoarse + 1; db < kCoarse; ++db)
          if (t + dt >= -outward && t + dt <= inward && b + db >= -inward && b + db <= outward)
            wanted[index(t + dt, b + db)] = 1;
    }
  }
  double best_agreement = -1;
  std::vector<std::pair<double, double>> best;
  std::vector<std::pair<std::pair<double, double>, double>> read_placings;  // candidates'
  for (int t = -outward; t <= inward; ++t) {
    for (int b = -inward; b <= outward; ++b) {
      // Detections move as a whole (their sides were found in the image); candidates' sides
      // independently.
      if ((!candidate && b != t) || !wanted[index(t, b)]) continue;
      const double agreement = candidate && !std::isnan(known[index(t, b)])
                                   ? known[index(t, b)]
                                   : agreement_at(t * step, b * step);
      if (agreement < 0) continue;
      if (candidate) read_placings.push_back({{t * step, b * step}, agreement});
      if (agreement > best_agreement + 1e-9) {
        best_agreement = agreement;
        best.clear();
      }
      if (agreement > best_agreement - 1e-9) best.emplace_back(t * step, b * step);
    }
  }
  if (best.empty()) return out;
  // The tied placing nearest their mean.
  double mt = 0, mb = 0;
  for (const auto& [t, b] : best) {
    mt += t / best.size();
    mb += b / best.size();
  }
  const auto nearest =
      std::min_element(best.begin(), best.end(), [&](const auto& x, const auto& y) {
        return std::hypot(x.first - mt, x.second - mb) < std::hypot(y.first - mt, y.second - mb);
      });
  out.shift_top = nearest->first;
  out.shift_bottom = nearest->second;
  out.cells = samples.read(out.shift_top, out.shift_bottom, book, read_options, scratch);
  out.read = true;
  const DecodeLimits family_limits = limits(family);
  out.decoded = books.decode(out.cells.bits, family_limits);
  if (candidate) {
    resolve_tied_placings(books, samples, read_options, best, family_limits,
                          settings_.candidate_min_security_bits, out);
    // The near-best placings include the tied ones, so their distinct readings are every reading
    // tried, and the choice pays for all of them. They vote also where the tied ones decode, but
    // with fewer chance-match bits than a candidate needs once their choice is paid for (an ULTRA
    // Puck 5 m from a grid of tag25h9: one square so, whose near-best placings read its id
    // securely).
    if (!out.decoded.accepted ||
        out.decoded.security_bits < settings_.candidate_min_security_bits) {
      std::vector<std::pair<double, double>> near;
      for (const auto& [placing, agreement] : read_placings)
        if (agreement > best_agreement - kNearTolerance - 1e-9) near.push_back(placing);
      if (near.size() > best.size())
        resolve_tied_placings(books, samples, read_options, near, family_limits,
                              settings_.candidate_min_security_bits, out);
    }
  }
  out.corners_px = samples.corners_at(out.shift_top, out.shift_bottom, image.geometry);
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
  const int errors = errors_against(*books_.at(d.family).all, r.cells.bits, d.id);
  return errors > limits(d.family).max_errors ? RingVerdict::kContradicted
                                              : RingVerdict::kUndecided;
}

namespace {

// Share of a candidate's margin cells brighter than the border next to them: a row of them may be
// missing where no ring crossed it (quiet_zone_fraction, detectors/aruco_detector.hpp).
constexpr double kMinCandidateMargin = 0.5;

// Candidates spanning fewer than this many samples a cell along the image's fine axis (its columns,
// unless they are the coarse one: CandidateSizes) are not read. The cells are read
// from the samples at their own azimuths and elevations, so 1.6 columns a cell still decode (a 40
// cm tag36h11 at 5 m on an OS1-64 at 1024 columns spans 13 columns: 25 of 50 seeds found, 12 with
// 2 pixels a cell; its 1 m tag at 12 m 21 of 30, 3 before), and with the map's id known 1.25 do
// (the 40 cm tag at 6 m, 10-11 pixels across: 8 of 10 seeds, 0 with 1.5 pixels a cell).
constexpr double kMinCandidatePixelsPerCell = 1.25;

// How far measured sides must move a weakly read candidate's for a second reading (pixels).
constexpr double kMinSideMovePx = 0.25;

// The largest distance between corresponding corners.
double moved_by(const std::array<Vec2, 4>& a, const std::array<Vec2, 4>& b) {
  double most = 0;
  for (int k = 0; k < 4; ++k) most = std::max(most, (a[k] - b[k]).norm());
  return most;
}

// The least box a candidate square of the narrowest supported family may have, in detector-image
// pixels. Along the fine axis it must span kMinCandidatePixelsPerCell samples a cell; along the
// coarse one (the rings on most spinning LiDARs, the columns where those are coarser) a sample
// spacing less: the binary image loses the border row or column no sample crossed, and the reader
// searches where those sides lie.
struct CandidateSizes {
  int min_cells = 1 << 30;
  double width_px_per_cell = 0, height_px_per_cell = 0;  // the least, along each axis
  double width_allowance_px = 0, height_allowance_px = 0;
  double min_width_px(int cells) const { return width_px_per_cell * cells - width_allowance_px; }
  double min_height_px(int cells) const { return height_px_per_cell * cells - height_allowance_px; }
};

CandidateSizes candidate_sizes(const std::map<std::string, FamilyCodeBooks>& books,
                               const ImageGeometry& detect_geometry, const ProjectedImage& image) {
  CandidateSizes sizes;
  for (const auto& entry : books)
    sizes.min_cells = std::min(sizes.min_cells, entry.second.all->border_width());
  // The detector-image rows a ring spans on average (square pixels stretch the rings apart).
  const double ring_spacing_px =
      static_cast<double>(detect_geometry.height) / std::max(1, image.geometry.height);
  if (columns_are_coarse(image.geometry)) {
    // Samples a cell along the rings' spacing (res_v: the mean on ring rows).
    sizes.width_px_per_cell =
        kMinCandidatePixelsPerCell * image.geometry.res_v / detect_geometry.res_h;
    sizes.height_px_per_cell = kMinCandidatePixelsPerCell * ring_spacing_px;
    sizes.width_allowance_px = 1;
  } else {
    sizes.width_px_per_cell = sizes.height_px_per_cell = kMinCandidatePixelsPerCell;
    sizes.height_allowance_px = ring_spacing_px;
  }
  return sizes;
}

}  // namespace

RingDecoder::Quads RingDecoder::candidate_quads(const cv::Mat& detect_gray,
                                                const ImageGeometry& detect_geometry,
                                                const ProjectedImage& image) const {
  if (books_.empty() || detect_gray.empty()) return {};
  const CandidateSizes sizes = candidate_sizes(books_, detect_geometry, image);
  return dark_quads(detect_gray, sizes.min_width_px(sizes.min_cells), sizes.min_cells,
                    sizes.min_height_px(sizes.min_cells));
}

void RingDecoder::read_weak_candidate_again(const std::string& family,
                                            const std::array<Vec2, 4>& corners_px,
                                            const ProjectedImage& image, const cv::Mat& intensity,
                                            RingRead& first) const {
  // The first reading's shifts and bits, before a better reading replaces it.
  const std::pair<double, double> first_shifts(first.shift_top, first.shift_bottom);
  const double first_bits = first.decoded.security_bits;
  int readings = 1;
  const auto read_again = [&](const std::array<Vec2, 4>& corners, double cost_bits,
                              std::optional<std::pair<double, double>> shifts) {
    RingRead again = read(family, corners, image, intensity, true, shifts);
    again.decoded.security_bits -= cost_bits;
    if (again.read && again.decoded.accepted &&
        again.decoded.security_bits > first.decoded.security_bits)
      first = std::move(again);
  };
  // First with the left and right sides where the rings cross the marker's mid level, when that
  // moves one of them by a quarter pixel or more (reading much the same placings again cost the
  // harness's cluttered scenes half as much time again). A second reading is a second chance to
  // match: it pays one bit.
  const auto measured =
      measured_side_columns(corners_px, image, intensity, first.cells.black, first.cells.white);
  if (measured && moved_by(*measured, corners_px) >= kMinSideMovePx) {
    ++readings;
    read_again(*measured, 1, std::nullopt);
  }
  // Only a first reading that already says more than chance is worth moving the sides for: in the
  // false-positive harness's cluttered scenes that kept 238 of 242 of the finds for a third of
  // the readings.
  const double step = settings_.candidate_side_step_px;
  if (!(step > 0) || first_bits < settings_.candidate_side_min_bits ||
      first.decoded.security_bits >= settings_.candidate_min_security_bits)
    return;
  // Then with each side moved a step either way, at the first reading's top and bottom shifts:
  // these readings differ in which columns fall in which cell, not in where the rows lie
  // (searching the shifts again for each, even a step either way of the first's, cost the
  // false-positive harness more for much the same finds). Each is one more chance to match: the
  // best pays log2 of every reading made, so the chance that any of them matches by chance stays
  // that of one.
  // Where the columns are the coarse axis the placings moved the left and right sides already:
  // the top and bottom ones are moved instead (rows are where columns are in the transposed quad).
  const bool rows = columns_are_coarse(image.geometry);
  const auto transposed = [](std::array<Vec2, 4> c) {
    for (Vec2& p : c) std::swap(p.x(), p.y());
    return c;
  };
  std::vector<std::array<Vec2, 4>> moved;
  for (int left = -1; left <= 1; ++left)
    for (int right = -1; right <= 1; ++right)
      if (left != 0 || right != 0)
        moved.push_back(
            rows ? transposed(sides_moved(transposed(corners_px), left * step, right * step))
                 : sides_moved(corners_px, left * step, right * step));
  const double cost_bits = std::log2(static_cast<double>(readings + moved.size()));
  for (const std::array<Vec2, 4>& corners : moved) read_again(corners, cost_bits, first_shifts);
}

void RingDecoder::decode_candidates(const cv::Mat& detect_gray,
                                    const ImageGeometry& detect_geometry,
                                    const ProjectedImage& image, const cv::Mat& intensity,
                                    const Quads& quads, std::vector<Detection>& out,
                                    const std::function<bool(const Vec2&)>& known) const {
  if (books_.empty() || detect_gray.empty()) return;
  const CandidateSizes sizes = candidate_sizes(books_, detect_geometry, image);
  const int min_cells = sizes.min_cells;
  const std::size_t before = out.size();
  // A full-circle image's columns one turn apart point the same way: a detection across the seam
  // has columns past the last one.
  const double turn = image.geometry.full_circle() ? image.geometry.columns_per_turn() : 0;
  // Covered by a detector's marker, or by one this pass decoded already (a square's nested
  // outlines, a square read again from the strip across the seam).
  const auto known_here = [&](const Vec2& centre) {
    if (known && known(centre)) return true;
    for (std::size_t i = before; i < out.size(); ++i)
      if (inside_convex(centre, out[i].corners_px)) return true;
    return false;
  };
  const auto known_at = [&](const Vec2& centre) {
    return known_here(centre) ||
           (turn > 0 && (known_here(centre + Vec2(turn, 0)) || known_here(centre - Vec2(turn, 0))));
  };
  const bool coarse_columns = columns_are_coarse(image.geometry);
  // Reads a dark quad whose corners are `corners` in `quad_gray` (the detector image, or the strip
  // across its seam) and `detect_corners` in the detector image's continuous coordinates.
  const auto read_quad = [&](const std::vector<Vec2>& corners, const cv::Mat& quad_gray,
                             const std::vector<Vec2>& detect_corners) {
    std::array<Vec2, 4> projected;
    for (int k = 0; k < 4; ++k)
      projected[k] = map_pixel(detect_corners[k], detect_geometry, image.geometry);
    move_hull_to_samples(image, projected);  // to where the samples lie
    if (known_at(0.25 * (projected[0] + projected[1] + projected[2] + projected[3]))) return;
    // The shorter of the top and bottom sides (the width) and of the left and right (the height).
    double narrowest = 1e9, lowest = 1e9;
    for (int k = 0; k < 4; ++k) {
      const Vec2 side = corners[(k + 1) % 4] - corners[k];
      double& shortest = std::abs(side.x()) >= std::abs(side.y()) ? narrowest : lowest;
      shortest = std::min(shortest, side.norm());
    }
    // Where the columns are coarse, the left and right sides squared to the top and bottom ones,
    // when that moves a corner by a quarter pixel or more.
    std::optional<std::array<Vec2, 4>> squared =
        coarse_columns
            ? squared_left_right_sides(projected, image.geometry.res_h, image.geometry.res_v)
            : std::nullopt;
    if (squared && moved_by(*squared, projected) < kMinSideMovePx) squared.reset();
    std::vector<std::pair<const std::string*, RingRead>> reads;
    for (const auto& [family, books] : books_) {
      // Each family's cells must be wide enough (dark_quads took the narrowest family's), to
      // half a pixel: where a side lies is known to about that (an OS1-64's 40 cm tag at 6 m is
      // 10 pixels across, 1.25 a cell, in some placings 9.98).
      // Along the coarse axis it may fall short by a sample spacing more (CandidateSizes: an
      // OS1-64's 1 m tag at 16 m is 10 pixels across and 5 rings, 9.3 pixels, tall).
      const int cells = books.all->border_width();
      if (narrowest < sizes.min_width_px(cells) - 0.5 || lowest < sizes.min_height_px(cells) - 0.5)
        continue;
      // Most dark blobs in a scene are not on white paper: a cheap look at the margin first.
      if (quiet_zone_fraction(quad_gray, corners, cells) < kMinCandidateMargin) continue;
      RingRead r = read(family, projected, image, intensity, true);
      const std::array<Vec2, 4>* read_at = &projected;  // the corners r was read at
      if (squared && !(r.read && r.decoded.accepted &&
                       r.decoded.security_bits >= settings_.candidate_min_security_bits)) {
        // The binary image's left and right outlines are ragged by a column, and a side fitted to
        // one leans (squared_left_right_sides); the placings move the sides, not turn them. A
        // second chance to match: it pays one bit.
        RingRead again = read(family, *squared, image, intensity, true);
        again.decoded.security_bits -= 1;
        if (again.read && (!r.read || (again.decoded.accepted &&
                                       (!r.decoded.accepted ||
                                        again.decoded.security_bits > r.decoded.security_bits)))) {
          r = std::move(again);
          read_at = &*squared;
        }
      }
      if (r.read && r.cells.levels_ok &&
          r.decoded.security_bits < settings_.candidate_min_security_bits)
        read_weak_candidate_again(family, *read_at, image, intensity, r);
      if (r.read) reads.emplace_back(&family, std::move(r));
    }
    // Every family whose fixed cells fit the square is one more try at a chance match: a
    // decoding pays for the others (measured: a DICT_4X4_50 square read through the original
    // ArUco dictionary's 7 x 7 cells matched id 193 on 24 of 25 bits, 12.0 bits, with seven
    // families asked for).
    const double family_bits =
        std::log2(static_cast<double>(std::max<std::size_t>(1, reads.size())));
    Detection best;
    for (const auto& [family, r] : reads) {
      const double security_bits = r.decoded.security_bits - family_bits;
      if (!r.decoded.accepted || security_bits < settings_.candidate_min_security_bits ||
          security_bits <= best.decision_margin)
        continue;
      best.family = *family;
      best.id = r.decoded.id;
      best.hamming = r.decoded.errors;
      best.decision_margin = security_bits;
      // Where the fixed cells read best: a side found in the binary image may lie up to half a
      // ring spacing off the square (ULTRA Puck, 1 m tag at 3 m: corners 38 mm off).
      best.corners_px.assign(r.corners_px.begin(), r.corners_px.end());
      std::rotate(best.corners_px.begin(), best.corners_px.begin() + r.decoded.quarter_turns,
                  best.corners_px.end());
    }
    if (best.id < 0) return;
    // OpenCV reports nested outlines of one square (inner and outer edge of the border), and the
    // strip across the seam repeats what lies near it: keep one decoding per id.
    bool seen = false;
    for (std::size_t i = before; i < out.size(); ++i)
      seen |= out[i].family == best.family && out[i].id == best.id;
    if (!seen) out.push_back(std::move(best));
  };
  const double min_width_px = sizes.min_width_px(min_cells),
               min_height_px = sizes.min_height_px(min_cells);
  std::vector<Vec2> corners, detect_corners;
  for (const std::array<Vec2, 4>& quad : quads) {
    corners.assign(quad.begin(), quad.end());
    push_edges_outward(corners);  // the sides run through the outermost pixel centres
    read_quad(corners, detect_gray, corners);
  }
  // A square across a full-circle image's seam is cut in two there, and one whose margin the
  // image's edge cuts fails the margin look: both are read from the strip across the seam
  // (seam_detection.hpp), which holds them whole.
  const std::optional<SeamStrip> cut = SeamStrip::of(detect_geometry);
  if (!cut || detect_gray.cols != detect_geometry.width) return;
  thread_local cv::Mat strip;
  cut->cut(detect_gray, strip);
  std::vector<Vec2*> keypoints;
  for (const std::array<Vec2, 4>& quad :
       dark_quads(strip, min_width_px, min_cells, min_height_px)) {
    corners.assign(quad.begin(), quad.end());
    push_edges_outward(corners);
    detect_corners = corners;
    keypoints.clear();
    for (Vec2& p : detect_corners) keypoints.push_back(&p);
    if (cut->place(keypoints) == SeamStrip::Place::kAway) continue;
    read_quad(corners, strip, detect_corners);
  }
}

}  // namespace iilfm::detail
