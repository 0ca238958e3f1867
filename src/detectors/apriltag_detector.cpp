#include "apriltag_detector.hpp"

#include <apriltag/apriltag.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <utility>

#include "../cell_code_book.hpp"
#include "iilfm/apriltag_families.hpp"
#include "iilfm/error.hpp"
#include "search_regions.hpp"

namespace iilfm::detail {

namespace {

// How far outside its quad libapriltag reads to decode `family`, as a share of the quad's side:
// the white row half a cell beyond the border, or the centres of data bits kept outside it
// (tagStandard, tagCircle); doubled, because perspective stretches the far side of a quad.
double decode_reach(const apriltag_family_t& family) {
  const int border = std::max(family.width_at_border, 1);
  double cells = 0.5;
  for (std::uint32_t i = 0; i < family.nbits; ++i) {
    // The bit positions are signed values stored as unsigned (negative outside the border).
    const double x = static_cast<std::int32_t>(family.bit_x[i]) + 0.5;
    const double y = static_cast<std::int32_t>(family.bit_y[i]) + 0.5;
    cells = std::max({cells, -x, -y, x - border, y - border});
  }
  return 2.0 * cells / border;
}

// libapriltag keeps a family's decoding table (every code within `bits` bit errors: about 19 MB
// and 10-40 ms to build for tag36h11 at 2 bits) in the family object, and builds it when a family
// without one is added to a detector. One family object per (family, bits), with its table, serves
// every detector of the process, so a Pipeline made per scan (iilfm eval, Python) does not rebuild
// it. Detectors only read the table. The map is never freed: it stays reachable until exit.
apriltag_family_t* shared_family(const AprilTagFamilyEntry& entry, int bits) {
  static std::mutex mutex;
  static auto* families = new std::map<std::pair<std::string, int>, apriltag_family_t*>();
  const std::lock_guard<std::mutex> lock(mutex);
  apriltag_family_t*& family = (*families)[{entry.name, bits}];
  if (!family) {
    family = entry.create();
    // Built here, under the lock, by a detector that then lets go of the family without freeing
    // the table (apriltag_detector_destroy would: it frees the tables of the families it holds).
    apriltag_detector_t* builder = apriltag_detector_create();
    apriltag_detector_add_family_bits(builder, family, bits);
    zarray_clear(builder->tag_families);
    apriltag_detector_destroy(builder);
  }
  return family;
}

class AprilTagDetector final : public MarkerDetector {
 public:
  AprilTagDetector(const AprilTagFamilyEntry& entry, const AprilTagOptions& options)
      : entry_(entry), name_(std::string("apriltag:") + entry.name) {
    apriltag_family_t* own = entry_.create();  // for its bit count; the table comes shared
    const int bits = options.max_hamming >= 0
                         ? options.max_hamming
                         : default_max_hamming(static_cast<int>(own->h), own->ncodes,
                                               static_cast<int>(own->nbits));
    entry_.destroy(own);
    family_ = shared_family(entry_, bits);
    detector_ = apriltag_detector_create();
    detector_->quad_decimate = options.decimate;
    detector_->quad_sigma = options.sigma;
    // One thread always: libapriltag 3.3's worker pool can hand a worker a task from a task list
    // being reallocated (fixed upstream in 3.4); two threads crashed about one run of the Detect
    // benchmarks in a hundred. They only paid on whole-image searches (docs/performance.md).
    detector_->nthreads = 1;
    detector_->refine_edges = options.refine_edges;
    detector_->decode_sharpening = options.decode_sharpening;
    apriltag_detector_add_family_bits(detector_, family_, bits);  // the table exists: not rebuilt
    // Regions keep libapriltag's own thresholds only without decimation or blur, which change
    // the tiles' footprint (docs/detectors.md).
    use_regions_ = options.search_regions && options.decimate <= 1 && options.sigma == 0;
    decode_gray_ = options.decode_gray;
    // -1 where even an exact reading is too likely by chance (tag16h5: 1.8e-3 a quad).
    gray_max_hamming_ = bits_within_chance(family_->ncodes, static_cast<int>(family_->nbits), bits);
    rules_.reach = decode_reach(*family_);
    rules_.min_side_px = std::max(3, family_->width_at_border - 1);
    half_resolution_from_px_ = options.half_resolution_px_per_cell > 0
                                   ? options.half_resolution_px_per_cell * family_->width_at_border
                                   : std::numeric_limits<double>::infinity();
  }
  ~AprilTagDetector() override {
    zarray_clear(detector_->tag_families);  // the shared family and its table stay
    apriltag_detector_destroy(detector_);
  }
  AprilTagDetector(const AprilTagDetector&) = delete;
  AprilTagDetector& operator=(const AprilTagDetector&) = delete;

