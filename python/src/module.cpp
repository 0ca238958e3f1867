// The `iilfm` Python module (built as iilfm._iilfm; python/iilfm/__init__.py re-exports it).
#include <opencv2/core/utility.hpp>
#include <string>

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
  m.def(
      "set_opencv_threads",
      [](int threads) {
        if (threads < 1)
          throw iilfm::InputError("set_opencv_threads: threads must be at least 1, got " +
                                  std::to_string(threads));
        cv::setNumThreads(threads);
      },
      py::arg("threads"),
      "Threads for OpenCV's own parallel loops in this process (the detection's contour tracing,\n"
      "ArUco's thresholds). The `iilfm` program sets it to its --threads (default 1): OpenCV's\n"
      "pool otherwise wakes for every image of over ~100k pixels, and its workers spin on the\n"
      "other cores (a fifth more CPU on a VLP-16 recording). Process-wide, so left to the caller;\n"
      "it also sets cv2's count when cv2 uses the same OpenCV library.");
  m.def(
      "opencv_threads", [] { return cv::getNumThreads(); },
      "Threads OpenCV's parallel loops may use in this process (see set_opencv_threads).");
}
