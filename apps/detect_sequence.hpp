// `iilfm detect` on a recording: every frame (or every sliding window of N frames) of a folder or
// a bag topic through one pipeline, one JSON line per result, the LiDAR trajectory in TUM form and
// the HTML report of the whole recording.
#pragma once

#include <functional>
#include <string>

#include "iilfm/pipeline.hpp"

namespace iilfm::cli {

struct SequenceArgs {
  std::string input;  // folder of cloud files, or a bag with `topic`
  std::string topic;
  int frames = 1;             // integration window, sliding by one frame
  double window_seconds = 0;  // > 0: a time window instead (FrameWindow::over_seconds)
  std::string jsonl_path, tum_path;
  std::string html_path;  // the sequence report (trajectory, per-frame table, one frame in full)
  long html_frame = -1;   // the frame shown in full; -1: the last one with markers
  bool quiet = false;
};

// True when `detect` should run over the whole recording rather than one (integrated) cloud.
bool is_sequence_run(const SequenceArgs& args);

// Processes the recording; returns the exit status. Damage part-way (a corrupt frame or chunk)
// raises InputError after the frames before it were processed and written.
// Options for the pipeline, given the first window's cloud (for an estimated resolution).
// Makes the pipeline's options from the first window, and says where its resolution came from
// (the JSON's image.resolution, e.g. "preset vlp16" or "estimated (ring field)").
using PipelineFactory =
    std::function<PipelineOptions(const PointCloud& first_window, std::string& resolution_source)>;
int run_detect_sequence(const SequenceArgs& args, const PipelineFactory& make_options);

}  // namespace iilfm::cli
