// Errors the library reports to its callers. Every message is one line that names the offending
// file or object and the problem, so the CLI can print it as is and exit with status 2.
#pragma once

#include <stdexcept>
#include <string>

namespace iilfm {

// Bad input: unreadable or malformed files, invalid options, inconsistent marker maps.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// Builds "<path>: <problem>", the shape of every file error.
inline InputError file_error(const std::string& path, const std::string& problem) {
  return InputError(path + ": " + problem);
}

}  // namespace iilfm
