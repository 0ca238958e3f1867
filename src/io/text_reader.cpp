// read_xyz_text: plain text x y z [intensity] per line, as exported by CloudCompare, MATLAB and
// spreadsheets.
#include <string_view>

#include "ascii_values.hpp"
#include "file_bytes.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "pcd_header.hpp"
#include "point_filter.hpp"

namespace iilfm::io {
namespace {

// Strips a '#' comment (or a "//" one at the line start) from a line.
std::string_view without_comment(std::string_view line) {
  const std::size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  const std::size_t first = line.find_first_not_of(" \t\r");
  if (first != std::string_view::npos && line.substr(first, 2) == "//") return {};
  return line;
}

}  // namespace

LoadedCloud read_xyz_text(const std::string& path) {
  const FileBytes file = read_file_bytes(path);
  const std::string_view text(reinterpret_cast<const char*>(file.begin()), file.size());
  LoadedCloud out;
  PointCloud& cloud = out.cloud;
  std::vector<std::string_view> tokens(4);
  std::size_t pos = 0, line_number = 0, columns = 0, slot = 0, in_block = 0;
  bool header_allowed = true;
  while (pos < text.size()) {
    const std::size_t newline = std::min(text.find('\n', pos), text.size());
    const std::string_view line = without_comment(text.substr(pos, newline - pos));
    pos = newline + 1;
    ++line_number;
    const std::size_t found = split_values(line, tokens, true);
    if (found == 0) continue;
    double values[4] = {0, 0, 0, 0};
    const std::size_t used = std::min<std::size_t>(found, 4);
    bool numeric = true;
    for (std::size_t i = 0; i < used; ++i) numeric = numeric && parse_number(tokens[i], values[i]);
    if (!numeric) {
      // One line of column names ("x y z intensity") may precede the numbers.
      if (header_allowed) {
        header_allowed = false;
        continue;
      }
      throw file_error(path, "line " + std::to_string(line_number) + ": not a number in '" +
                                 quote_for_message(line) + "'");
    }
    header_allowed = false;
    if (found < 3)
      throw file_error(path, "line " + std::to_string(line_number) + " has " +
                                 std::to_string(found) + " values, need x y z [intensity]");
    if (columns == 0) columns = found;
    if (found != columns)
      throw file_error(path, "line " + std::to_string(line_number) + " has " +
                                 std::to_string(found) + " values, the first point line has " +
                                 std::to_string(columns));
    if (in_block == 0) slot = grow_columns(cloud, kDecodeBlockPoints, false, false);
    const std::size_t i = slot + in_block;
    cloud.x[i] = convert_scalar<float>(values[0]);
    cloud.y[i] = convert_scalar<float>(values[1]);
    cloud.z[i] = convert_scalar<float>(values[2]);
    cloud.intensity[i] = convert_scalar<float>(values[3]);
    ++out.stats.points_in_file;
    if (++in_block == kDecodeBlockPoints) {
      drop_invalid_points(cloud, slot, out.stats);
      in_block = 0;
    }
  }
  if (in_block > 0) {
    cloud.x.resize(slot + in_block);
    cloud.y.resize(slot + in_block);
    cloud.z.resize(slot + in_block);
    cloud.intensity.resize(slot + in_block);
    drop_invalid_points(cloud, slot, out.stats);
  }
  return out;
}

}  // namespace iilfm::io
