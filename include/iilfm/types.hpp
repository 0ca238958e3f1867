// Value types shared by every stage: the structure-of-arrays point cloud and small geometry
// aliases.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace iilfm {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Isometry3 = Eigen::Isometry3d;

// A LiDAR point cloud as structure of arrays: one contiguous column per field, so the projection
// streams through memory. `ring` and `time` are empty when the source has no such field.
struct PointCloud {
  std::vector<float> x, y, z;
  std::vector<float> intensity;
  std::vector<std::uint16_t> ring;  // laser channel, 0 = lowest beam where the driver says so
  std::vector<double> time;         // per-point timestamp in seconds (absolute or relative)

  std::size_t size() const { return x.size(); }
  bool empty() const { return x.empty(); }
  bool has_ring() const { return !ring.empty(); }
  bool has_time() const { return !time.empty(); }

  void reserve(std::size_t n, bool with_ring = false, bool with_time = false) {
    x.reserve(n);
    y.reserve(n);
    z.reserve(n);
    intensity.reserve(n);
    if (with_ring) ring.reserve(n);
    if (with_time) time.reserve(n);
  }
  void clear() {
    x.clear();
    y.clear();
    z.clear();
    intensity.clear();
    ring.clear();
    time.clear();
  }
  void push_back(float px, float py, float pz, float pi) {
    x.push_back(px);
    y.push_back(py);
    z.push_back(pz);
    intensity.push_back(pi);
  }
  Vec3 point(std::size_t i) const { return Vec3(x[i], y[i], z[i]); }
};

// One field of points held elsewhere: element i is data[i * stride] (stride in elements, not
// bytes), so a column of a PointCloud (stride 1) and a column of an interleaved N x K array
// (stride K) read alike.
template <typename T>
struct StridedColumn {
  const T* data = nullptr;
  std::ptrdiff_t stride = 1;

  T operator[](std::size_t i) const { return data[static_cast<std::ptrdiff_t>(i) * stride]; }
  explicit operator bool() const { return data != nullptr; }
};

// A read-only view of points the caller owns, in any layout: structure of arrays (a PointCloud) or
// rows of an interleaved array, as numpy hands them over. The projection and the plane lifting
// read points through it, so a caller's buffer is used without copying. The viewed memory must
// outlive every use of the view and of results that index into it.
struct PointView {
  StridedColumn<float> x, y, z, intensity;
  StridedColumn<std::uint16_t> ring;  // empty (null) when the source has no ring field
  std::size_t count = 0;

  PointView() = default;
  PointView(const PointCloud& cloud)  // NOLINT(google-explicit-constructor): a cloud is a view
      : x{cloud.x.data(), 1},
        y{cloud.y.data(), 1},
        z{cloud.z.data(), 1},
        intensity{cloud.intensity.data(), 1},
        ring{cloud.has_ring() ? cloud.ring.data() : nullptr, 1},
        count(cloud.size()) {}
  PointView(PointCloud&&) = delete;  // a view of a temporary would dangle

  std::size_t size() const { return count; }
  bool empty() const { return count == 0; }
  bool has_ring() const { return static_cast<bool>(ring); }
  Vec3 point(std::size_t i) const { return Vec3(x[i], y[i], z[i]); }
};

// What a reader saw while loading: every point in the file, and the ones it kept.
struct CloudStats {
  std::size_t points_in_file = 0;  // points the file declares and holds
  std::size_t valid_points = 0;    // points kept in the cloud
  std::size_t non_finite = 0;      // skipped: a coordinate or the intensity was NaN or Inf
  std::size_t zero = 0;            // skipped: x = y = z = 0 (drivers' "no return")
};

}  // namespace iilfm
