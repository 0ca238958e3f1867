// Shared pieces of the `iilfm` Python module: the cloud object, numpy views of C++ buffers, and
// the registration function of each part of the module.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm::python {

namespace py = pybind11;

// A cloud read by read_cloud() or read_frames() or made by simulate(): C++ owns the columns,
// numpy views them.
struct Cloud {
  std::shared_ptr<PointCloud> points = std::make_shared<PointCloud>();
  CloudStats stats;
  std::string path;
  std::optional<double> stamp;  // seconds; a frame of a recording only
};

// A numpy array over `data` (shape and strides in elements) that keeps `owner` alive.
template <typename T>
py::array view_of(const T* data, std::vector<py::ssize_t> shape,
                  std::vector<py::ssize_t> strides_elements, py::handle owner) {
  for (py::ssize_t& s : strides_elements) s *= static_cast<py::ssize_t>(sizeof(T));
  py::array a(py::dtype::of<T>(), std::move(shape), std::move(strides_elements), data, owner);
  // Read-only: the buffers belong to the C++ side.
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

// A read-only numpy view of a single-channel cv::Mat (CV_8U, CV_32S, CV_32F) kept alive by owner.
py::array mat_view(const cv::Mat& mat, py::handle owner);

// A row-major Eigen matrix as a new numpy array.
template <typename Matrix>
py::array_t<double> to_numpy(const Matrix& m) {
  py::array_t<double> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto w = a.mutable_unchecked<2>();
  for (py::ssize_t r = 0; r < m.rows(); ++r)
    for (py::ssize_t c = 0; c < m.cols(); ++c) w(r, c) = m(r, c);
  return a;
}

void register_cloud(py::module_& m);
void register_frames(py::module_& m);
void register_pipeline(py::module_& m);
void register_simulate(py::module_& m);

}  // namespace iilfm::python
