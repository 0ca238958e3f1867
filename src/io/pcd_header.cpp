#include "pcd_header.hpp"

#include <charconv>
#include <cstring>
#include <optional>
#include <string_view>

#include "iilfm/error.hpp"

namespace iilfm::io {
namespace {

// Bounds one COUNT so size * count * fields cannot overflow; real descriptors stay far below.
constexpr std::uint64_t kMaxCount = std::uint64_t{1} << 24;

using Words = std::vector<std::string_view>;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

Words split_words(std::string_view line) {
  Words words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; };
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

std::optional<std::uint64_t> parse_unsigned(std::string_view word) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (ec != std::errc() || end != word.data() + word.size()) return std::nullopt;
  return value;
}

// The header entries as written, before validation.
struct RawHeader {
  std::optional<Words> fields, sizes, types, counts;
  std::optional<std::uint64_t> width, height, points;
  std::optional<std::string_view> data;
  std::size_t data_offset = 0;
};

std::uint64_t parse_count_entry(const Words& values, std::string_view keyword,
                                const std::string& path) {
  if (values.size() != 1) {
    throw file_error(path, std::string(keyword) + " needs one number, found " +
                               std::to_string(values.size()) + " values");
  }
  const auto value = parse_unsigned(values[0]);
  if (!value) {
    throw file_error(path, std::string(keyword) + " is not a non-negative integer: '" +
                               quote_for_message(values[0]) + "'");
  }
  return *value;
}

RawHeader scan_header_lines(const std::uint8_t* data, std::size_t size, const std::string& path) {
  RawHeader raw;
  const char* text = reinterpret_cast<const char*>(data);
  std::size_t pos = 0;
  while (pos < size) {
    const void* newline = std::memchr(text + pos, '\n', size - pos);
    const std::size_t line_end =
        newline ? static_cast<std::size_t>(static_cast<const char*>(newline) - text) : size;
    std::string_view line(text + pos, line_end - pos);
    pos = newline ? line_end + 1 : size;
    line = line.substr(0, line.find('#'));  // comment lines and trailing comments
    Words words = split_words(line);
    if (words.empty()) continue;
    const std::string_view keyword = words.front();
    const Words values(words.begin() + 1, words.end());
    if (keyword == "DATA") {
      if (values.size() != 1) throw file_error(path, "DATA needs one encoding name");
      raw.data = values[0];
      raw.data_offset = pos;
      return raw;
    }
    if (keyword == "FIELDS" || keyword == "COLUMNS") {  // COLUMNS: the older name of FIELDS
      raw.fields = values;
    } else if (keyword == "SIZE") {
      raw.sizes = values;
    } else if (keyword == "TYPE") {
      raw.types = values;
    } else if (keyword == "COUNT") {
      raw.counts = values;
    } else if (keyword == "WIDTH") {
      raw.width = parse_count_entry(values, keyword, path);
    } else if (keyword == "HEIGHT") {
      raw.height = parse_count_entry(values, keyword, path);
    } else if (keyword == "POINTS") {
      raw.points = parse_count_entry(values, keyword, path);
    }
    // VERSION, VIEWPOINT and anything unknown carry nothing the reader needs.
  }
  throw file_error(path, "not a PCD file: header has no DATA line");
}

std::optional<ScalarType> scalar_type_of(std::string_view type, std::uint64_t size) {
  if (type.size() != 1) return std::nullopt;
  switch (type[0]) {
    case 'I':
      if (size == 1) return ScalarType::kI8;
      if (size == 2) return ScalarType::kI16;
      if (size == 4) return ScalarType::kI32;
      if (size == 8) return ScalarType::kI64;
      break;
    case 'U':
      if (size == 1) return ScalarType::kU8;
      if (size == 2) return ScalarType::kU16;
      if (size == 4) return ScalarType::kU32;
      if (size == 8) return ScalarType::kU64;
      break;
    case 'F':
      if (size == 4) return ScalarType::kF32;
      if (size == 8) return ScalarType::kF64;
      break;
  }
  return std::nullopt;
}

void check_list_length(const Words& list, std::string_view keyword, std::size_t field_count,
                       const std::string& path) {
  if (list.size() != field_count) {
    throw file_error(path, std::string(keyword) + " lists " + std::to_string(list.size()) +
                               " values but FIELDS names " + std::to_string(field_count));
  }
}

std::vector<PcdField> build_fields(const RawHeader& raw, const std::string& path) {
  if (!raw.fields || raw.fields->empty()) throw file_error(path, "header missing FIELDS");
  if (!raw.sizes) throw file_error(path, "header missing SIZE");
  if (!raw.types) throw file_error(path, "header missing TYPE");
  const std::size_t n = raw.fields->size();
  check_list_length(*raw.sizes, "SIZE", n, path);
  check_list_length(*raw.types, "TYPE", n, path);
  if (raw.counts) check_list_length(*raw.counts, "COUNT", n, path);

  std::vector<PcdField> fields;
  fields.reserve(n);
  std::size_t byte_offset = 0;
  std::size_t value_index = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string name((*raw.fields)[i]);
    const std::string quoted = "'" + quote_for_message(name) + "'";
    const auto size = parse_unsigned((*raw.sizes)[i]);
    if (!size) {
      throw file_error(path, "SIZE of field " + quoted + " is not a number: '" +
                                 quote_for_message((*raw.sizes)[i]) + "'");
    }
    const auto type = scalar_type_of((*raw.types)[i], *size);
    if (!type) {
      throw file_error(path, "unsupported TYPE " + quote_for_message((*raw.types)[i]) +
                                 " with SIZE " + std::to_string(*size) + " for field " + quoted);
    }
    std::uint64_t count = 1;
    if (raw.counts) {
      const auto parsed = parse_unsigned((*raw.counts)[i]);
      if (!parsed || *parsed == 0 || *parsed > kMaxCount) {
        throw file_error(path, "COUNT of field " + quoted + " must be 1.." +
                                   std::to_string(kMaxCount) + ", found '" +
                                   quote_for_message((*raw.counts)[i]) + "'");
      }
      count = *parsed;
    }
    fields.push_back({name, *type, static_cast<std::size_t>(*size), static_cast<std::size_t>(count),
                      byte_offset, value_index});
    byte_offset += static_cast<std::size_t>(*size * count);
    value_index += static_cast<std::size_t>(count);
  }
  return fields;
}

