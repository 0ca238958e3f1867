// The PCD header: field layout, point counts and data encoding, parsed and validated so the body
// decoders can trust every size and offset in it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "iilfm/io/cloud_io.hpp"
#include "packed_points.hpp"
#include "scalar_column.hpp"

namespace iilfm::io {

struct PcdField {
  std::string name;
  ScalarType type;
  std::size_t size;         // bytes per element
  std::size_t count;        // elements per point
  std::size_t byte_offset;  // of element 0 within a point record
  std::size_t value_index;  // of element 0 among the values of an ascii line
};

// Which field feeds each cloud column (indices into PcdHeader::fields), found by the rules every
// reader of named fields shares.
using PcdColumnSources = PackedRoles;

struct PcdHeader {
  std::vector<PcdField> fields;
  PcdColumnSources sources;
  std::size_t point_size = 0;        // bytes per point record: sum of size * count
  std::size_t values_per_point = 0;  // numbers per ascii line: sum of count
  std::uint64_t points = 0;
  PcdEncoding encoding = PcdEncoding::kAscii;
  std::size_t data_offset = 0;  // first byte after the DATA line
};

// Parses the header at the start of `data`. InputError "<path>: <problem>" when a mandatory entry
// is missing, the per-field lists disagree in length, a type is unknown, x/y/z are missing, or
// POINTS disagrees with WIDTH * HEIGHT.
PcdHeader parse_pcd_header(const std::uint8_t* data, std::size_t size, const std::string& path);

// Quotes text taken from a file for an error message: at most 40 characters, control bytes shown
// as '?', so a binary blob cannot break the one-line message.
std::string quote_for_message(std::string_view text);

}  // namespace iilfm::io
