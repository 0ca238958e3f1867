// Spherical projection of a point cloud into an intensity image and a range image (paper Sec.
// III-A).
//
// Orientation: the image looks like a picture taken from the LiDAR (world left = image left, up =
// up), so u = u0 - azimuth / res_h and v = v0 - elevation / res_v. Pixel (col, row) has its centre
// at the continuous coordinates (u, v) = (col, row), the OpenCV convention.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "iilfm/huge_page_allocator.hpp"
#include "iilfm/types.hpp"

namespace iilfm {

// The mapping between directions and continuous image coordinates, and its exact inverse.
// Columns are uniform in azimuth. Rows are uniform in elevation, or, for a spinning LiDAR projected
// ring by ring, follow a table of ring elevations (piecewise linear between row centres, so the
// mapping stays continuous, monotone and exactly invertible).
struct ImageGeometry {
  int width = 0, height = 0;
  double res_h = 0, res_v = 0;        // radians per pixel (res_v: mean row spacing for ring rows)
  double u0 = 0, v0 = 0;              // image coordinates of azimuth 0 / elevation 0 (uniform rows)
  std::vector<double> row_elevation;  // ring rows: each row's elevation, strictly decreasing

  bool ring_rows() const { return !row_elevation.empty(); }
  Vec2 pixel_of_angles(double azimuth, double elevation) const {
    return Vec2(u0 - azimuth / res_h, v_of_elevation(elevation));
  }
  Vec2 pixel_of_point(const Vec3& p) const;
  double azimuth_of_u(double u) const { return (u0 - u) * res_h; }
  double elevation_of_v(double v) const {
    return row_elevation.empty() ? (v0 - v) * res_v : table_elevation_of_v(v);
  }
  double v_of_elevation(double elevation) const {
    return row_elevation.empty() ? v0 - elevation / res_v : table_v_of_elevation(elevation);
  }
  Vec3 ray(double u, double v) const;  // unit direction through continuous image coordinates
  Vec3 ray(const Vec2& uv) const { return ray(uv.x(), uv.y()); }
  bool contains_pixel(int col, int row) const {
    return col >= 0 && row >= 0 && col < width && row < height;
  }
  // Columns of one full turn of azimuth (not always a whole number: 360 / 0.352 = 1022.7).
  double columns_per_turn() const { return 2 * M_PI / res_h; }
  // True when the columns cover every azimuth: then a column past the last one (or before the
  // first) continues the image on the other side of the azimuth seam.
  bool full_circle() const { return res_h > 0 && width >= columns_per_turn() - 0.5; }
  // The image column whose direction is nearest that of column `col`, which may lie one turn
  // off the image in a full-circle image; `col` itself otherwise.
  // Columns a u at or past the last column's right edge wraps back by: one turn in a
  // full-circle image, 0 otherwise (then such a u lies outside the image).
  int wrapping_columns() const {
    return full_circle() ? static_cast<int>(std::lround(columns_per_turn())) : 0;
  }
  int wrap_column(int col) const {
    if ((col >= 0 && col < width) || !full_circle()) return col;  // the common case first
    const int turn = static_cast<int>(std::lround(columns_per_turn()));
    return col < 0 ? col + turn : col - turn;
  }

