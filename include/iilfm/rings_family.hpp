// Concentric-ring markers ("rings:ring7h3", "rings:ring9h3"), shared by the detector back-end, the
// simulator's print and `iilfm marker print`. Header-only so that the simulator, which does not
// link the detection library, draws exactly what the detector decodes.
//
// A marker of outer diameter `size` is cut into bits + 3 annuli of equal width u = 1 / (bits + 3)
// of its radius, from the outside in: a black frame, a white guard ring, `bits` data rings (black =
// 1, the outermost data ring is the most significant bit) and a black centre disc. White paper of
// kRingsQuietZone radii surrounds it. The code is rotation-invariant by construction, so a marker
// gives one keypoint, its centre; its in-plane rotation is unknowable.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "iilfm/error.hpp"

namespace iilfm {

// White paper around the frame, in units of the marker's radius.
constexpr double kRingsQuietZone = 0.3;

struct RingsFamily {
  std::string name;  // "ring7h3"
  int bits = 0;      // data rings
  int min_distance = 0;
  std::vector<std::uint32_t> codes;  // id -> data rings, bit (bits - 1) = outermost

  int annuli() const { return bits + 3; }  // frame, guard, data rings, centre disc
  double ring_width() const { return 1.0 / annuli(); }
  // Whether annulus k (0 = frame, 1 = guard, 2.. = data, annuli() - 1 = centre) of `id` is black.
  bool annulus_black(int id, int k) const {
    if (k == 0 || k == annuli() - 1) return true;
    if (k == 1) return false;
    return (codes[static_cast<std::size_t>(id)] >> (bits - 1 - (k - 2))) & 1u;
  }
  // Whether the point at `r` radii from the centre is black (r >= 1: paper).
  bool black_at(int id, double r) const {
    if (r >= 1.0) return false;
    const int k = static_cast<int>((1.0 - r) * annuli());
    return annulus_black(id, k < annuli() ? k : annuli() - 1);
  }
};

namespace rings_detail {

inline int popcount(std::uint32_t v) {
  int n = 0;
  for (; v; v &= v - 1) ++n;
  return n;
}

// Black/white changes from the guard ring (white) through the data rings to the centre (black).
inline int transitions(std::uint32_t code, int bits) {
  int changes = 0, previous = 0;
  for (int k = bits - 1; k >= 0; --k) {
    const int bit = static_cast<int>((code >> k) & 1u);
    changes += bit != previous;
    previous = bit;
  }
  return changes + (previous != 1);
}

// The greedy lexicographic code of `bits`-bit words at Hamming distance >= `distance`, keeping
// only words with at least 3 black/white changes between guard and centre: a plain disc, a
// bull's-eye or a single ring (common shapes in the world) is no marker.
inline std::vector<std::uint32_t> lexicode(int bits, int distance) {
  std::vector<std::uint32_t> codes;
  for (std::uint32_t word = 0; word < (1u << bits); ++word) {
    if (transitions(word, bits) < 3) continue;
    bool far = true;
    for (std::uint32_t c : codes) far = far && popcount(c ^ word) >= distance;
    if (far) codes.push_back(word);
  }
  return codes;
}

}  // namespace rings_detail

// The families: ring7h3 (wide rings, for long range) and ring9h3 (more ids).
inline const std::vector<RingsFamily>& rings_families() {
  static const std::vector<RingsFamily> families = [] {
    std::vector<RingsFamily> list;
    for (int bits : {7, 9})
      list.push_back(
          {"ring" + std::to_string(bits) + "h3", bits, 3, rings_detail::lexicode(bits, 3)});
    return list;
  }();
  return families;
}

// The family named `name` (without "rings:"); InputError naming the known ones otherwise.
inline const RingsFamily& find_rings_family(const std::string& name) {
  std::string known;
  for (const RingsFamily& f : rings_families()) {
    if (f.name == name) return f;
    known += (known.empty() ? "" : ", ") + f.name;
  }
  throw InputError("unknown rings family '" + name + "' (known: " + known + ")");
}

// InputError unless `id` is one of the family's ids.
inline void check_rings_id(const RingsFamily& family, int id) {
  if (id < 0 || id >= static_cast<int>(family.codes.size()))
    throw InputError("marker id " + std::to_string(id) + " is outside rings:" + family.name +
                     " (0.." + std::to_string(family.codes.size() - 1) + ")");
}

}  // namespace iilfm