PcdColumnSources find_sources(const std::vector<PcdField>& fields, const std::string& path) {
  std::vector<std::string> names;
  names.reserve(fields.size());
  for (const PcdField& f : fields) names.push_back(f.name);
  const PcdColumnSources s = find_roles_by_name(names);  // the rules of every named-field reader
  for (const auto& [index, name] : {std::pair{s.x, "x"}, {s.y, "y"}, {s.z, "z"}}) {
    if (index == PcdColumnSources::kAbsent) {
      throw file_error(path,
                       std::string("FIELDS has no '") + name + "' field (x, y, z are needed)");
    }
  }
  return s;
}

std::uint64_t point_count(const RawHeader& raw, const std::string& path) {
  const std::uint64_t height = raw.height.value_or(1);
  if (!raw.width) {
    if (!raw.points) throw file_error(path, "header missing POINTS and WIDTH");
    return *raw.points;
  }
  std::uint64_t product = 0;
  if (__builtin_mul_overflow(*raw.width, height, &product)) {
    throw file_error(path, "WIDTH*HEIGHT overflows");
  }
  if (raw.points && *raw.points != product) {
    throw file_error(path, "POINTS " + std::to_string(*raw.points) +
                               " does not match WIDTH*HEIGHT " + std::to_string(*raw.width) + "*" +
                               std::to_string(height) + " = " + std::to_string(product));
  }
  return product;
}

PcdEncoding encoding_of(std::string_view name, const std::string& path) {
  if (equals_ignoring_case(name, "ascii")) return PcdEncoding::kAscii;
  if (equals_ignoring_case(name, "binary")) return PcdEncoding::kBinary;
  if (equals_ignoring_case(name, "binary_compressed")) return PcdEncoding::kBinaryCompressed;
  throw file_error(path, "unknown DATA encoding '" + quote_for_message(name) +
                             "' (expected ascii, binary or binary_compressed)");
}

}  // namespace

std::string quote_for_message(std::string_view text) {
  constexpr std::size_t kMaxShown = 40;
  std::string out;
  for (const char c : text.substr(0, kMaxShown)) {
    const auto byte = static_cast<unsigned char>(c);
    out.push_back(byte < 0x20 || byte >= 0x7f ? '?' : c);
  }
  if (text.size() > kMaxShown) out += "...";
  return out;
}

PcdHeader parse_pcd_header(const std::uint8_t* data, std::size_t size, const std::string& path) {
  const RawHeader raw = scan_header_lines(data, size, path);
  PcdHeader header;
  header.fields = build_fields(raw, path);
  header.sources = find_sources(header.fields, path);
  const PcdField& last = header.fields.back();
  header.point_size = last.byte_offset + last.size * last.count;
  header.values_per_point = last.value_index + last.count;
  header.points = point_count(raw, path);
  header.encoding = encoding_of(*raw.data, path);
  header.data_offset = raw.data_offset;
  return header;
}

}  // namespace iilfm::io