 private:
  double table_elevation_of_v(double v) const;
  double table_v_of_elevation(double elevation) const;
};

// An angular window in radians (azimuth grows to the left, elevation up).
struct AngularBounds {
  double azimuth_min = 0, azimuth_max = 0;
  double elevation_min = 0, elevation_max = 0;
};

// How one pixel's value is formed when several points fall into it.
enum class CollisionPolicy {
  kMean,     // mean range and intensity: unbiased under range noise (default)
  kNearest,  // range and intensity of the nearest point (a z-buffer; biased towards the sensor)
};

// How image rows are laid out.
enum class RowLayout {
  kUniform,  // rows res_v apart in elevation (the paper's projection; any LiDAR)
  // One row per ring of a spinning LiDAR, from the ring field or the elevation clusters; falls
  // back to uniform rows when the cloud shows no ring structure.
  kRings,
};

struct ProjectionOptions {
  double res_h_deg = 0.05;
  double res_v_deg = 0.05;  // uniform rows only
  RowLayout rows = RowLayout::kUniform;
  // When set and the cloud lies inside it, the image covers this window, so every frame of a
  // sensor has the same image size; otherwise the cloud's own angular extent is used.
  std::optional<AngularBounds> field_of_view;
  CollisionPolicy collision = CollisionPolicy::kMean;
  std::size_t max_pixels = 50'000'000;  // refuse absurd images (e.g. a tiny resolution typo)
  // Threads for the per-point and per-pixel passes of large clouds and images (at least 32k
  // points or 64k pixels a thread; at most 64). The images are the same for any count.
  int threads = 1;
  // Ring rows: record where each pixel's sample lies when a ring fires off the column grid
  // (ProjectedImage::column_offset; docs/pipeline.md, "Samples off the column grid").
  bool column_offsets = true;
};

struct ProjectedImage {
  ImageGeometry geometry;
  cv::Mat intensity;  // CV_32F mean (or nearest) intensity; 0 where unobserved
  cv::Mat range;      // CV_32F range in metres; 0 where unobserved
  cv::Mat mask;       // CV_8U 255 where observed, 0 where no point fell
  // CV_32S index of a point in the pixel, -1 where unobserved: its only point where count is 1
  // (what lifting reads); with several, the last in the cloud's order (the nearest with
  // CollisionPolicy::kNearest; WindowProjector gives -1 there).
  cv::Mat index;
  cv::Mat count;  // CV_32S number of points in the pixel
  // Ring rows whose samples lie off the column grid (a spinning LiDAR's firing stagger, its
  // encoder's phase): CV_32F, where each single-point pixel's sample lies, in columns right of its
  // centre (0 for other pixels). Empty when every ring row lies within 0.05 columns of the grid,
  // and for uniform rows.
  cv::Mat column_offset;
  std::size_t points_projected = 0;
  std::string row_source = "uniform";  // "uniform", "ring field" or "elevation clusters"
  // A new value with every projection written into this image, so an incremental projector can
  // tell whether the image still holds its own last output.
  std::uint64_t stamp = 0;

  bool observed(int col, int row) const { return mask.at<std::uint8_t>(row, col) != 0; }
};

// A process-wide unique value for ProjectedImage::stamp.
std::uint64_t next_projection_stamp();

// The angular extent of a cloud (points at the origin are ignored).
AngularBounds angular_extent(const PointCloud& cloud);

// Image geometry covering `bounds` at the given resolution.
ImageGeometry geometry_for_bounds(const AngularBounds& bounds, double res_h, double res_v);

// InputError naming the size and the limit when `g` has more than `max_pixels` pixels.
void require_image_within(const ImageGeometry& g, std::size_t max_pixels);

// Projects clouds, reusing its buffers from frame to frame.
class SphericalProjector {
 public:
  explicit SphericalProjector(ProjectionOptions options);

  // Fills `out` (buffers are reused when sizes match). InputError if the image would be too large.
  void project(const PointCloud& cloud, ProjectedImage& out);
  // The same over points in any layout (e.g. a caller's interleaved array), without copying them.
  void project(const PointView& points, ProjectedImage& out);

  const ProjectionOptions& options() const { return options_; }

 private:
  // Everything binning touches for one pixel, in 16 bytes (four per cache line, none straddling
  // two), so a scattered point order (the Livox rosette) costs one cache miss per point.
  struct PixelAccumulator {
    float range_sum, intensity_sum;
    std::int32_t index;   // the last point binned (with the nearest policy: the nearest one)
    std::uint32_t count;  // points in the pixel
  };
  static_assert(sizeof(PixelAccumulator) == 16, "four accumulators per cache line");

  // Accumulators per image row: the width rounded up to whole cache lines, plus one line when
  // that count is even. A row whose size is a multiple of 4 KB (2048 or 1024 columns) would map
  // every row of a column to the same cache sets, and a spinning sweep bins column by column.
  static std::size_t accumulator_row_stride(int width);

  // Pass 4: rows [first_row, end_row) of accumulators (`stride` apart) turned into the images'
  // rows (`width` apart), and cleared.
  static void write_images(PixelAccumulator* pixels, int first_row, int end_row, int width,
                           std::size_t stride, bool nearest, float* range, float* intensity,
                           std::uint8_t* mask, std::int32_t* index, std::int32_t* count);

  ProjectionOptions options_;
  std::vector<float> azimuth_, elevation_, range_;
  // Each point's accumulator (row * accumulator_row_stride + column), -1 when not in the image.
  std::vector<std::int32_t> pixel_;
  std::vector<std::uint16_t> ring_copy_;  // a strided ring field, made contiguous for pass 2
  // Read in scattered order (a rosette revisits a spot every few frames): huge pages spare the
  // TLB misses.
  std::vector<PixelAccumulator, detail::HugePageAllocator<PixelAccumulator>> pixels_;
  bool pixels_clear_ = true;  // every accumulator is zero (pass 4 leaves them so)
};

}  // namespace iilfm
