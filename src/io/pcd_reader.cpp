// read_pcd: the header, then the decoder for its DATA encoding.
#include "file_bytes.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "pcd_body.hpp"
#include "pcd_header.hpp"

namespace iilfm::io {

LoadedCloud read_pcd(const std::string& path) {
  const FileBytes file = read_file_bytes(path);
  const PcdHeader header = parse_pcd_header(file.begin(), file.size(), path);
  LoadedCloud loaded;
  switch (header.encoding) {
    case PcdEncoding::kAscii:
      decode_pcd_ascii(file, header, path, loaded);
      break;
    case PcdEncoding::kBinary:
      decode_pcd_binary(file, header, path, loaded);
      break;
    case PcdEncoding::kBinaryCompressed:
      decode_pcd_binary_compressed(file, header, path, loaded);
      break;
  }
  return loaded;
}

}  // namespace iilfm::io
