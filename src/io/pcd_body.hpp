// Decoders for the three PCD DATA encodings. Each checks the body against the header before it
// allocates, then appends the valid points to out.cloud and counts all of them in out.stats.
#pragma once

#include <string>

#include "file_bytes.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "pcd_header.hpp"

namespace iilfm::io {

void decode_pcd_ascii(const FileBytes& file, const PcdHeader& header, const std::string& path,
                      LoadedCloud& out);
void decode_pcd_binary(const FileBytes& file, const PcdHeader& header, const std::string& path,
                       LoadedCloud& out);
void decode_pcd_binary_compressed(const FileBytes& file, const PcdHeader& header,
                                  const std::string& path, LoadedCloud& out);

}  // namespace iilfm::io
