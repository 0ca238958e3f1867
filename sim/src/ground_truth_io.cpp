// Ground truth as JSON: poses as 4x4 row-major matrices, corners as [x, y, z] rows.
#include "iilfm/sim/ground_truth_io.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>

#include "iilfm/error.hpp"

namespace iilfm::sim {
namespace {

using json = nlohmann::ordered_json;  // keeps the fields in the order written

bool is_flat_array(const json& value) {
  if (!value.is_array()) return false;
  for (const json& element : value) {
    if (element.is_structured()) return false;
  }
  return true;
}

// Like json::dump(2), but arrays of numbers stay on one line: a 4x4 pose reads as four rows.
void write_json(std::ostream& out, const json& value, int indent) {
  const std::string pad(indent + 2, ' ');
  if (value.is_object() && !value.empty()) {
    out << "{\n";
    std::size_t i = 0;
    for (auto it = value.begin(); it != value.end(); ++it, ++i) {
      out << pad << json(it.key()).dump() << ": ";
      write_json(out, it.value(), indent + 2);
      out << (i + 1 < value.size() ? ",\n" : "\n");
    }
    out << std::string(indent, ' ') << "}";
  } else if (value.is_array() && !value.empty() && !is_flat_array(value)) {
    out << "[\n";
    for (std::size_t i = 0; i < value.size(); ++i) {
      out << pad;
      write_json(out, value[i], indent + 2);
      out << (i + 1 < value.size() ? ",\n" : "\n");
    }
    out << std::string(indent, ' ') << "]";
  } else if (is_flat_array(value)) {
    out << "[";
    for (std::size_t i = 0; i < value.size(); ++i) out << (i ? ", " : "") << value[i].dump();
    out << "]";
  } else {
    out << value.dump();
  }
}

json matrix_rows(const Isometry3& T) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) {
    json row = json::array();
    for (int c = 0; c < 4; ++c) row.push_back(T.matrix()(r, c));
    rows.push_back(row);
  }
  return rows;
}

json corner_rows(const std::array<Vec3, 4>& corners) {
  json rows = json::array();
  for (const Vec3& c : corners) rows.push_back({c.x(), c.y(), c.z()});
  return rows;
}

Isometry3 matrix_from_rows(const json& rows) {
  Isometry3 T = Isometry3::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = rows.at(r).at(c).get<double>();
  }
  return T;
}

std::array<Vec3, 4> corners_from_rows(const json& rows) {
  if (rows.size() != 4) throw InputError("expected 4 corners, got " + std::to_string(rows.size()));
  std::array<Vec3, 4> corners;
  for (int i = 0; i < 4; ++i) {
    corners[i] = Vec3(rows.at(i).at(0).get<double>(), rows.at(i).at(1).get<double>(),
                      rows.at(i).at(2).get<double>());
  }
  return corners;
}

}  // namespace

void write_ground_truth_json(const std::string& path, const GroundTruth& truth) {
  json markers = json::array();
  for (const MarkerTruth& m : truth.markers) {
    markers.push_back({{"family", m.family},
                       {"id", m.id},
                       {"size_m", m.size_m},
                       {"visible", m.visible},
                       {"points_on_marker", m.points_on_marker},
                       {"corners_world", corner_rows(m.corners_world)},
                       {"corners_lidar", corner_rows(m.corners_lidar)},
                       {"T_world_marker", matrix_rows(m.T_world_marker)},
                       {"T_lidar_marker", matrix_rows(m.T_lidar_marker)}});
  }
  const json doc = {{"sensor", truth.sensor},
                    {"frames", truth.frames},
                    {"seed", truth.seed},
                    {"range_sigma_m", truth.range_sigma_m},
                    {"T_world_lidar", matrix_rows(truth.T_world_lidar)},
                    {"markers", markers}};
  std::ofstream out(path);
  if (!out) throw file_error(path, "cannot open for writing");
  write_json(out, doc, 0);
  out << "\n";
  if (!out) throw file_error(path, "write failed");
}

GroundTruth read_ground_truth_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw file_error(path, "cannot open");
  try {
    const json doc = json::parse(in);
    GroundTruth truth;
    truth.sensor = doc.at("sensor").get<std::string>();
    truth.frames = doc.at("frames").get<int>();
    truth.seed = doc.at("seed").get<std::uint64_t>();
    truth.range_sigma_m = doc.value("range_sigma_m", 0.0);
    truth.T_world_lidar = matrix_from_rows(doc.at("T_world_lidar"));
    for (const json& jm : doc.at("markers")) {
      MarkerTruth m;
      m.family = jm.at("family").get<std::string>();
      m.id = jm.at("id").get<int>();
      m.size_m = jm.at("size_m").get<double>();
      m.visible = jm.at("visible").get<bool>();
      m.points_on_marker = jm.value("points_on_marker", std::size_t{0});
      m.corners_world = corners_from_rows(jm.at("corners_world"));
      m.corners_lidar = corners_from_rows(jm.at("corners_lidar"));
      m.T_world_marker = matrix_from_rows(jm.at("T_world_marker"));
      m.T_lidar_marker = matrix_from_rows(jm.at("T_lidar_marker"));
      truth.markers.push_back(m);
    }
    return truth;
  } catch (const json::exception& e) {
    throw file_error(path, std::string("bad ground truth JSON: ") + e.what());
  } catch (const InputError& e) {
    throw file_error(path, e.what());
  }
}

}  // namespace iilfm::sim
