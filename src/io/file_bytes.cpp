#include "file_bytes.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "iilfm/error.hpp"

namespace iilfm::io {
namespace {

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

std::string system_problem(const char* what) {
  return std::string(what) + ": " + std::strerror(errno);
}

// Fallback for files the system will not map: a plain read loop into an uninitialised buffer.
bool read_into(int fd, std::uint8_t* buffer, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t got = ::read(fd, buffer + done, size - done);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    done += static_cast<std::size_t>(got);
  }
  return true;
}

}  // namespace

FileBytes::FileBytes(FileBytes&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      mapped_(other.mapped_) {}

FileBytes& FileBytes::operator=(FileBytes&& other) noexcept {
  if (this != &other) {
    release();
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
    mapped_ = other.mapped_;
  }
  return *this;
}

FileBytes::~FileBytes() { release(); }

void FileBytes::release() {
  if (!data_) return;
  if (mapped_) {
    ::munmap(data_, size_);
  } else {
    delete[] data_;
  }
  data_ = nullptr;
}

FileBytes read_file_bytes(const std::string& path) {
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) {
    if (errno == ENOENT) throw file_error(path, "file not found");
    throw file_error(path, system_problem("cannot open file"));
  }
  struct stat info;
  if (::fstat(fd.get(), &info) != 0) throw file_error(path, system_problem("cannot stat file"));
  if (!S_ISREG(info.st_mode)) throw file_error(path, "not a regular file");
  if (info.st_size == 0) throw file_error(path, "empty file");

  FileBytes bytes;
  bytes.size_ = static_cast<std::size_t>(info.st_size);
  // MAP_POPULATE maps the whole (usually cached) file at once instead of faulting page by page.
  void* mapped = ::mmap(nullptr, bytes.size_, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd.get(), 0);
  if (mapped != MAP_FAILED) {
    bytes.data_ = static_cast<std::uint8_t*>(mapped);
    bytes.mapped_ = true;
    return bytes;
  }
  bytes.data_ = new std::uint8_t[bytes.size_];  // default-initialised: no zero fill before the read
  if (!read_into(fd.get(), bytes.data_, bytes.size_)) {
    throw file_error(
        path, "read error: got fewer bytes than the file size " + std::to_string(bytes.size_));
  }
  return bytes;
}

}  // namespace iilfm::io
