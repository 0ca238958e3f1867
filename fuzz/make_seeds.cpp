// Writes the seed corpora of the cloud fuzz targets from one simulated scan (scripts/fuzz_seeds.sh
// runs it): a few hundred of the scan's points in every encoding each reader takes, so the fuzzer
// starts from valid files of a few KB. Usage: iilfm_fuzz_seeds SCAN.pcd CORPUS_DIR
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "iilfm/io/cloud_io.hpp"

namespace {

namespace fs = std::filesystem;
using iilfm::PointCloud;

// Every k-th point, `count` of them, with ring and time when the scan has them.
PointCloud sample(const PointCloud& scan, std::size_t count) {
  PointCloud out;
  const std::size_t step = std::max<std::size_t>(1, scan.size() / count);
  for (std::size_t i = 0; i < scan.size() && out.size() < count; i += step) {
    out.push_back(scan.x[i], scan.y[i], scan.z[i], scan.intensity[i]);
    if (scan.has_ring()) out.ring.push_back(scan.ring[i]);
    if (scan.has_time()) out.time.push_back(scan.time[i]);
  }
  return out;
}

template <typename T>
void put(std::ofstream& out, T value, bool big_endian = false) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (big_endian) std::reverse(bytes, bytes + sizeof(T));
  out.write(bytes, sizeof(T));
}

void write_kitti(const fs::path& path, const PointCloud& c) {
  std::ofstream out(path, std::ios::binary);
  for (std::size_t i = 0; i < c.size(); ++i)
    for (float v : {c.x[i], c.y[i], c.z[i], c.intensity[i] / 255.f}) put(out, v);
}

void write_ply(const fs::path& path, const PointCloud& c, const std::string& format) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat " << format << " 1.0\nelement vertex " << c.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar intensity\n"
         "end_header\n";
  const bool big = format == "binary_big_endian";
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto level = static_cast<std::uint8_t>(c.intensity[i]);
    if (format == "ascii") {
      out << c.x[i] << ' ' << c.y[i] << ' ' << c.z[i] << ' ' << int(level) << '\n';
    } else {
      for (float v : {c.x[i], c.y[i], c.z[i]}) put(out, v, big);
      put(out, level);
    }
  }
}

void write_xyz(const fs::path& path, const PointCloud& c, char separator, bool header) {
  std::ofstream out(path);
  if (header) out << "x" << separator << "y" << separator << "z" << separator << "intensity\n";
  for (std::size_t i = 0; i < c.size(); ++i)
    out << c.x[i] << separator << c.y[i] << separator << c.z[i] << separator << c.intensity[i]
        << '\n';
}

// The pipeline target's input: one choice byte, then float32 quadruples.
void write_pipeline(const fs::path& path, const PointCloud& c, std::uint8_t choice) {
  std::ofstream out(path, std::ios::binary);
  put(out, choice);
  for (std::size_t i = 0; i < c.size(); ++i)
    for (float v : {c.x[i], c.y[i], c.z[i], c.intensity[i]}) put(out, v);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: iilfm_fuzz_seeds SCAN.pcd CORPUS_DIR\n";
    return 2;
  }
  const PointCloud scan = iilfm::io::read_pcd(argv[1]).cloud;
  const fs::path corpus = argv[2];
  for (const char* target : {"pcd", "kitti", "ply", "xyz", "pipeline"})
    fs::create_directories(corpus / target);

  const PointCloud small = sample(scan, 100);
  PointCloud plain = small;  // x y z intensity only
  plain.ring.clear();
  plain.time.clear();
  using iilfm::io::PcdEncoding;
  iilfm::io::write_pcd((corpus / "pcd/ascii.pcd").string(), small, PcdEncoding::kAscii);
  iilfm::io::write_pcd((corpus / "pcd/binary.pcd").string(), small, PcdEncoding::kBinary);
  iilfm::io::write_pcd((corpus / "pcd/compressed.pcd").string(), small,
                       PcdEncoding::kBinaryCompressed);
  iilfm::io::write_pcd((corpus / "pcd/xyzi_binary.pcd").string(), plain, PcdEncoding::kBinary);
  write_kitti(corpus / "kitti/scan.bin", small);
  write_ply(corpus / "ply/ascii.ply", small, "ascii");
  write_ply(corpus / "ply/binary_le.ply", small, "binary_little_endian");
  write_ply(corpus / "ply/binary_be.ply", small, "binary_big_endian");
  write_xyz(corpus / "xyz/blanks.xyz", small, ' ', false);
  write_xyz(corpus / "xyz/csv_header.xyz", small, ',', true);
  const PointCloud dense = sample(scan, 250);
  for (std::uint8_t choice : {0, 1, 2, 4})
    write_pipeline(corpus / ("pipeline/scan_" + std::to_string(choice) + ".bin"), dense, choice);
  std::cout << "seeds written to " << corpus.string() << "\n";
  return 0;
}
