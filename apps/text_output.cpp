#include "text_output.hpp"

#include <fstream>
#include <iostream>

#include "iilfm/error.hpp"

namespace iilfm::cli {

bool is_stdout(const std::string& path) { return path == "-"; }

bool stdout_claimed(const std::vector<std::pair<const char*, std::string>>& text,
                    const std::vector<std::pair<const char*, std::string>>& binary) {
  for (const auto& [name, path] : binary)
    if (is_stdout(path))
      throw InputError(std::string(name) + " -: only --json, --jsonl and --tum write to stdout");
  const char* claimed = nullptr;
  for (const auto& [name, path] : text) {
    if (!is_stdout(path)) continue;
    if (claimed)
      throw InputError(std::string(claimed) + " - and " + name +
                       " -: only one output can be stdout");
    claimed = name;
  }
  return claimed != nullptr;
}

std::ostream& report_stream(bool result_on_stdout) {
  return result_on_stdout ? std::cerr : std::cout;
}

void write_text(const std::string& path, const std::string& text, const std::string& what) {
  if (is_stdout(path)) {
    if (!(std::cout << text) || !std::cout.flush())
      throw file_error("stdout", "cannot write " + what);
    return;
  }
  std::ofstream file(path);
  if (!file || !(file << text) || !file.flush()) throw file_error(path, "cannot write " + what);
}

std::string markers_found(const FrameResult& result) {
  std::string text = std::to_string(result.markers.size()) + " marker(s)";
  if (result.unknown_ids_dropped > 0)
    text += " (and " + std::to_string(result.unknown_ids_dropped) +
            " of ids not given with --ids, not reported)";
  if (result.not_square_dropped > 0)
    text += "; " + std::to_string(result.not_square_dropped) +
            " detection(s) dropped: their lifted corners are no square (chance matches)";
  return text;
}

}  // namespace iilfm::cli
