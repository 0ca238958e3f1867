// DATA ascii: one point per line, values separated by spaces or tabs, "nan" allowed.
#include <algorithm>
#include <charconv>
#include <cstring>
#include <string_view>

#include "ascii_values.hpp"
#include "iilfm/error.hpp"
#include "pcd_body.hpp"
#include "point_filter.hpp"

namespace iilfm::io {
namespace {

class AsciiBodyParser {
 public:
  AsciiBodyParser(const PcdHeader& header, const std::string& path, std::size_t first_line_number)
      : header_(header),
        path_(path),
        line_number_(first_line_number),
        tokens_(header.values_per_point) {}

  void parse(std::string_view body, LoadedCloud& out) {
    const PcdColumnSources& s = header_.sources;
    const bool with_intensity = s.intensity != PcdColumnSources::kAbsent;
    const bool with_ring = s.ring != PcdColumnSources::kAbsent;
    const bool with_time = s.time != PcdColumnSources::kAbsent;
    // Every value takes at least a digit and a separator, which bounds what the body can hold
    // whatever POINTS claims.
    const std::size_t most_points = body.size() / (2 * header_.values_per_point) + 1;
    out.cloud.reserve(
        static_cast<std::size_t>(std::min<std::uint64_t>(header_.points, most_points)), with_ring,
        with_time);
    out.stats.points_in_file = static_cast<std::size_t>(header_.points);
    PointCloud& cloud = out.cloud;
    std::size_t block_size = 0, in_block = 0, slot = 0;

    std::size_t pos = 0;
    std::uint64_t parsed = 0;
    while (parsed < header_.points && pos < body.size()) {
      const std::size_t newline = body.find('\n', pos);
      const std::size_t line_end = newline == std::string_view::npos ? body.size() : newline;
      const std::string_view line = body.substr(pos, line_end - pos);
      pos = line_end + 1;
      ++line_number_;
      const std::size_t found = split_values(line, tokens_);
      if (found == 0) continue;  // blank line
      if (found != header_.values_per_point) {
        fail("has " + std::to_string(found) + " values, expected " +
             std::to_string(header_.values_per_point));
      }
      if (in_block == 0) {
        block_size = static_cast<std::size_t>(
            std::min<std::uint64_t>(kDecodeBlockPoints, header_.points - parsed));
        slot = grow_columns(cloud, block_size, with_ring, with_time);
      }
      const std::size_t i = slot + in_block;
      cloud.x[i] = value<float>(s.x);
      cloud.y[i] = value<float>(s.y);
      cloud.z[i] = value<float>(s.z);
      if (with_intensity) cloud.intensity[i] = value<float>(s.intensity);
      if (with_ring) cloud.ring[i] = value<std::uint16_t>(s.ring);
      if (with_time) cloud.time[i] = value<double>(s.time);
      ++parsed;
      if (++in_block == block_size) {
        drop_invalid_points(cloud, slot, out.stats);
        in_block = 0;
      }
    }
    if (parsed < header_.points) {
      throw file_error(path_, "truncated ascii data: expected " + std::to_string(header_.points) +
                                  " points, found " + std::to_string(parsed));
    }
  }

 private:
  template <typename Dst>
  Dst value(int field_index) const {
    const std::size_t token_index = header_.fields[field_index].value_index;
    const std::string_view token = tokens_[token_index];
    double v;
    if (!parse_number(token, v)) {
      fail("value " + std::to_string(token_index + 1) + " is not a number: '" +
           quote_for_message(token) + "'");
    }
    return convert_scalar<Dst>(v);
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw file_error(path_, "ascii data line " + std::to_string(line_number_) + " " + problem);
  }

  const PcdHeader& header_;
  const std::string& path_;
  std::size_t line_number_;  // in the file, 1-based, of the line being parsed
  std::vector<std::string_view> tokens_;
};

}  // namespace

void decode_pcd_ascii(const FileBytes& file, const PcdHeader& header, const std::string& path,
                      LoadedCloud& out) {
  if (header.points == 0) return;  // nothing to parse, whatever follows the header
  const char* text = reinterpret_cast<const char*>(file.begin());
  const std::size_t header_lines =
      static_cast<std::size_t>(std::count(text, text + header.data_offset, '\n'));
  const std::string_view body(text + header.data_offset, file.size() - header.data_offset);
  // A line of V values takes at least 2V - 1 bytes; checked before the token array is sized by V.
  if (header.values_per_point > body.size() / 2 + 1) {
    throw file_error(path, "truncated ascii data: a point has " +
                               std::to_string(header.values_per_point) +
                               " values but the data is " + std::to_string(body.size()) + " bytes");
  }
  AsciiBodyParser(header, path, header_lines).parse(body, out);
}

}  // namespace iilfm::io
