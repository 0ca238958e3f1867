// Internal: the scene moved into the LiDAR frame as flat rectangles, and rays cast from the
// LiDAR origin (or, for a moving sensor, from where the LiDAR is at the beam's time) against them.
#pragma once

#include <vector>

#include "iilfm/sim/marker_texture.hpp"
#include "iilfm/sim/scene.hpp"
#include "iilfm/types.hpp"

namespace iilfm::sim {

struct RayHit {
  double range = 0;  // distance from the LiDAR origin along the unit ray
  float intensity = 0;
  int marker = -1;               // index into Scene::markers when the ray hit a printed sheet
  bool in_black_square = false;  // inside the marker's outer black square
  bool on_black_print = false;   // landed on a black cell of a printed marker
};

class SceneRaycaster {
 public:
  // Renders each distinct (family, id) once. InputError for markers the simulator cannot print.
  // With `raw_reference_m` > 0 a hit's intensity is the raw return strength, reflectivity x
  // cos(incidence) x (raw_reference_m / range)^2 (SimOptions::IntensityModel::kRaw).
  SceneRaycaster(const Scene& scene, const Isometry3& T_lidar_world, double raw_reference_m = 0);

  // Nearest surface along `direction` (unit, LiDAR frame) from the LiDAR origin; false if none.
  bool cast(const Vec3& direction, RayHit* hit) const {
    return cast_from(Vec3::Zero(), direction, hit);
  }

  // The same from `origin` (LiDAR frame). Off the origin the per-sheet cones do not apply, so
  // every sheet is tested.
  bool cast_from(const Vec3& origin, const Vec3& direction, RayHit* hit) const;

 private:
  struct Rectangle {
    Vec3 centre, x_axis, y_axis, normal;
    double half_width = 0, half_height = 0;
  };
  struct Sheet {  // a printed marker: its whole image, quiet zone included
    Rectangle rect;
    // Cone from the origin around the sheet: rays outside it cannot hit, one dot product tells.
    Vec3 towards_centre = Vec3::UnitX();
    double cos_cone = -1;
    int texture = 0;
    double cell_m = 0, half_black_m = 0;
  };

  // Ray parameter and in-plane coordinates of a hit on `r`, or false when the ray misses it.
  static bool intersect(const Rectangle& r, const Vec3& origin, const Vec3& direction,
                        bool front_only, double* range, double* local_x, double* local_y);
  bool on_black_cell(const Sheet& sheet, double local_x, double local_y) const;

  std::vector<Rectangle> walls_;
  std::vector<float> wall_reflectivity_;
  std::vector<Sheet> sheets_;
  std::vector<MarkerTexture> textures_;
  float white_ = 0, black_ = 0;
  double raw_reference_m_ = 0;
};

}  // namespace iilfm::sim
