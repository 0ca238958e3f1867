// What Pipeline.detect accepts, turned into a PointView over the caller's memory: an iilfm.Cloud,
// an (N, >=4) array of x, y, z, intensity[, ...], or a dict of columns. The caller's buffer is read
// in place when its layout allows (float32 with any strides); otherwise, and when points must be
// skipped (NaN/Inf, or x = y = z = 0, as the file readers skip them), one float32 copy is made.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bindings.hpp"

namespace iilfm::python {

struct PointsInput {
  PointView view;
  CloudStats stats;
  std::string path;  // the Cloud's file, "" for arrays
  bool copied = false;
  // When skipping made a copy: the caller's row of each kept point (to map the index image back).
  std::vector<std::int32_t> original_row;

  PointsInput() = default;
  PointsInput(const PointsInput&) = delete;
  PointsInput& operator=(const PointsInput&) = delete;

 private:
  friend std::unique_ptr<PointsInput> points_from_python(const py::handle& points);
  friend std::unique_ptr<PointsInput> points_owning(PointCloud cloud, const CloudStats& stats,
                                                    std::string path);
  PointCloud filtered_;            // the copy, when one was made
  std::vector<py::object> owned_;  // converted arrays and the caller's objects, kept alive
};

// InputError for anything that is not points, or when no valid point is left.
std::unique_ptr<PointsInput> points_from_python(const py::handle& points);

// Points the input holds itself (the union of a frame window): `copied`, no original rows.
std::unique_ptr<PointsInput> points_owning(PointCloud cloud, const CloudStats& stats,
                                           std::string path);

// A copy of the viewed points (x, y, z, intensity, and ring when there is one).
PointCloud copy_of(const PointView& view);

}  // namespace iilfm::python
