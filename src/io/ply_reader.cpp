// read_ply: the vertex element of a PLY file (ascii, binary_little_endian, binary_big_endian).
// Elements before the vertices (rare, but allowed) are skipped; faces after them are ignored.
#include <algorithm>
#include <cmath>
#include <string_view>

#include "ascii_values.hpp"
#include "file_bytes.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "packed_points.hpp"
#include "pcd_header.hpp"
#include "point_filter.hpp"

namespace iilfm::io {
namespace {

enum class PlyFormat { kAscii, kLittle, kBig };

struct PlyProperty {
  std::string name;
  ScalarType type;
  bool is_list = false;
  ScalarType count_type = ScalarType::kU8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;
  std::size_t body_line = 0;  // 1-based line number of the first body line (ascii)
};

bool ply_type(std::string_view name, ScalarType& type) {
  static const std::pair<std::string_view, ScalarType> kTypes[] = {
      {"char", ScalarType::kI8},    {"int8", ScalarType::kI8},     {"uchar", ScalarType::kU8},
      {"uint8", ScalarType::kU8},   {"short", ScalarType::kI16},   {"int16", ScalarType::kI16},
      {"ushort", ScalarType::kU16}, {"uint16", ScalarType::kU16},  {"int", ScalarType::kI32},
      {"int32", ScalarType::kI32},  {"uint", ScalarType::kU32},    {"uint32", ScalarType::kU32},
      {"float", ScalarType::kF32},  {"float32", ScalarType::kF32}, {"double", ScalarType::kF64},
      {"float64", ScalarType::kF64}};
  for (const auto& [n, t] : kTypes) {
    if (n == name) {
      type = t;
      return true;
    }
  }
  return false;
}

PlyHeader parse_header(const FileBytes& file, const std::string& path) {
  const std::string_view text(reinterpret_cast<const char*>(file.begin()), file.size());
  PlyHeader header;
  std::vector<std::string_view> words(8);
  std::size_t pos = 0, line_number = 0;
  bool format_seen = false;
  while (true) {
    const std::size_t newline = text.find('\n', pos);
    if (newline == std::string_view::npos) throw file_error(path, "PLY header has no end_header");
    std::string_view line = text.substr(pos, newline - pos);
    pos = newline + 1;
    ++line_number;
    const std::size_t n = split_values(line, words);
    if (line_number == 1) {
      if (n != 1 || words[0] != "ply") throw file_error(path, "not a PLY file (no 'ply' line)");
      continue;
    }
    if (n == 0) continue;
    const std::string_view keyword = words[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      if (n < 2) throw file_error(path, "PLY format line without a format");
      if (words[1] == "ascii")
        header.format = PlyFormat::kAscii;
      else if (words[1] == "binary_little_endian")
        header.format = PlyFormat::kLittle;
      else if (words[1] == "binary_big_endian")
        header.format = PlyFormat::kBig;
      else
        throw file_error(path, "unknown PLY format '" + quote_for_message(words[1]) + "'");
      format_seen = true;
    } else if (keyword == "element") {
      double count;
      // 2^63 and beyond cannot be converted to the count type (and no file holds that many).
      if (n != 3 || !parse_number(words[2], count) || count < 0 || count != std::floor(count) ||
          !(count < 9.2e18))
        throw file_error(path, "PLY header line " + std::to_string(line_number) +
                                   ": expected 'element NAME COUNT'");
      header.elements.push_back({std::string(words[1]), static_cast<std::uint64_t>(count), {}});
    } else if (keyword == "property") {
      if (header.elements.empty())
        throw file_error(
            path, "PLY property before any element (line " + std::to_string(line_number) + ")");
      PlyProperty p;
      bool ok;
      if (n == 5 && words[1] == "list") {
        p.is_list = true;
        p.name = std::string(words[4]);
        ok = ply_type(words[2], p.count_type) && ply_type(words[3], p.type);
      } else {
        p.name = std::string(n == 3 ? words[2] : "");
        ok = n == 3 && ply_type(words[1], p.type);
      }
      if (!ok)
        throw file_error(path, "PLY header line " + std::to_string(line_number) +
                                   ": bad property '" + quote_for_message(line) + "'");
      header.elements.back().properties.push_back(std::move(p));
    } else {
      throw file_error(path, "PLY header line " + std::to_string(line_number) +
                                 ": unknown keyword '" + quote_for_message(keyword) + "'");
    }
  }
  if (!format_seen) throw file_error(path, "PLY header has no format line");
  header.body_offset = pos;
  header.body_line = line_number + 1;
  return header;
}

std::uint64_t read_count(const std::uint8_t* at, ScalarType type, bool big_endian) {
  std::uint8_t bytes[8];
  const std::size_t size = scalar_size(type);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = big_endian ? at[size - 1 - i] : at[i];
  double value = 0;
  decode_column(type, bytes, 0, 1, &value);
  if (!(value >= 0) || value >= 1e18) return UINT64_MAX;  // negative, NaN or absurd
  return static_cast<std::uint64_t>(value);
}

// Byte length of the binary records of an element that comes before the vertices.
std::size_t skip_binary_element(const PlyElement& e, const std::uint8_t* data, std::size_t size,
                                bool big_endian, const std::string& path) {
  if (e.properties.empty()) return 0;
  const auto fail = [&] {
    return file_error(path, "PLY data ends inside element '" + e.name + "'");
  };
  std::size_t at = 0;
  for (std::uint64_t r = 0; r < e.count; ++r) {
    for (const PlyProperty& p : e.properties) {
      const std::size_t element_size = scalar_size(p.type);
      std::uint64_t count = 1;
      if (p.is_list) {
        const std::size_t count_size = scalar_size(p.count_type);
        if (count_size > size - at) throw fail();
        count = read_count(data + at, p.count_type, big_endian);
        at += count_size;
      }
      if (count > (size - at) / element_size) throw fail();
      at += count * element_size;
    }
  }
  return at;
}

const PlyElement* vertex_element(const PlyHeader& header, const std::string& path) {
  for (const PlyElement& e : header.elements) {
    if (e.name != "vertex") continue;
    for (const PlyProperty& p : e.properties)
      if (p.is_list) throw file_error(path, "PLY vertex property '" + p.name + "' is a list");
    return &e;
  }
  throw file_error(path, "PLY file has no vertex element");
}

void read_binary(const FileBytes& file, const PlyHeader& header, const std::string& path,
                 LoadedCloud& out) {
  const bool big_endian = header.format == PlyFormat::kBig;
  const std::uint8_t* data = file.begin() + header.body_offset;
  std::size_t size = file.size() - header.body_offset;
  for (const PlyElement& e : header.elements) {
    if (e.name != "vertex") {
      const std::size_t skipped = skip_binary_element(e, data, size, big_endian, path);
      data += skipped;
      size -= skipped;
      continue;
    }
    std::vector<PackedField> fields;
    std::size_t record = 0;
    for (const PlyProperty& p : e.properties) {
      fields.push_back({p.name, p.type, record});
      record += scalar_size(p.type);
    }
    const PackedRoles roles = find_packed_roles(fields);
    if (!roles.has_xyz()) throw file_error(path, "PLY vertices have no x, y, z properties");
    if (record == 0 || e.count > size / record)
      throw file_error(path, "truncated PLY data: " + std::to_string(e.count) + " vertices of " +
                                 std::to_string(record) + " bytes need more than the " +
                                 std::to_string(size) + " bytes left");
    decode_packed_records(data, e.count, record, fields, roles, big_endian, out);
    return;
  }
}

void read_ascii(const FileBytes& file, const PlyHeader& header, const std::string& path,
                LoadedCloud& out) {
  const std::string_view body(reinterpret_cast<const char*>(file.begin()) + header.body_offset,
                              file.size() - header.body_offset);
  const PlyElement& vertices = *vertex_element(header, path);
  std::vector<PackedField> fields;
  for (const PlyProperty& p : vertices.properties) fields.push_back({p.name, p.type, 0});
  const PackedRoles roles = find_packed_roles(fields);
  if (!roles.has_xyz()) throw file_error(path, "PLY vertices have no x, y, z properties");
  const bool with_ring = roles.ring >= 0, with_time = roles.time >= 0;

  std::size_t pos = 0, line_number = header.body_line - 1;
  auto next_line = [&](std::string_view& line) {
    while (pos < body.size()) {
      const std::size_t newline = std::min(body.find('\n', pos), body.size());
      line = body.substr(pos, newline - pos);
      pos = newline + 1;
      ++line_number;
      if (line.find_first_not_of(" \t\r") != std::string_view::npos) return true;
    }
    return false;
  };
  std::string_view line;
  for (const PlyElement& e : header.elements) {
    if (&e == &vertices) break;
    for (std::uint64_t r = 0; r < e.count; ++r)
      if (!next_line(line)) throw file_error(path, "PLY data ends inside element '" + e.name + "'");
  }
  // Each vertex line takes at least two bytes per value: bounds the count before allocating.
  if (vertices.count > body.size() / (2 * fields.size()) + 1)
    throw file_error(path, "truncated PLY data: " + std::to_string(vertices.count) +
                               " vertices cannot fit in " + std::to_string(body.size()) + " bytes");
  std::vector<std::string_view> tokens(fields.size());
  out.stats.points_in_file = vertices.count;
  out.cloud.reserve(vertices.count, with_ring, with_time);
  auto value = [&](int role) {
    double v;
    if (!parse_number(tokens[static_cast<std::size_t>(role)], v))
      throw file_error(path, "PLY line " + std::to_string(line_number) + ": '" +
                                 quote_for_message(tokens[static_cast<std::size_t>(role)]) +
                                 "' is not a number");
    return v;
  };
  for (std::uint64_t done = 0; done < vertices.count; done += kDecodeBlockPoints) {
    const std::size_t count = static_cast<std::size_t>(
        std::min<std::uint64_t>(kDecodeBlockPoints, vertices.count - done));
    const std::size_t slot = grow_columns(out.cloud, count, with_ring, with_time);
    PointCloud& c = out.cloud;
    for (std::size_t i = slot; i < slot + count; ++i) {
      if (!next_line(line))
        throw file_error(path, "truncated PLY data: expected " + std::to_string(vertices.count) +
                                   " vertices, found " + std::to_string(done + i - slot));
      const std::size_t n = split_values(line, tokens);
      if (n != fields.size())
        throw file_error(path, "PLY line " + std::to_string(line_number) + " has " +
                                   std::to_string(n) + " values, expected " +
                                   std::to_string(fields.size()));
      c.x[i] = convert_scalar<float>(value(roles.x));
      c.y[i] = convert_scalar<float>(value(roles.y));
      c.z[i] = convert_scalar<float>(value(roles.z));
      if (roles.intensity >= 0) c.intensity[i] = convert_scalar<float>(value(roles.intensity));
      if (with_ring) c.ring[i] = convert_scalar<std::uint16_t>(value(roles.ring));
      if (with_time) c.time[i] = value(roles.time);
    }
    drop_invalid_points(c, slot, out.stats);
  }
}

}  // namespace

LoadedCloud read_ply(const std::string& path) {
  const FileBytes file = read_file_bytes(path);
  const PlyHeader header = parse_header(file, path);
  vertex_element(header, path);
  LoadedCloud out;
  if (header.format == PlyFormat::kAscii)
    read_ascii(file, header, path, out);
  else
    read_binary(file, header, path, out);
  return out;
}

}  // namespace iilfm::io
