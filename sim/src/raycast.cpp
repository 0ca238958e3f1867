// Ray casting against a handful of rectangles: a plain loop beats any acceleration structure at
// this scale (a few walls and tens of markers).
#include "raycast.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace iilfm::sim {
namespace {

// A sheet printed flush on a wall lies in the wall's plane; it wins ties up to this distance.
constexpr double kFlushTolerance = 1e-6;

}  // namespace

SceneRaycaster::SceneRaycaster(const Scene& scene, const Isometry3& T_lidar_world,
                               double raw_reference_m)
    : white_(scene.white_intensity),
      black_(scene.black_intensity),
      raw_reference_m_(raw_reference_m) {
  auto to_lidar = [&](const Isometry3& T_world_local, double width, double height) {
    const Isometry3 T = T_lidar_world * T_world_local;
    Rectangle r;
    r.centre = T.translation();
    r.x_axis = T.linear().col(0);
    r.y_axis = T.linear().col(1);
    r.normal = T.linear().col(2);
    r.half_width = width / 2;
    r.half_height = height / 2;
    return r;
  };
  for (const Wall& wall : scene.walls) {
    walls_.push_back(to_lidar(wall.T_world_wall, wall.width_m, wall.height_m));
    wall_reflectivity_.push_back(wall.reflectivity);
  }
  std::map<std::pair<std::string, int>, int> texture_of;
  for (const MarkerSpec& m : scene.markers) {
    const auto key = std::make_pair(m.family, m.id);
    auto it = texture_of.find(key);
    if (it == texture_of.end()) {
      textures_.push_back(render_marker_texture(m.family, m.id));
      it = texture_of.emplace(key, static_cast<int>(textures_.size()) - 1).first;
    }
    const MarkerTexture& texture = textures_[it->second];
    Sheet sheet;
    sheet.texture = it->second;
    sheet.cell_m = m.size_m / texture.width_at_border;
    sheet.half_black_m = m.size_m / 2;
    const double printed = sheet.cell_m * texture.total_width;
    sheet.rect = to_lidar(m.T_world_marker, printed, printed);
    const double distance = sheet.rect.centre.norm(), reach = printed / std::sqrt(2.0);
    if (distance > reach) {
      sheet.towards_centre = sheet.rect.centre / distance;
      sheet.cos_cone = std::cos(std::asin(reach / distance));
    }
    sheets_.push_back(sheet);
  }
}

bool SceneRaycaster::intersect(const Rectangle& r, const Vec3& origin, const Vec3& direction,
                               bool front_only, double* range, double* local_x, double* local_y) {
  const double facing = r.normal.dot(direction);
  if (facing == 0 || (front_only && facing > 0)) return false;
  const double t = r.normal.dot(r.centre - origin) / facing;
  if (t <= 0) return false;
  const Vec3 offset = origin + t * direction - r.centre;
  const double lx = r.x_axis.dot(offset), ly = r.y_axis.dot(offset);
  if (std::abs(lx) > r.half_width || std::abs(ly) > r.half_height) return false;
  *range = t;
  *local_x = lx;
  *local_y = ly;
  return true;
}

bool SceneRaycaster::on_black_cell(const Sheet& sheet, double local_x, double local_y) const {
  const MarkerTexture& texture = textures_[sheet.texture];
  const int last = texture.total_width - 1;
  // Image column grows to the marker's right, row grows downwards from the top edge.
  int col = static_cast<int>(std::floor(local_x / sheet.cell_m + 0.5 * texture.total_width));
  int row = static_cast<int>(std::floor(0.5 * texture.total_width - local_y / sheet.cell_m));
  col = col < 0 ? 0 : (col > last ? last : col);  // a hit exactly on the outer edge
  row = row < 0 ? 0 : (row > last ? last : row);
  return texture.is_black(row, col);
}

bool SceneRaycaster::cast_from(const Vec3& origin, const Vec3& direction, RayHit* hit) const {
  const bool at_origin = origin.isZero(0);
  double best = INFINITY, range, lx, ly;
  double cos_incidence = 1;
  bool found = false;
  for (std::size_t i = 0; i < walls_.size(); ++i) {
    if (intersect(walls_[i], origin, direction, false, &range, &lx, &ly) && range < best) {
      best = range;
      hit->intensity = wall_reflectivity_[i];
      cos_incidence = std::abs(walls_[i].normal.dot(direction));
      found = true;
    }
  }
  hit->marker = -1;
  hit->in_black_square = false;
  hit->on_black_print = false;
  for (std::size_t i = 0; i < sheets_.size(); ++i) {
    const Sheet& sheet = sheets_[i];
    if (at_origin && direction.dot(sheet.towards_centre) < sheet.cos_cone) continue;
    if (intersect(sheet.rect, origin, direction, true, &range, &lx, &ly) &&
        range < best + kFlushTolerance) {
      best = std::min(best, range);
      hit->on_black_print = on_black_cell(sheet, lx, ly);
      hit->intensity = hit->on_black_print ? black_ : white_;
      hit->marker = static_cast<int>(i);
      hit->in_black_square =
          std::abs(lx) <= sheet.half_black_m && std::abs(ly) <= sheet.half_black_m;
      cos_incidence = std::abs(sheet.rect.normal.dot(direction));
      found = true;
    }
  }
  hit->range = best;
  if (found && raw_reference_m_ > 0) {
    const double falloff = raw_reference_m_ / best;
    hit->intensity = static_cast<float>(hit->intensity * cos_incidence * falloff * falloff);
  }
  return found;
}

}  // namespace iilfm::sim
