// The text outputs of `iilfm detect` (--json, --jsonl, --tum): a file, or stdout for "-", so that a
// result can be piped (`iilfm detect scan.pcd --json - | jq .pose`). Then the human-readable
// report goes to stderr: stdout carries the result and nothing else.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "iilfm/pipeline.hpp"

namespace iilfm::cli {

bool is_stdout(const std::string& path);

// Options given as (name, path). InputError when more than one text output is "-" or a binary one
// (--image, --html) is; returns whether a text output is "-".
bool stdout_claimed(const std::vector<std::pair<const char*, std::string>>& text,
                    const std::vector<std::pair<const char*, std::string>>& binary);

// Where the human-readable report goes: stdout, or stderr when a result goes to stdout.
std::ostream& report_stream(bool result_on_stdout);

// The report's count of markers: "2 marker(s)", those of ids not given with --ids, and the
// detections dropped because their lifted corners are no square.
std::string markers_found(const FrameResult& result);

// Writes `text` whole to `path` (stdout for "-") and flushes it; InputError "<path>: cannot write
// <what>" when that fails.
void write_text(const std::string& path, const std::string& text, const std::string& what);

}  // namespace iilfm::cli
