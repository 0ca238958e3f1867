// Whole-file access for the cloud readers. The file is memory-mapped when the system allows it (no
// copy: the decoders read the page cache directly), else read into a buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace iilfm::io {

class FileBytes {
 public:
  FileBytes() = default;
  FileBytes(FileBytes&& other) noexcept;
  FileBytes& operator=(FileBytes&& other) noexcept;
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;
  ~FileBytes();

  const std::uint8_t* begin() const { return data_; }
  const std::uint8_t* end() const { return data_ + size_; }
  std::size_t size() const { return size_; }

 private:
  friend FileBytes read_file_bytes(const std::string& path);
  void release();

  std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
  bool mapped_ = false;  // munmap rather than delete[]
};

// Reads the file at `path`. InputError "<path>: <problem>" when it is missing, not a regular file,
// unreadable or empty.
FileBytes read_file_bytes(const std::string& path);

}  // namespace iilfm::io
