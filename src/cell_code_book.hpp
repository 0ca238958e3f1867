// A square marker family as a grid of printed cells (fixed black, fixed white or a data bit) and
// its codes, and a decoder that reads codes with unknown (erased) bits. Used to decode markers from
// the rings that actually crossed them (ring_cell_reader.hpp), where a spinning LiDAR leaves cell
// rows unsampled.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace iilfm::detail {

class CellCodeBook {
 public:
  static constexpr int kFixedBlack = -1;
  static constexpr int kFixedWhite = -2;

  // The book of an AprilTag ("apriltag:tag36h11") or ArUco ("aruco:DICT_4X4_50") family; null
  // for other back-ends (boards, rings). InputError for unknown families.
  static std::unique_ptr<CellCodeBook> for_family(const std::string& family);

  // Cells of the printed image (white margin included), row-major, row 0 at the top of the
  // printed marker: kFixedBlack, kFixedWhite, or the data bit's index.
  int total_width() const { return total_width_; }
  int border_width() const { return border_width_; }
  // Cell index (in the printed image) of the black square's first cell row and column.
  int border_start() const { return (total_width_ - border_width_) / 2; }
  int cell_role(int col, int row) const { return roles_[row * total_width_ + col]; }
  // The same by row-major cell index (row * total_width + col).
  int cell_role(int index) const { return roles_[index]; }
  int bits() const { return bits_; }
  int codes() const { return static_cast<int>(codes_[0].size()); }
  int min_distance() const { return min_distance_; }
  // Code number `index` as read in a frame turned by `quarter_turns` clockwise quarter turns: bit
  // k set when data cell k of that frame is white. In a family's book the index is the id.
  std::uint64_t code(int index, int quarter_turns) const { return codes_[quarter_turns][index]; }
  // The marker id of code number `index`.
  int id_at(int index) const { return ids_.empty() ? index : ids_[index]; }

  // The same cells with the codes of `ids` alone (code numbers of this book, which in a family's
  // book are the ids; InputError for one out of range), numbered in the order given.
  CellCodeBook restricted_to(const std::vector<int>& ids) const;

  // Builds a book from the cell roles (total_width^2) and each id's data bits (bit k = data cell
  // k is white) as printed upright. Public for tests.
  CellCodeBook(int total_width, int border_width, std::vector<int> roles,
               const std::vector<std::uint64_t>& upright_codes, int min_distance);

 private:
  int total_width_, border_width_, bits_ = 0, min_distance_;
  std::vector<int> roles_;
  std::array<std::vector<std::uint64_t>, 4> codes_;
  std::vector<int> ids_;  // id of each code; empty: the index
};

// Data bits read from a marker: bit k of `white` is data cell k's colour, valid where `known`.
struct BitReading {
  std::uint64_t white = 0, known = 0;
};

struct DecodeLimits {
  int max_errors = 0;  // misread bits tolerated among the known ones
  // The best code must be at least this many bits further from every other code (and rotation)
  // on the known bits than twice its errors: 2 t + margin <= that distance.
  int min_distance_margin = 2;
  // log2 of the chance that a random reading matches some code this well must be at most
  // -min_security_bits (counting every code, rotation and hypothesis tried).
  double min_security_bits = 10;
};

struct DecodeResult {
  bool accepted = false;
  int id = -1, quarter_turns = 0;
  int errors = 0, erasures = 0;
  // Fewest known bits in which another code (any rotation) differs from the best one.
  int distance_to_next = 0;
  // Fewest known bits in which another code (any rotation) differs from the reading: at least
  // distance_to_next - errors.
  int reading_to_next = 0;
  double security_bits = 0;
};

// The code nearest `reading` over every id and rotation; accepted when within the limits.
// `hypotheses`: how many readings of the same marker the caller tries (each is a chance to match
// by accident).
DecodeResult decode_cells(const CellCodeBook& book, const BitReading& reading,
                          const DecodeLimits& limits, int hypotheses = 1);

// Whether `decoded` lies within the errors and the distance to the next code that `limits` allow:
// decode_cells accepts it when it also has the chance-match bits.
bool unambiguous(const DecodeResult& decoded, const DecodeLimits& limits);

// DecodeResult::security_bits of a reading with `known` bits matching a code but for `errors`:
// -log2 of the chance that a random reading matches some code (any id and turn) that well, over
// `hypotheses` readings tried.
double chance_match_bits(const CellCodeBook& book, int known, int errors, int hypotheses = 1);
// The same for any family of `codes` codes (AprilTag's bound on corrected bits uses it too).
double chance_match_bits(double codes, int known, int errors, int hypotheses = 1);

// Known bits of `reading` that differ from code `id` read upright (rotation 0), in a family's
// book (not a restricted one).
int errors_against(const CellCodeBook& book, const BitReading& reading, int id);

}  // namespace iilfm::detail
