// LZF codec written from the stream description in lzf.hpp.
#include "lzf.hpp"

#include <algorithm>
#include <cstring>

namespace iilfm::io {
namespace {

constexpr std::size_t kMaxLiteralRun = 32;
constexpr std::size_t kMinMatch = 3;  // length code 0 would read as a literal control byte
constexpr std::size_t kMaxMatch = 2 + 7 + 255;
constexpr std::size_t kMaxDistance = 8192;  // 13 offset bits, stored minus one
constexpr unsigned kHashBits = 14;

std::uint32_t hash3(const std::uint8_t* p) {
  const std::uint32_t v = (std::uint32_t{p[0]} << 16) | (std::uint32_t{p[1]} << 8) | p[2];
  return (v * 2654435761u) >> (32 - kHashBits);
}

void emit_literals(const std::uint8_t* begin, const std::uint8_t* end,
                   std::vector<std::uint8_t>& out) {
  while (begin < end) {
    const std::size_t run = std::min<std::size_t>(kMaxLiteralRun, end - begin);
    out.push_back(static_cast<std::uint8_t>(run - 1));
    out.insert(out.end(), begin, begin + run);
    begin += run;
  }
}

void emit_back_reference(std::size_t length, std::size_t distance, std::vector<std::uint8_t>& out) {
  const std::size_t code = length - 2;
  const std::size_t offset = distance - 1;
  const std::uint8_t offset_high = static_cast<std::uint8_t>(offset >> 8);
  if (code < 7) {
    out.push_back(static_cast<std::uint8_t>((code << 5) | offset_high));
  } else {
    out.push_back(static_cast<std::uint8_t>((7 << 5) | offset_high));
    out.push_back(static_cast<std::uint8_t>(code - 7));
  }
  out.push_back(static_cast<std::uint8_t>(offset & 0xff));
}

}  // namespace

std::vector<std::uint8_t> lzf_compress(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> out;
  out.reserve(size + size / kMaxLiteralRun + 16);
  // Last position (plus one, 0 = none) where each 3-byte hash was seen.
  std::vector<std::size_t> last_seen(std::size_t{1} << kHashBits, 0);
  std::size_t literal_start = 0;
  std::size_t pos = 0;
  while (pos + kMinMatch <= size) {
    const std::uint32_t h = hash3(data + pos);
    const std::size_t candidate = last_seen[h];
    last_seen[h] = pos + 1;
    if (candidate != 0) {
      const std::size_t ref = candidate - 1;
      const std::size_t distance = pos - ref;
      if (distance <= kMaxDistance && std::memcmp(data + ref, data + pos, kMinMatch) == 0) {
        const std::size_t limit = std::min(kMaxMatch, size - pos);
        std::size_t length = kMinMatch;
        while (length < limit && data[ref + length] == data[pos + length]) ++length;
        emit_literals(data + literal_start, data + pos, out);
        emit_back_reference(length, distance, out);
        // Index the last position of the match so the next repeat finds a close reference.
        const std::size_t tail = pos + length - 1;
        if (tail + kMinMatch <= size) last_seen[hash3(data + tail)] = tail + 1;
        pos += length;
        literal_start = pos;
        continue;
      }
    }
    ++pos;
  }
  emit_literals(data + literal_start, data + size, out);
  return out;
}

bool lzf_decompress(const std::uint8_t* input, std::size_t input_size, std::uint8_t* output,
                    std::size_t output_size, std::string& problem) {
  std::size_t in = 0;
  std::size_t out = 0;
  while (in < input_size) {
    const std::size_t control = input[in++];
    if (control < kMaxLiteralRun) {
      const std::size_t run = control + 1;
      if (run > input_size - in) {
        problem = "literal run at byte " + std::to_string(in - 1) + " runs past the input";
        return false;
      }
      if (run > output_size - out) {
        problem = "literal run overruns the " + std::to_string(output_size) + "-byte output";
        return false;
      }
      std::memcpy(output + out, input + in, run);
      in += run;
      out += run;
      continue;
    }
    std::size_t length = control >> 5;
    if (length == 7) {
      if (in >= input_size) {
        problem = "back-reference at byte " + std::to_string(in - 1) + " is cut off";
        return false;
      }
      length += input[in++];
    }
    if (in >= input_size) {
      problem = "back-reference at byte " + std::to_string(in - 1) + " is cut off";
      return false;
    }
    const std::size_t distance = (((control & 0x1f) << 8) | input[in++]) + 1;
    length += 2;
    if (distance > out) {
      problem = "back-reference reaches " + std::to_string(distance) +
                " bytes back at output byte " + std::to_string(out);
      return false;
    }
    if (length > output_size - out) {
      problem = "back-reference overruns the " + std::to_string(output_size) + "-byte output";
      return false;
    }
    const std::uint8_t* from = output + out - distance;
    std::uint8_t* to = output + out;
    if (distance >= length) {
      std::memcpy(to, from, length);
    } else if (distance == 1) {
      std::memset(to, *from, length);  // a run of one byte, common in sparse columns
    } else {
      // Overlapping: the copy reads bytes it has just written, so it must go byte by byte.
      for (std::size_t k = 0; k < length; ++k) to[k] = from[k];
    }
    out += length;
  }
  if (out != output_size) {
    problem = "stream ends after " + std::to_string(out) + " of " + std::to_string(output_size) +
              " bytes";
    return false;
  }
  return true;
}

}  // namespace iilfm::io
