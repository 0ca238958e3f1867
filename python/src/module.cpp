// The `iilfm` Python module (built as iilfm._iilfm; python/iilfm/__init__.py re-exports it).
#include "bindings.hpp"
#include "iilfm/error.hpp"

namespace iilfm::python {

py::array mat_view(const cv::Mat& mat, py::handle owner) {
  const std::vector<py::ssize_t> shape = {mat.rows, mat.cols};
  const auto row = static_cast<py::ssize_t>(mat.step1());
  switch (mat.type()) {
    case CV_8U:
      return view_of(mat.ptr<std::uint8_t>(), shape, {row, 1}, owner);
    case CV_32S:
      return view_of(mat.ptr<std::int32_t>(), shape, {row, 1}, owner);
    case CV_32F:
      return view_of(mat.ptr<float>(), shape, {row, 1}, owner);
    default:
      throw std::logic_error("mat_view: unsupported cv::Mat type " + std::to_string(mat.type()));
  }
}

}  // namespace iilfm::python

PYBIND11_MODULE(_iilfm, m) {
  namespace py = pybind11;
  m.doc() =
      "iilfm: LiDAR fiducial markers from intensity images. Read a cloud, run a Pipeline on "
      "numpy points, get corners and poses as numpy arrays.";
  // Bad input (files, options, maps) raises iilfm.InputError, a ValueError whose text is the
  // message the `iilfm` program prints after "iilfm: ".
  py::register_exception<iilfm::InputError>(m, "InputError", PyExc_ValueError);
  iilfm::python::register_cloud(m);
  iilfm::python::register_frames(m);
  iilfm::python::register_pipeline(m);
  iilfm::python::register_simulate(m);
}