  const std::string& family() const override { return name_; }

  void detect(const cv::Mat& gray, std::vector<Detection>& out) override {
    detect_with(gray, rules_, out);
  }

  void detect_images(const DetectorImages& images, std::vector<Detection>& out) override {
    const cv::Mat& binary = images.image;
    CV_Assert(binary.type() == CV_8UC1);
    SearchRegionRules rules = rules_;
    rules.crossing_column = images.crossing_column;
    const bool gray_given = !images.gray.empty() && images.gray.size() == binary.size() &&
                            images.valid.size() == binary.size();
    if (!decode_gray_ || !gray_given) {
      detect_with(binary, rules, out);
      return;
    }
    detect_in_search_regions(
        binary, use_regions_, rules, crop_,
        [&](const cv::Mat& part, cv::Point origin, int least_outer_side_px) {
          const std::size_t before = out.size();
          detect_in(part, origin, least_outer_side_px, out);
          const cv::Rect box(origin, part.size());
          // Binary first, because gray alone lost sharp markers 1.7 pixels a cell wide that the
          // binary image decodes (ULTRA Puck, tag grid at 3.5 m). An image searched whole is a
          // cluttered one (or not binary): there libapriltag's own threshold on the gray pixels of
          // a busy real scan decoded texture into a code (a tag16h5 sliver on a Pandar64 scan)
          // where the binary image gives none.
          if (out.size() > before || box.size() == binary.size()) return;
          // Not where under a fifth of the pixels hold a value (a single rosette frame, 5-10 %):
          // the gray crop is then mostly its holes' binary classes, and trying it took `mid40-1`
          // detection from 0.8 to 1.6 ms. (An Avia's 1 m tag at 35 m, which the gray pixels decode,
          // has values in 26-32 % of its region.)
          if (cv::countNonZero(images.valid(box)) * 5 < box.area()) return;
          // The gray pixels, those without a value keeping their binary class (a hole in a white
          // wall stays white, not the gray image's black).
          images.gray(box).copyTo(gray_crop_);
          binary(box).copyTo(gray_crop_, images.valid(box) == 0);
          detect_in(gray_crop_, origin, least_outer_side_px, out);
          // A second try on a quad the binary pixels could not read keeps only readings unlikely by
          // chance (kMaxChanceMatch), whatever the family corrects: with the gray pixels unclipped,
          // a 17 cm DICT_ARUCO_ORIGINAL marker at 10 m from an Avia (1.4 pixels a cell) read as
          // tag16h5 id 15 without error (chance 1.8e-3).
          const auto by_chance = [&](const Detection& d) { return d.hamming > gray_max_hamming_; };
          out.erase(std::remove_if(out.begin() + static_cast<std::ptrdiff_t>(before), out.end(),
                                   by_chance),
                    out.end());
        });
  }

 private:
  void detect_with(const cv::Mat& gray, const SearchRegionRules& rules,
                   std::vector<Detection>& out) {
    CV_Assert(gray.type() == CV_8UC1);
    detect_in_search_regions(gray, use_regions_, rules, crop_,
                             [&](const cv::Mat& part, cv::Point origin, int least_outer_side_px) {
                               detect_in(part, origin, least_outer_side_px, out);
                             });
  }

