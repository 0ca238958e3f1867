// A recording as a sequence of frames: every cloud file of a folder, or every message of one bag
// topic. Sources read one frame at a time, so a long recording never sits in memory at once.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "iilfm/io/cloud_io.hpp"

namespace iilfm::io {

struct Frame {
  std::size_t index = 0;  // 0-based position in the recording
  double stamp_s = 0;     // when the frame was taken, seconds (see open_frame_source)
  std::string source;     // the file, or "rec.bag:/topic#12"
  LoadedCloud loaded;
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The next frame; false after the last. InputError "<path>: <problem>" for a frame that cannot
  // be read (a corrupt file or chunk, a truncated bag): every frame before it has been delivered.
  virtual bool next(Frame& frame) = 0;
  // Frames the source expects to deliver, 0 when unknown.
  virtual std::size_t total() const = 0;
  virtual const std::string& name() const = 0;
};

// The files read_cloud takes in `folder`, sorted by name.
std::vector<std::string> cloud_files_in(const std::string& folder);

// A folder of cloud files (every file a frame, in name order), one cloud file (one frame) or a
// bag (see open_bag): its `topic`, or when `topic` is empty its only point cloud topic (an
// InputError names them when it has several). Stamps: a bag frame's message header stamp, or the
// record time when the header has none; a file's name when it is a number (seconds, or
// nanoseconds when it is an integer of 16 digits or more, as ROS exporters name files), else the
// frame index.
std::unique_ptr<FrameSource> open_frame_source(const std::string& input, const std::string& topic);

}  // namespace iilfm::io
