// Reads the YAML scene format of docs/simulator.md. Every problem names the file, the entry
// (e.g. "markers[2]") and what is wrong, since users write these files by hand.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "iilfm/error.hpp"
#include "iilfm/sim/marker_texture.hpp"
#include "iilfm/sim/scene_file.hpp"
#include "iilfm/sim/sensor_models.hpp"
#include "rpy.hpp"

namespace iilfm::sim {
namespace {

constexpr float kDefaultReflectivity = 60;  // matt paint, as the named scenes use

class SceneReader {
 public:
  explicit SceneReader(std::string source) : source_(std::move(source)) {}

  SceneSetup read(const YAML::Node& root) const {
    if (!root.IsMap()) fail("file", "expected a mapping with walls, markers and lidar");
    allow_keys(root, "file", {"lidar", "print", "walls", "boxes", "markers"});
    SceneSetup setup;
    read_lidar(root["lidar"], setup);
    if (const YAML::Node print = root["print"]) {
      allow_keys(print, "print", {"white", "black"});
      setup.scene.white_intensity = static_cast<float>(number(print, "white", "print", 120));
      setup.scene.black_intensity = static_cast<float>(number(print, "black", "print", 10));
    }
    for_each(root["walls"], "walls", [&](const YAML::Node& n, const std::string& where) {
      setup.scene.walls.push_back(read_wall(n, where));
    });
    const std::size_t explicit_walls = setup.scene.walls.size();  // markers refer to these
    for_each(root["boxes"], "boxes", [&](const YAML::Node& n, const std::string& where) {
      append_box(n, where, setup.scene.walls);
    });
    for_each(root["markers"], "markers", [&](const YAML::Node& n, const std::string& where) {
      setup.scene.markers.push_back(read_marker(n, where, setup.scene.walls, explicit_walls));
    });
    if (setup.scene.walls.empty() && setup.scene.markers.empty()) {
      fail("file", "the scene has no walls, boxes or markers");
    }
    return setup;
  }

  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw InputError(source_ + ": " + where + ": " + problem);
  }

 private:
  std::string source_;

  void allow_keys(const YAML::Node& map, const std::string& where,
                  const std::set<std::string>& known) const {
    for (const auto& entry : map) {
      const std::string key = entry.first.as<std::string>();
      if (known.count(key)) continue;
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      fail(where, "unknown key '" + key + "' (known: " + list + ")");
    }
  }

  template <typename Fn>
  void for_each(const YAML::Node& list, const std::string& what, Fn fn) const {
    if (!list) return;
    if (!list.IsSequence()) fail(what, "expected a list");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string where = what + "[" + std::to_string(i) + "]";
      if (!list[i].IsMap()) fail(where, "expected a mapping");
      fn(list[i], where);
    }
  }

