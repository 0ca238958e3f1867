#include "hole_classes.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "cpu_clones.hpp"
#include "iilfm/error.hpp"

namespace iilfm::detail {

namespace {

// Counts of one band of `block` rows: observed and white pixels per column (byte masks hold 0 or
// 255, so & 1 counts), then per block, then each block with its left and right neighbours into
// `across_white` / `across_observed` (bw entries each). 16-bit counts: twice the lanes of int,
// and a block's 3 x 3 neighbourhood holds at most 9 x 64 x 64 pixels.
IILFM_AVX2_CLONES void count_band(const cv::Mat& valid, const cv::Mat& detect, int first_row,
                                  int block, int bw, std::uint16_t* __restrict column_white,
                                  std::uint16_t* __restrict column_observed,
                                  std::uint16_t* __restrict block_white,
                                  std::uint16_t* __restrict block_observed,
                                  std::uint16_t* __restrict across_white,
                                  std::uint16_t* __restrict across_observed) {
  const int cols = detect.cols;
  const int end_row = std::min(detect.rows, first_row + block);
  {  // the band's first row sets the counts (a band always has one), the others add to them
    const std::uint8_t* __restrict d = detect.ptr<std::uint8_t>(first_row);
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(first_row);
    for (int c = 0; c < cols; ++c) {
      column_observed[c] = static_cast<std::uint16_t>(m[c] & 1);
      column_white[c] = static_cast<std::uint16_t>(m[c] & d[c] & 1);
    }
  }
  for (int r = first_row + 1; r < end_row; ++r) {
    const std::uint8_t* __restrict d = detect.ptr<std::uint8_t>(r);
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      column_observed[c] = static_cast<std::uint16_t>(column_observed[c] + (m[c] & 1));
      column_white[c] = static_cast<std::uint16_t>(column_white[c] + (m[c] & d[c] & 1));
    }
  }
  const int whole = cols / block;  // blocks whose `block` columns all lie in the image
  if (block == 2) {                // the default, in a loop without an inner one, so it vectorises
    for (int bc = 0; bc < whole; ++bc) {
      block_white[bc] = static_cast<std::uint16_t>(column_white[2 * bc] + column_white[2 * bc + 1]);
      block_observed[bc] =
          static_cast<std::uint16_t>(column_observed[2 * bc] + column_observed[2 * bc + 1]);
    }
  } else {
    for (int bc = 0; bc < whole; ++bc) {
      int w = 0, n = 0;  // in registers, not added into the arrays column by column
      for (int k = bc * block; k < (bc + 1) * block; ++k) {
        w += column_white[k];
        n += column_observed[k];
      }
      block_white[bc] = static_cast<std::uint16_t>(w);
      block_observed[bc] = static_cast<std::uint16_t>(n);
    }
  }
  if (whole < bw) {  // the last, partial block
    int w = 0, n = 0;
    for (int k = whole * block; k < cols; ++k) {
      w += column_white[k];
      n += column_observed[k];
    }
    block_white[whole] = static_cast<std::uint16_t>(w);
    block_observed[whole] = static_cast<std::uint16_t>(n);
  }
  // Across: a block and its left and right neighbours, in loops without a bound per block.
  for (int bc = 0; bc < bw; ++bc) {
    across_white[bc] = block_white[bc];
    across_observed[bc] = block_observed[bc];
  }
  for (int bc = 1; bc < bw; ++bc) {
    across_white[bc] = static_cast<std::uint16_t>(across_white[bc] + block_white[bc - 1]);
    across_observed[bc] = static_cast<std::uint16_t>(across_observed[bc] + block_observed[bc - 1]);
  }
  for (int bc = 0; bc + 1 < bw; ++bc) {
    across_white[bc] = static_cast<std::uint16_t>(across_white[bc] + block_white[bc + 1]);
    across_observed[bc] = static_cast<std::uint16_t>(across_observed[bc] + block_observed[bc + 1]);
  }
}

// The class of each block of one band from the across-counts of the bands above, at and below it
// (a band off the image is a row of zeros), spread to one byte per column, then written into the
// band's unobserved pixels.
IILFM_AVX2_CLONES void write_band(const cv::Mat& valid, cv::Mat& detect, int first_row, int block,
                                  int bw, const std::uint16_t* __restrict w0,
                                  const std::uint16_t* __restrict w1,
                                  const std::uint16_t* __restrict w2,
                                  const std::uint16_t* __restrict n0,
                                  const std::uint16_t* __restrict n1,
                                  const std::uint16_t* __restrict n2, std::uint8_t* __restrict cls,
                                  std::uint8_t* __restrict hole) {
  const int cols = detect.cols;
  for (int bc = 0; bc < bw; ++bc) {
    const int w = w0[bc] + w1[bc] + w2[bc];
    const int n = n0[bc] + n1[bc] + n2[bc];
    cls[bc] = (n == 0 || 2 * w > n) ? 255 : 0;
  }
  const int whole = cols / block;
  if (block == 2) {  // the default: two bytes a block, in a loop that vectorises
    for (int bc = 0; bc < whole; ++bc) {
      const auto pair = static_cast<std::uint16_t>(cls[bc] * 0x0101u);
      std::memcpy(hole + 2 * bc, &pair, 2);
    }
  } else {
    for (int bc = 0; bc < whole; ++bc)
      for (int k = 0; k < block; ++k) hole[bc * block + k] = cls[bc];
  }
  for (int c = whole * block; c < cols; ++c) hole[c] = cls[whole];
  const int end_row = std::min(detect.rows, first_row + block);
  for (int r = first_row; r < end_row; ++r) {
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(r);
    std::uint8_t* __restrict d = detect.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c)
      d[c] = static_cast<std::uint8_t>((d[c] & m[c]) | (hole[c] & ~m[c]));  // masks: 0 or 255
  }
}

}  // namespace

