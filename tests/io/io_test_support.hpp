// Shared helpers for the I/O tests: a self-deleting temp directory, raw byte writing and an
// assertion for the one-line "<path>: <problem>" errors.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "iilfm/error.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm::io::testing {

class TempDir : public iilfm::testing::ScratchDir {
 public:
  TempDir() : ScratchDir("iilfm_io") {}
};

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write test file " + path);
}

// Appends the bytes of a value as the host (little-endian) stores it.
template <typename T>
void append_raw(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// A v0.7 header for the given per-field lists and point count.
inline std::string pcd_header(const std::string& fields, const std::string& sizes,
                              const std::string& types, const std::string& counts,
                              std::uint64_t points, const std::string& data) {
  const std::string n = std::to_string(points);
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " +
         sizes + "\nTYPE " + types + "\nCOUNT " + counts + "\nWIDTH " + n +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA " + data + "\n";
}

// An LZF stream of literal runs only: valid input for any LZF decoder, built without our
// compressor so the reader is checked against the format itself.
inline std::string lzf_literals(const std::string& data) {
  std::string out;
  for (std::size_t i = 0; i < data.size(); i += 32) {
    const std::size_t run = std::min<std::size_t>(32, data.size() - i);
    out.push_back(static_cast<char>(run - 1));
    out.append(data, i, run);
  }
  return out;
}

}  // namespace iilfm::io::testing

// Expects `statement` to throw iilfm::InputError whose one-line message contains `path` and
// `keyword`.
#define EXPECT_INPUT_ERROR(statement, path, keyword)                                     \
  EXPECT_THROW(                                                                          \
      {                                                                                  \
        try {                                                                            \
          statement;                                                                     \
        } catch (const iilfm::InputError& error) {                                       \
          const std::string message = error.what();                                      \
          EXPECT_NE(message.find(path), std::string::npos) << "message: " << message;    \
          EXPECT_NE(message.find(keyword), std::string::npos) << "message: " << message; \
          EXPECT_EQ(message.find('\n'), std::string::npos) << "message: " << message;    \
          throw;                                                                         \
        }                                                                                \
      },                                                                                 \
      iilfm::InputError)
