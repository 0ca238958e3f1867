// write_pcd: PCD v0.7, fields x y z intensity [ring] [time], in any of the three encodings.
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "lzf.hpp"

namespace iilfm::io {
namespace {

// One output field: where its values live in the cloud and how wide each is.
struct OutputField {
  const void* values;
  std::size_t size;
};

std::vector<OutputField> output_fields(const PointCloud& cloud) {
  std::vector<OutputField> fields = {
      {cloud.x.data(), 4}, {cloud.y.data(), 4}, {cloud.z.data(), 4}, {cloud.intensity.data(), 4}};
  if (cloud.has_ring()) fields.push_back({cloud.ring.data(), 2});
  if (cloud.has_time()) fields.push_back({cloud.time.data(), 8});
  return fields;
}

void check_columns(const std::string& path, const PointCloud& cloud) {
  const std::size_t n = cloud.size();
  const bool consistent = cloud.y.size() == n && cloud.z.size() == n &&
                          cloud.intensity.size() == n &&
                          (!cloud.has_ring() || cloud.ring.size() == n) &&
                          (!cloud.has_time() || cloud.time.size() == n);
  if (!consistent) {
    throw file_error(path, "cannot write a cloud whose columns differ in length (x has " +
                               std::to_string(n) + " points)");
  }
}

const char* encoding_name(PcdEncoding encoding) {
  switch (encoding) {
    case PcdEncoding::kAscii:
      return "ascii";
    case PcdEncoding::kBinary:
      return "binary";
    case PcdEncoding::kBinaryCompressed:
      return "binary_compressed";
  }
  return "binary";
}

std::string header_text(const PointCloud& cloud, PcdEncoding encoding) {
  const std::string n = std::to_string(cloud.size());
  std::string fields = "x y z intensity", sizes = "4 4 4 4", types = "F F F F", counts = "1 1 1 1";
  if (cloud.has_ring()) fields += " ring", sizes += " 2", types += " U", counts += " 1";
  if (cloud.has_time()) fields += " time", sizes += " 8", types += " F", counts += " 1";
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " +
         sizes + "\nTYPE " + types + "\nCOUNT " + counts + "\nWIDTH " + n +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA " + encoding_name(encoding) +
         "\n";
}

// Shortest decimal that reads back to the same value, so ascii files round-trip exactly.
template <typename T>
void append_number(T value, std::string& out) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

std::string ascii_body(const PointCloud& cloud) {
  std::string body;
  body.reserve(cloud.size() * 48);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    append_number(cloud.x[i], body);
    body += ' ';
    append_number(cloud.y[i], body);
    body += ' ';
    append_number(cloud.z[i], body);
    body += ' ';
    append_number(cloud.intensity[i], body);
    if (cloud.has_ring()) {
      body += ' ';
      append_number(cloud.ring[i], body);
    }
    if (cloud.has_time()) {
      body += ' ';
      append_number(cloud.time[i], body);
    }
    body += '\n';
  }
  return body;
}

// Point-major records, fields packed in header order.
std::vector<std::uint8_t> binary_body(const std::vector<OutputField>& fields, std::size_t n) {
  std::size_t point_size = 0;
  for (const OutputField& f : fields) point_size += f.size;
  std::vector<std::uint8_t> body(n * point_size);
  std::size_t offset = 0;
  for (const OutputField& f : fields) {
    const auto* values = static_cast<const std::uint8_t*>(f.values);
    std::uint8_t* out = body.data() + offset;
    for (std::size_t i = 0; i < n; ++i)
      std::memcpy(out + i * point_size, values + i * f.size, f.size);
    offset += f.size;
  }
  return body;
}

// Field-major columns, LZF-compressed, behind the two uint32 sizes.
std::vector<std::uint8_t> compressed_body(const std::string& path,
                                          const std::vector<OutputField>& fields, std::size_t n) {
  std::vector<std::uint8_t> columns;
  for (const OutputField& f : fields) {
    const auto* values = static_cast<const std::uint8_t*>(f.values);
    columns.insert(columns.end(), values, values + n * f.size);
  }
  if (columns.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw file_error(path, "cloud of " + std::to_string(n) +
                               " points is too large for binary_compressed (4 GiB limit)");
  }
  const std::vector<std::uint8_t> packed = lzf_compress(columns.data(), columns.size());
  if (packed.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw file_error(path, "compressed data exceeds the 4 GiB binary_compressed limit");
  }
  std::vector<std::uint8_t> body(8 + packed.size());
  const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(packed.size()),
                                  static_cast<std::uint32_t>(columns.size())};
  std::memcpy(body.data(), sizes, sizeof sizes);
  if (!packed.empty()) std::memcpy(body.data() + 8, packed.data(), packed.size());
  return body;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

void write_file(const std::string& path, const std::string& header, const void* body,
                std::size_t body_size) {
  std::FILE* raw = std::fopen(path.c_str(), "wb");
  if (!raw) throw file_error(path, std::string("cannot create file: ") + std::strerror(errno));
  std::unique_ptr<std::FILE, FileCloser> file(raw);
  const bool written = std::fwrite(header.data(), 1, header.size(), raw) == header.size() &&
                       (body_size == 0 || std::fwrite(body, 1, body_size, raw) == body_size);
  const int write_errno = errno;
  if (std::fclose(file.release()) != 0 || !written) {
    throw file_error(path,
                     std::string("write failed: ") + std::strerror(written ? errno : write_errno));
  }
}

}  // namespace

void write_pcd(const std::string& path, const PointCloud& cloud, PcdEncoding encoding) {
  check_columns(path, cloud);
  const std::string header = header_text(cloud, encoding);
  const std::size_t n = cloud.size();
  switch (encoding) {
    case PcdEncoding::kAscii: {
      const std::string body = ascii_body(cloud);
      return write_file(path, header, body.data(), body.size());
    }
    case PcdEncoding::kBinary: {
      const std::vector<std::uint8_t> body = binary_body(output_fields(cloud), n);
      return write_file(path, header, body.data(), body.size());
    }
    case PcdEncoding::kBinaryCompressed: {
      const std::vector<std::uint8_t> body = compressed_body(path, output_fields(cloud), n);
      return write_file(path, header, body.data(), body.size());
    }
  }
}

}  // namespace iilfm::io
