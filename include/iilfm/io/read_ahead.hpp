// Reading a recording on a thread of its own while the caller works on the frames already read:
// decompressing a bag chunk, decoding a message or parsing a PCD file overlaps the detection of
// the frame before, instead of adding to it.
#pragma once

#include <cstddef>
#include <memory>

#include "iilfm/io/frame_source.hpp"

namespace iilfm::io {

// A FrameSource that delivers what `inner` delivers, in its order, with at most `depth` frames
// read ahead of the caller (a bounded queue: a long recording never piles up in memory). An error
// `inner` raises comes after every frame it delivered before, as from `inner` itself. Destroying
// the source stops the reader after the frame it is reading; it is never left running.
std::unique_ptr<FrameSource> read_ahead(std::unique_ptr<FrameSource> inner, std::size_t depth = 2);

}  // namespace iilfm::io
