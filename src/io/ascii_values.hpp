// Splitting and parsing the numbers of one text line, shared by the ascii readers (PCD, PLY,
// XYZI text).
#pragma once

#include <charconv>
#include <string_view>
#include <vector>

namespace iilfm::io {

inline bool is_value_separator(char c, bool commas) {
  return c == ' ' || c == '\t' || c == '\r' || (commas && c == ',');
}

// Splits `line` into `tokens` (reused across lines); returns the number of values found, which may
// exceed tokens.size() when the line has too many. With `commas`, a comma separates like a blank.
inline std::size_t split_values(std::string_view line, std::vector<std::string_view>& tokens,
                                bool commas = false) {
  std::size_t found = 0;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_value_separator(line[i], commas)) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_value_separator(line[i], commas)) ++i;
    if (i == start) break;
    if (found < tokens.size()) tokens[found] = line.substr(start, i - start);
    ++found;
  }
  return found;
}

// strtod-like, without locale or allocation; accepts a leading '+', "nan" and "inf".
inline bool parse_number(std::string_view token, double& value) {
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin != end && *begin == '+') ++begin;
  const auto [stop, ec] = std::from_chars(begin, end, value);
  return ec == std::errc() && stop == end;
}

}  // namespace iilfm::io