  double number(const YAML::Node& map, const std::string& key, const std::string& where,
                std::optional<double> fallback = std::nullopt) const {
    const YAML::Node n = map[key];
    if (!n) {
      if (fallback) return *fallback;
      fail(where, "needs '" + key + "'");
    }
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(where, "'" + key + "' must be a number");
    }
    if (!std::isfinite(v)) fail(where, "'" + key + "' must be finite");
    return v;
  }

  double positive(const YAML::Node& map, const std::string& key, const std::string& where) const {
    const double v = number(map, key, where);
    if (!(v > 0)) fail(where, "'" + key + "' must be positive, got " + std::to_string(v));
    return v;
  }

  template <int N>
  Eigen::Matrix<double, N, 1> vector(const YAML::Node& map, const std::string& key,
                                     const std::string& where, bool required) const {
    Eigen::Matrix<double, N, 1> v = Eigen::Matrix<double, N, 1>::Zero();
    const YAML::Node n = map[key];
    if (!n) {
      if (required) fail(where, "needs '" + key + "'");
      return v;
    }
    const std::string expected =
        "'" + key + "' must be a list of " + std::to_string(N) + " numbers";
    if (!n.IsSequence() || n.size() != N) fail(where, expected);
    for (int i = 0; i < N; ++i) {
      try {
        v[i] = n[i].as<double>();
      } catch (const YAML::Exception&) {
        fail(where, expected);
      }
      if (!std::isfinite(v[i])) fail(where, expected);
    }
    return v;
  }

  std::string text(const YAML::Node& map, const std::string& key, const std::string& where) const {
    const YAML::Node n = map[key];
    if (!n) fail(where, "needs '" + key + "'");
    if (!n.IsScalar()) fail(where, "'" + key + "' must be a name");
    return n.as<std::string>();
  }

  Isometry3 pose(const YAML::Node& map, const std::string& position_key, const std::string& where,
                 bool position_required) const {
    Isometry3 T = Isometry3::Identity();
    T.translation() = vector<3>(map, position_key, where, position_required);
    T.linear() = rotation_from_rpy_deg(vector<3>(map, "rpy_deg", where, false));
    return T;
  }

  void read_lidar(const YAML::Node& lidar, SceneSetup& setup) const {
    if (!lidar) fail("lidar", "the file needs a 'lidar' entry with at least the sensor");
    if (!lidar.IsMap()) fail("lidar", "expected a mapping");
    allow_keys(lidar, "lidar", {"sensor", "position", "rpy_deg"});
    setup.sensor = text(lidar, "sensor", "lidar");
    try {
      sensor_model(setup.sensor);
    } catch (const InputError& e) {
      fail("lidar", e.what());
    }
    setup.T_world_lidar = pose(lidar, "position", "lidar", false);
  }

  Wall read_wall(const YAML::Node& n, const std::string& where) const {
    allow_keys(n, where, {"name", "centre", "rpy_deg", "width", "height", "reflectivity"});
    Wall w;
    w.T_world_wall = pose(n, "centre", where, true);
    w.width_m = positive(n, "width", where);
    w.height_m = positive(n, "height", where);
    w.reflectivity = static_cast<float>(number(n, "reflectivity", where, kDefaultReflectivity));
    return w;
  }

  void append_box(const YAML::Node& n, const std::string& where, std::vector<Wall>& walls) const {
    allow_keys(n, where, {"name", "centre", "size", "yaw_deg", "reflectivity"});
    const Vec3 centre = vector<3>(n, "centre", where, true);
    const Vec3 size = vector<3>(n, "size", where, true);
    if (!(size.minCoeff() > 0)) fail(where, "'size' must be three positive lengths");
    const float reflectivity =
        static_cast<float>(number(n, "reflectivity", where, kDefaultReflectivity));
    for (const Wall& face : box_walls(centre, size, number(n, "yaw_deg", where, 0), reflectivity)) {
      walls.push_back(face);
    }
  }

  MarkerSpec read_marker(const YAML::Node& n, const std::string& where,
                         const std::vector<Wall>& walls, std::size_t explicit_walls) const {
    allow_keys(n, where, {"family", "id", "size", "pose", "on_wall", "at", "angle_deg"});
    MarkerSpec m;
    m.family = text(n, "family", where);
    const double id = number(n, "id", where);
    if (id < 0 || id != std::floor(id)) fail(where, "'id' must be a whole number >= 0");
    m.id = static_cast<int>(id);
    m.size_m = positive(n, "size", where);
    try {
      render_marker_texture(m.family, m.id);  // an unknown family or id fails here, not later
    } catch (const InputError& e) {
      fail(where, e.what());
    }
    const bool by_pose = static_cast<bool>(n["pose"]), on_wall = static_cast<bool>(n["on_wall"]);
    if (by_pose == on_wall) fail(where, "give either 'pose' or 'on_wall' with 'at'");
    if (by_pose) {
      const YAML::Node p = n["pose"];
      const std::string pose_where = where + ".pose";
      if (!p.IsMap()) fail(pose_where, "expected a mapping with position and rpy_deg");
      allow_keys(p, pose_where, {"position", "rpy_deg"});
      if (n["at"] || n["angle_deg"]) fail(where, "'at' and 'angle_deg' go with 'on_wall'");
      m.T_world_marker = pose(p, "position", pose_where, true);
      return m;
    }
    const double index = number(n, "on_wall", where);
    if (index < 0 || index != std::floor(index) || index >= static_cast<double>(explicit_walls)) {
      fail(where, "'on_wall' must be the index of one of the " + std::to_string(explicit_walls) +
                      " walls (from 0)");
    }
    const Wall& wall = walls[static_cast<std::size_t>(index)];
    const Eigen::Vector2d at = vector<2>(n, "at", where, true);
    if (std::abs(at.x()) > wall.width_m / 2 || std::abs(at.y()) > wall.height_m / 2) {
      fail(where, "'at' lies off wall " + std::to_string(static_cast<int>(index)) +
                      " (its half-width and half-height are " + std::to_string(wall.width_m / 2) +
                      " and " + std::to_string(wall.height_m / 2) + " m)");
    }
    // Printed on the wall's front (its local +z side), upright along the wall's y, then turned.
    return marker_on_wall(wall, m.family, m.id, m.size_m, at.x(), at.y(),
                          number(n, "angle_deg", where, 0));
  }
};

}  // namespace

SceneSetup parse_scene_yaml(const std::string& text, const std::string& source) {
  const SceneReader reader(source);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    reader.fail("line " + std::to_string(e.mark.line + 1), "not valid YAML (" + e.msg + ")");
  }
  try {
    return reader.read(root);
  } catch (const YAML::Exception& e) {
    reader.fail("line " + std::to_string(e.mark.line + 1), e.msg);
  }
}

SceneSetup read_scene_yaml(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the scene file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_scene_yaml(text.str(), path);
}

}  // namespace iilfm::sim
