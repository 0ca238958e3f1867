#include "iilfm/marker_map.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"
#include "iilfm/pose.hpp"

namespace iilfm {

namespace {

std::string fmt(double value) {
  std::ostringstream s;
  s.precision(4);
  s << value;
  return s.str();
}

Vec3 read_vec3(const YAML::Node& node, const std::string& what) {
  if (!node || !node.IsSequence() || node.size() != 3)
    throw InputError(what + " must be a list of 3 numbers");
  Vec3 v;
  for (int k = 0; k < 3; ++k) {
    try {
      v[k] = node[k].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(what + " must be a list of 3 numbers");
    }
    if (!std::isfinite(v[k])) throw InputError(what + " has a non-finite value");
  }
  return v;
}

// The corners of a marker given by `size` and `pose` (position + rpy_deg or quat_xyzw).
std::array<Vec3, 4> corners_from_pose(const YAML::Node& node) {
  const double size = node["size"].as<double>();
  if (!(size > 0) || !std::isfinite(size)) throw InputError("size must be a positive number");
  const YAML::Node pose = node["pose"];
  if (!pose || !pose.IsMap()) throw InputError("'size' needs a 'pose' with position and rotation");
  Isometry3 T = Isometry3::Identity();
  T.translation() = read_vec3(pose["position"], "pose.position");
  if (pose["rpy_deg"] && pose["quat_xyzw"])
    throw InputError("pose has both rpy_deg and quat_xyzw; give one");
  if (pose["rpy_deg"]) {
    T.linear() = rotation_from_rpy_deg(read_vec3(pose["rpy_deg"], "pose.rpy_deg"));
  } else if (pose["quat_xyzw"]) {
    const YAML::Node q = pose["quat_xyzw"];
    if (!q.IsSequence() || q.size() != 4) throw InputError("pose.quat_xyzw must be 4 numbers");
    Eigen::Quaterniond quat(q[3].as<double>(), q[0].as<double>(), q[1].as<double>(),
                            q[2].as<double>());
    if (!(quat.norm() > 1e-9) || !std::isfinite(quat.norm()))
      throw InputError("pose.quat_xyzw has zero or non-finite length");
    T.linear() = quat.normalized().toRotationMatrix();
  } else {
    throw InputError("pose needs rpy_deg or quat_xyzw");
  }
  std::array<Vec3, 4> corners = marker_frame_corners(size);
  for (Vec3& c : corners) c = T * c;
  return corners;
}

MapMarker parse_marker(const YAML::Node& node) {
  if (!node.IsMap()) throw InputError("each marker must be a mapping");
  MapMarker marker;
  if (!node["family"]) throw InputError("missing 'family'");
  marker.family = node["family"].as<std::string>();
  if (!node["id"]) throw InputError("missing 'id'");
  marker.id = node["id"].as<int>();
  if (node["corners"]) {
    const YAML::Node corners = node["corners"];
    if (!corners.IsSequence() || corners.size() != 4)
      throw InputError(
          "'corners' must list exactly 4 points (top-left, top-right, bottom-right, "
          "bottom-left), got " +
          std::to_string(corners.IsSequence() ? corners.size() : 0));
    for (int k = 0; k < 4; ++k)
      marker.corners_world[k] = read_vec3(corners[k], "corner " + std::to_string(k + 1));
  } else if (node["size"]) {
    marker.corners_world = corners_from_pose(node);
  } else {
    throw InputError("needs 'corners' or 'size' and 'pose'");
  }
  return marker;
}

void validate_geometry(MapMarker& marker, const MapTolerances& tol) {
  const auto& c = marker.corners_world;
  double edges[4], mean_edge = 0;
  for (int k = 0; k < 4; ++k) {
    edges[k] = (c[(k + 1) % 4] - c[k]).norm();
    mean_edge += edges[k] / 4;
  }
  if (!(mean_edge > 1e-6)) throw InputError("corners coincide");
  // Corners near the float limits overflow the edge lengths; every check below would then pass.
  if (!std::isfinite(mean_edge))
    throw InputError("corners are too far apart: their edge lengths overflow");
  for (int k = 0; k < 4; ++k) {
    if (std::abs(edges[k] - mean_edge) > tol.squareness * mean_edge)
      throw InputError("corners are not a square: edge " + std::to_string(k + 1) + " is " +
                       fmt(edges[k]) + " m, mean edge " + fmt(mean_edge) + " m");
  }
  const double diagonal = std::sqrt(2.0) * mean_edge;
  for (double d : {(c[2] - c[0]).norm(), (c[3] - c[1]).norm()}) {
    if (std::abs(d - diagonal) > tol.squareness * diagonal)
      throw InputError("corners are not a square: diagonal " + fmt(d) + " m, expected " +
                       fmt(diagonal) + " m (check the corner order)");
  }
  Vec3 centre = (c[0] + c[1] + c[2] + c[3]) / 4;
  Mat3 scatter = Mat3::Zero();
  for (const Vec3& p : c) scatter += (p - centre) * (p - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
  const Vec3 normal = eig.eigenvectors().col(0);
  double worst = 0;
  for (const Vec3& p : c) worst = std::max(worst, std::abs(normal.dot(p - centre)));
  if (!(worst <= tol.planarity_m))
    throw InputError("corners are not planar: a corner is " + fmt(worst * 1000) +
                     " mm off their plane (tolerance " + fmt(tol.planarity_m * 1000) + " mm)");
  marker.size = mean_edge;
}

}  // namespace

void MarkerMap::add(const MapMarker& input, const std::string& where, const MapTolerances& tol) {
  MapMarker marker = input;
  const std::string label = where + ": marker " + marker.key();
  try {
    const int ids = family_layout(marker.family).ids;  // throws for unknown families
    if (marker.id < 0 || (ids > 0 && marker.id >= ids))
      throw InputError("id not in the family (ids 0.." + std::to_string(ids - 1) + ")");
    validate_geometry(marker, tol);
  } catch (const InputError& e) {
    throw InputError(label + ": " + e.what());
  }
  if (find(marker.family, marker.id)) throw InputError(label + ": duplicate marker id");
  markers_.push_back(marker);
}

MarkerMap MarkerMap::load(const std::string& path, const MapTolerances& tolerances) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw file_error(path, "cannot open marker map");
  } catch (const YAML::Exception& e) {
    throw file_error(
        path, "not valid YAML: " + e.msg + " (line " + std::to_string(e.mark.line + 1) + ")");
  }
  if (!root.IsMap() || !root["markers"] || !root["markers"].IsSequence())
    throw file_error(path, "expected a top-level 'markers:' list");
  MarkerMap map;
  const YAML::Node markers = root["markers"];
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const std::string where = path + ": marker #" + std::to_string(i + 1);
    MapMarker marker;
    try {
      marker = parse_marker(markers[i]);
    } catch (const InputError& e) {
      throw InputError(where + ": " + e.what());
    } catch (const YAML::Exception& e) {
      throw InputError(where + ": " + e.msg);
    }
    map.add(marker, path + " (#" + std::to_string(i + 1) + ")", tolerances);
  }
  if (map.empty()) throw file_error(path, "marker map lists no markers");
  return map;
}

const MapMarker* MarkerMap::find(const std::string& family, int id) const {
  for (const MapMarker& m : markers_)
    if (m.id == id && m.family == family) return &m;
  return nullptr;
}

}  // namespace iilfm