void classify_holes(const cv::Mat& valid, int block, cv::Mat& detect, HoleClassBuffers& buffers) {
  if (block < 1 || block > kMaxHoleClassBlock)
    throw InputError("hole class block must be 1 to " + std::to_string(kMaxHoleClassBlock) +
                     " pixels (got " + std::to_string(block) + ")");
  const int rows = detect.rows, cols = detect.cols;
  if (rows == 0 || cols == 0) return;
  const int bw = (cols + block - 1) / block, bh = (rows + block - 1) / block;
  const auto width = static_cast<std::size_t>(bw);
  buffers.column_white.resize(static_cast<std::size_t>(cols));
  buffers.column_observed.resize(static_cast<std::size_t>(cols));
  buffers.block_white.resize(width);
  buffers.block_observed.resize(width);
  // Four slots of across-counts per kind: band b in slot b % 3, slot 3 all zeros (off the image).
  buffers.across_white.assign(4 * width, 0);
  buffers.across_observed.assign(4 * width, 0);
  buffers.block_class.resize(width);
  buffers.hole_row.resize(static_cast<std::size_t>(cols));
  const auto slot = [&](std::vector<std::uint16_t>& v, int band) {
    const int s = band < 0 || band >= bh ? 3 : band % 3;
    return v.data() + static_cast<std::size_t>(s) * width;
  };
  // Which bands hold a hole: only those are written, and only they and their neighbours counted
  // (a band without one is left as it is; on spinning LiDARs most are, measured: 106 of 178 rows
  // of a ULTRA Puck image).
  buffers.band_has_hole.assign(static_cast<std::size_t>(bh) + 2, 0);
  std::uint8_t* const has_hole = buffers.band_has_hole.data() + 1;  // [-1] and [bh] stay 0
  for (int r = 0; r < rows; ++r)
    if (std::memchr(valid.ptr<std::uint8_t>(r), 0, static_cast<std::size_t>(cols)))
      has_hole[r / block] = 1;
  // Band b is counted, then band b - 1 written, while its rows are still in cache.
  for (int band = 0; band <= bh; ++band) {
    if (band < bh && (has_hole[band - 1] | has_hole[band] | has_hole[band + 1]))
      count_band(valid, detect, band * block, block, bw, buffers.column_white.data(),
                 buffers.column_observed.data(), buffers.block_white.data(),
                 buffers.block_observed.data(), slot(buffers.across_white, band),
                 slot(buffers.across_observed, band));
    const int done = band - 1;
    if (done < 0 || !has_hole[done]) continue;
    write_band(valid, detect, done * block, block, bw, slot(buffers.across_white, done - 1),
               slot(buffers.across_white, done), slot(buffers.across_white, done + 1),
               slot(buffers.across_observed, done - 1), slot(buffers.across_observed, done),
               slot(buffers.across_observed, done + 1), buffers.block_class.data(),
               buffers.hole_row.data());
  }
}

}  // namespace iilfm::detail
