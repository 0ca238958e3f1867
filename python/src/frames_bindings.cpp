// iilfm.read_frames: a recording (a bag topic, or a folder of cloud files) as an iterator of
// Clouds with their stamps, read by the readers of `iilfm detect`.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <optional>

#include "bindings.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/frame_source.hpp"
#include "iilfm/io/read_ahead.hpp"

namespace iilfm::python {

namespace {

class FrameReader {
 public:
  explicit FrameReader(std::unique_ptr<io::FrameSource> source) : source_(std::move(source)) {}

  Cloud next() {
    io::Frame frame;
    bool got;
    {
      py::gil_scoped_release release;  // decompression and decoding
      got = source_->next(frame);
    }
    if (!got) throw py::stop_iteration();
    Cloud cloud;
    *cloud.points = std::move(frame.loaded.cloud);
    cloud.stats = frame.loaded.stats;
    cloud.path = frame.source;
    cloud.stamp = frame.stamp_s;
    return cloud;
  }
  std::size_t total() const { return source_->total(); }
  const std::string& name() const { return source_->name(); }

 private:
  std::unique_ptr<io::FrameSource> source_;
};

}  // namespace

void register_frames(py::module_& m) {
  py::class_<FrameReader>(m, "FrameReader",
                          "The frames of a recording, in time order: iterate for Clouds.")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &FrameReader::next)
      .def("__len__", &FrameReader::total)
      .def_property_readonly("name", &FrameReader::name, "'rec.mcap:/points' or the folder");

  m.def(
      "read_frames",
      [](const std::filesystem::path& input, const std::optional<std::string>& topic) {
        const std::string path = input.string();
        // Read ahead on a thread of its own, as `iilfm detect` does: Pipeline.detect releases
        // the GIL, so the next frames are decoded while one is detected.
        return FrameReader(io::read_ahead(io::open_frame_source(path, topic.value_or(""))));
      },
      py::arg("path"), py::arg("topic") = py::none(),
      "Reads a recording frame by frame: a bag (ROS 1 .bag, ROS 2 folder or .db3, .mcap) with\n"
      "`topic` (default: its only point cloud topic), or a folder of cloud files (in name order). "
      "Yields iilfm.Cloud objects with\n"
      "`stamp` (seconds: the message header stamp, or a numeric file name) and `path`\n"
      "('rec.mcap:/points#12'); Pipeline.detect and detect_frames take them. The next two\n"
      "frames are read ahead on a thread of their own while the caller works.\n"
      "Raises InputError (a ValueError) with the program's message for a missing file or topic,\n"
      "and, part-way, for damage: every frame before it has been yielded.");
}

}  // namespace iilfm::python
