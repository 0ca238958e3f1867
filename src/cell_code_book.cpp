#include "cell_code_book.hpp"

#include <apriltag/apriltag.h>

#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>
#include <opencv2/aruco/dictionary.hpp>

#include "cpu_clones.hpp"
#include "iilfm/apriltag_families.hpp"
#include "iilfm/aruco_dictionaries.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"

namespace iilfm::detail {

namespace {

int popcount(std::uint64_t x) { return static_cast<int>(std::bitset<64>(x).count()); }

std::unique_ptr<CellCodeBook> apriltag_book(const std::string& name, int min_distance) {
  const AprilTagFamilyEntry* entry = find_apriltag_family(name);
  if (!entry) throw InputError("unknown AprilTag family 'apriltag:" + name + "'");
  std::unique_ptr<apriltag_family_t, void (*)(apriltag_family_t*)> family(entry->create(),
                                                                          entry->destroy);
  if (family->nbits > 64) return nullptr;
  // Fixed cells as libapriltag prints id 0; data cells where its bit table puts them.
  const AprilTagImage print = render_apriltag(name, 0);
  const int total = print.total_width;
  const int start = (total - print.width_at_border) / 2;
  std::vector<int> roles(static_cast<std::size_t>(total) * total);
  for (std::size_t i = 0; i < roles.size(); ++i)
    roles[i] = print.pixels[i] ? CellCodeBook::kFixedWhite : CellCodeBook::kFixedBlack;
  const int nbits = static_cast<int>(family->nbits);
  for (int k = 0; k < nbits; ++k) {
    // Reversed-border families store negative positions in the unsigned table.
    const int x = static_cast<int>(family->bit_x[k]) + start;
    const int y = static_cast<int>(family->bit_y[k]) + start;
    if (x < 0 || y < 0 || x >= total || y >= total) return nullptr;
    roles[static_cast<std::size_t>(y) * total + x] = k;
  }
  // libapriltag's bit k is the code's (nbits - 1 - k)-th bit, set = white.
  std::vector<std::uint64_t> codes(family->ncodes);
  for (std::uint32_t id = 0; id < family->ncodes; ++id) {
    std::uint64_t bits = 0;
    for (int k = 0; k < nbits; ++k)
      if ((family->codes[id] >> (nbits - 1 - k)) & 1u) bits |= std::uint64_t{1} << k;
    codes[id] = bits;
  }
  return std::make_unique<CellCodeBook>(total, print.width_at_border, std::move(roles), codes,
                                        min_distance);
}

std::unique_ptr<CellCodeBook> aruco_book(const std::string& name, int min_distance) {
  const ArucoDictionaryEntry* entry = find_aruco_dictionary(name);
  if (!entry) throw InputError("unknown ArUco dictionary 'aruco:" + name + "'");
  const cv::Ptr<cv::aruco::Dictionary> dict = cv::aruco::getPredefinedDictionary(entry->id);
  const int m = dict->markerSize;
  // drawMarker's one-cell black border inside iilfm's one-cell white margin (docs/detectors.md).
  const int total = m + 4;
  std::vector<int> roles(static_cast<std::size_t>(total) * total, CellCodeBook::kFixedBlack);
  for (int y = 0; y < total; ++y)
    for (int x = 0; x < total; ++x) {
      int& role = roles[static_cast<std::size_t>(y) * total + x];
      if (x == 0 || y == 0 || x == total - 1 || y == total - 1) role = CellCodeBook::kFixedWhite;
      if (x >= 2 && y >= 2 && x < total - 2 && y < total - 2) role = (y - 2) * m + (x - 2);
    }
  std::vector<std::uint64_t> codes(static_cast<std::size_t>(dict->bytesList.rows));
  for (int id = 0; id < dict->bytesList.rows; ++id) {
    const cv::Mat bits = cv::aruco::Dictionary::getBitsFromByteList(dict->bytesList.row(id), m);
    std::uint64_t code = 0;
    for (int k = 0; k < m * m; ++k)
      if (bits.at<std::uint8_t>(k / m, k % m)) code |= std::uint64_t{1} << k;
    codes[id] = code;
  }
  return std::make_unique<CellCodeBook>(total, m + 2, std::move(roles), codes, min_distance);
}

// log2 of the number of k-bit patterns within t of a given one.
double log2_ball(int k, int t) {
  double sum = 0, term = 1;
  for (int i = 0; i <= std::min(t, k); ++i) {
    sum += term;
    term = term * (k - i) / (i + 1);
  }
  return std::log2(sum);
}

}  // namespace

std::unique_ptr<CellCodeBook> CellCodeBook::for_family(const std::string& family) {
  const auto colon = family.find(':');
  if (colon == std::string::npos) return nullptr;
  const std::string backend = family.substr(0, colon), name = family.substr(colon + 1);
  if (backend != "apriltag" && backend != "aruco") return nullptr;
  const int min_distance = family_layout(family).min_distance;
  return backend == "apriltag" ? apriltag_book(name, min_distance) : aruco_book(name, min_distance);
}

CellCodeBook::CellCodeBook(int total_width, int border_width, std::vector<int> roles,
                           const std::vector<std::uint64_t>& upright_codes, int min_distance)
    : total_width_(total_width),
      border_width_(border_width),
      min_distance_(min_distance),
      roles_(std::move(roles)) {
  for (int role : roles_) bits_ = std::max(bits_, role + 1);
  // Where each data cell goes when the print is turned a quarter clockwise: (x, y) ->
  // (T - 1 - y, x). The families' data cells map onto data cells.
  std::vector<int> turn(static_cast<std::size_t>(bits_), -1);
  for (int y = 0; y < total_width_; ++y)
    for (int x = 0; x < total_width_; ++x) {
      const int k = cell_role(x, y);
      if (k < 0) continue;
      const int target = cell_role(total_width_ - 1 - y, x);
      if (target < 0) throw InputError("marker cells are not symmetric under quarter turns");
      turn[k] = target;
    }
  codes_[0] = upright_codes;
  for (int q = 1; q < 4; ++q) {
    codes_[q].resize(upright_codes.size());
    for (std::size_t id = 0; id < upright_codes.size(); ++id) {
      std::uint64_t turned = 0;
      for (int k = 0; k < bits_; ++k)
        if ((codes_[q - 1][id] >> k) & 1u) turned |= std::uint64_t{1} << turn[k];
      codes_[q][id] = turned;
    }
  }
}

CellCodeBook CellCodeBook::restricted_to(const std::vector<int>& ids) const {
  CellCodeBook out = *this;
  std::vector<bool> seen(static_cast<std::size_t>(codes()), false);
  for (auto& turned : out.codes_) turned.clear();
  for (int id : ids) {
    if (id < 0 || id >= codes())
      throw InputError("marker id " + std::to_string(id) + " is not in the family (ids 0.." +
                       std::to_string(codes() - 1) + ")");
    if (seen[static_cast<std::size_t>(id)]) continue;
    seen[static_cast<std::size_t>(id)] = true;
    for (int q = 0; q < 4; ++q) out.codes_[q].push_back(codes_[q][static_cast<std::size_t>(id)]);
    out.ids_.push_back(id_at(id));
  }
  return out;
}

// Compares the reading with all 4 turns of every code, twice (thousands of bit counts).
IILFM_POPCNT_CLONES DecodeResult decode_cells(const CellCodeBook& book, const BitReading& reading,
                                              const DecodeLimits& limits, int hypotheses) {
  DecodeResult best;
  const int known = popcount(reading.known);
  best.erasures = book.bits() - known;
  best.errors = std::numeric_limits<int>::max();
  int second = std::numeric_limits<int>::max();  // the next nearest code's errors
  int nearest = -1;                              // code number in the book
  for (int q = 0; q < 4; ++q)
    for (int index = 0; index < book.codes(); ++index) {
      const int errors = popcount((book.code(index, q) ^ reading.white) & reading.known);
      if (errors < best.errors) {
        second = best.errors;
        best.errors = errors;
        nearest = index;
        best.quarter_turns = q;
      } else {
        second = std::min(second, errors);
      }
    }
  if (nearest < 0) return best;
  best.reading_to_next = std::min(second, known);
  const std::uint64_t chosen = book.code(nearest, best.quarter_turns);
  best.distance_to_next = known;
  for (int q = 0; q < 4; ++q)
    for (int index = 0; index < book.codes(); ++index) {
      if (index == nearest && q == best.quarter_turns) continue;
      best.distance_to_next =
          std::min(best.distance_to_next, popcount((book.code(index, q) ^ chosen) & reading.known));
    }
  best.id = book.id_at(nearest);
  best.security_bits = chance_match_bits(book, known, best.errors, hypotheses);
  best.accepted = unambiguous(best, limits) && best.security_bits >= limits.min_security_bits;
  return best;
}

bool unambiguous(const DecodeResult& decoded, const DecodeLimits& limits) {
  return decoded.errors <= limits.max_errors &&
         2 * decoded.errors + limits.min_distance_margin <= decoded.distance_to_next;
}

double chance_match_bits(double codes, int known, int errors, int hypotheses) {
  // A random reading lands within `errors` of one of the 4 N candidates with probability
  // hypotheses * 4 N * ball(known, errors) / 2^known.
  return known - std::log2(4.0 * codes * std::max(1, hypotheses)) - log2_ball(known, errors);
}

double chance_match_bits(const CellCodeBook& book, int known, int errors, int hypotheses) {
  return chance_match_bits(book.codes(), known, errors, hypotheses);
}

int errors_against(const CellCodeBook& book, const BitReading& reading, int id) {
  return popcount((book.code(id, 0) ^ reading.white) & reading.known);
}

}  // namespace iilfm::detail