  // Runs libapriltag on `image`, whose pixel (0, 0) is `origin` of the detector's input. Where
  // the region's outermost outlines span half_resolution_px_per_cell pixels a cell or more,
  // libapriltag finds its quads at half the resolution (a quarter of the pixels to threshold,
  // join and cluster); edge refinement and decoding still read every pixel.
  void detect_in(const cv::Mat& image, cv::Point origin, int least_outer_side_px,
                 std::vector<Detection>& out) {
    // libapriltag 3.3 reads outside images under 6 pixels wide or high (a one-row image from a
    // degenerate cloud crashed the fuzzer); upstream now returns nothing for them, and no tag fits.
    if (image.cols < 6 || image.rows < 6) return;
    // At half resolution the image libapriltag segments must still be 6 pixels each way.
    if (use_regions_)
      detector_->quad_decimate =
          least_outer_side_px >= half_resolution_from_px_ && image.cols >= 12 && image.rows >= 12
              ? 2.0f
              : 1.0f;
    image_u8_t view{image.cols, image.rows, static_cast<std::int32_t>(image.step[0]),
                    const_cast<std::uint8_t*>(image.ptr<std::uint8_t>())};
    zarray_t* found = apriltag_detector_detect(detector_, &view);
    for (int i = 0; i < zarray_size(found); ++i) {
      apriltag_detection_t* d = nullptr;
      zarray_get(found, i, &d);
      Detection det;
      det.family = name_;
      det.id = d->id;
      det.hamming = d->hamming;
      det.decision_margin = d->decision_margin;
      // libapriltag gives p[0..3] = bottom-left, bottom-right, top-right, top-left of the printed
      // tag, with pixel centres at i + 0.5; reorder to TL, TR, BR, BL and shift to centres at i.
      for (int k = 3; k >= 0; --k)
        det.corners_px.emplace_back(d->p[k][0] - 0.5 + origin.x, d->p[k][1] - 0.5 + origin.y);
      out.push_back(std::move(det));
    }
    apriltag_detections_destroy(found);
  }

  // A copy, not a reference into the families table, which a detector with static storage may
  // outlive.
  const AprilTagFamilyEntry entry_;
  std::string name_;
  apriltag_family_t* family_ = nullptr;  // shared_family's: never freed by the detector
  apriltag_detector_t* detector_ = nullptr;
  bool use_regions_ = false;
  bool decode_gray_ = true;
  int gray_max_hamming_ = 0;            // errors a reading of the gray pixels may have
  double half_resolution_from_px_ = 0;  // a region's least outer side for half resolution
  SearchRegionRules rules_;
  cv::Mat crop_;       // a search region's pixels, reused from call to call
  cv::Mat gray_crop_;  // its gray pixels, when the binary ones decoded nothing
};

}  // namespace

int default_max_hamming(int family_min_distance, std::uint32_t family_codes, int family_bits) {
  // Correcting 2 bits in families of tens of thousands of codes builds a lookup table that takes
  // seconds and hundreds of MB at start-up; 1 bit keeps them instant.
  const int cap = family_codes > 5000 ? 1 : 2;
  const int bits = std::clamp((family_min_distance - 1) / 2 - 2, 0, cap);
  // Measured: tag25h9 correcting 2 bits (chance 1.4e-3 a quad) decoded a marker in 1 of 100
  // marker-free room scans, 1 bit (1.1e-4) in none, and both found the same markers to 10 m.
  return std::max(0, bits_within_chance(family_codes, family_bits, bits));
}

int bits_within_chance(std::uint32_t family_codes, int family_bits, int most) {
  int bits = most;
  while (bits >= 0 && chance_match(family_codes, family_bits, bits) > kMaxChanceMatch) --bits;
  return bits;
}

double chance_match(std::uint32_t family_codes, int family_bits, int corrected) {
  return std::exp2(-chance_match_bits(family_codes, family_bits, corrected));
}

std::unique_ptr<MarkerDetector> make_apriltag_detector(const std::string& tag_family,
                                                       const AprilTagOptions& options) {
  const AprilTagFamilyEntry* entry = find_apriltag_family(tag_family);
  if (!entry) {
    throw InputError("unknown AprilTag family 'apriltag:" + tag_family +
                     "' (libapriltag ships tag16h5, tag25h9, tag36h10, tag36h11, tagCircle21h7, "
                     "tagCircle49h12, tagCustom48h12, tagStandard41h12, tagStandard52h13)");
  }
  return std::make_unique<AprilTagDetector>(*entry, options);
}

FamilyLayout apriltag_layout(const std::string& tag_family) {
  const AprilTagFamilyEntry* entry = find_apriltag_family(tag_family);
  if (!entry) throw InputError("unknown AprilTag family 'apriltag:" + tag_family + "'");
  apriltag_family_t* family = entry->create();
  FamilyLayout layout{family->width_at_border, family->total_width, static_cast<int>(family->h),
                      static_cast<int>(family->ncodes)};
  entry->destroy(family);
  return layout;
}

}  // namespace iilfm::detail
