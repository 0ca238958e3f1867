// iilfm.Cloud and iilfm.read_cloud: files read by the C++ readers, columns shown as numpy views.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include "bindings.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"

namespace iilfm::python {

namespace {

py::array column(const py::object& self, const std::vector<float>& values) {
  return view_of(values.data(), {static_cast<py::ssize_t>(values.size())}, {1}, self);
}

py::dict stats_dict(const CloudStats& s) {
  py::dict d;
  d["points_in_file"] = s.points_in_file;
  d["valid_points"] = s.valid_points;
  d["non_finite"] = s.non_finite;
  d["zero"] = s.zero;
  return d;
}

}  // namespace

void register_cloud(py::module_& m) {
  py::class_<Cloud>(m, "Cloud",
                    "A point cloud owned by iilfm. Its columns are read-only numpy views "
                    "(no copy); Pipeline.detect reads it in place.")
      .def("__len__", [](const Cloud& c) { return c.points->size(); })
      .def_property_readonly(
          "x", [](py::object self) { return column(self, self.cast<Cloud&>().points->x); },
          "x in metres, float32 (N,)")
      .def_property_readonly(
          "y", [](py::object self) { return column(self, self.cast<Cloud&>().points->y); },
          "y in metres, float32 (N,)")
      .def_property_readonly(
          "z", [](py::object self) { return column(self, self.cast<Cloud&>().points->z); },
          "z in metres, float32 (N,)")
      .def_property_readonly(
          "intensity",
          [](py::object self) { return column(self, self.cast<Cloud&>().points->intensity); },
          "intensity in the sensor's units, float32 (N,)")
      .def_property_readonly(
          "ring",
          [](py::object self) -> py::object {
            const auto& ring = self.cast<Cloud&>().points->ring;
            if (ring.empty()) return py::none();
            return view_of(ring.data(), {static_cast<py::ssize_t>(ring.size())}, {1}, self);
          },
          "laser channel, uint16 (N,), or None when the file has none")
      .def_property_readonly(
          "time",
          [](py::object self) -> py::object {
            const auto& time = self.cast<Cloud&>().points->time;
            if (time.empty()) return py::none();
            return view_of(time.data(), {static_cast<py::ssize_t>(time.size())}, {1}, self);
          },
          "per-point time stamp in seconds, float64 (N,), or None")
      .def_property_readonly(
          "stats", [](const Cloud& c) { return stats_dict(c.stats); },
          "what the reader saw: points_in_file, valid_points, non_finite and zero (skipped)")
      .def_readonly("path", &Cloud::path,
                    "the file it was read from, 'rec.bag:/topic#12' for a frame of a recording, "
                    "'' when simulated")
      .def_readonly("stamp", &Cloud::stamp,
                    "a recording's frame: when it was taken, seconds (read_frames); else None")
      .def(
          "xyzi",
          [](const Cloud& c) {
            const PointCloud& p = *c.points;
            py::array_t<float> a({static_cast<py::ssize_t>(p.size()), py::ssize_t{4}});
            auto w = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < p.size(); ++i) {
              const auto r = static_cast<py::ssize_t>(i);
              w(r, 0) = p.x[i];
              w(r, 1) = p.y[i];
              w(r, 2) = p.z[i];
              w(r, 3) = p.intensity[i];
            }
            return a;
          },
          "A new (N, 4) float32 array of x, y, z, intensity (a copy).")
      .def("__repr__", [](const Cloud& c) {
        return "<iilfm.Cloud " + std::to_string(c.points->size()) + " points" +
               (c.path.empty() ? "" : " from " + c.path) + ">";
      });

  m.def(
      "read_cloud",
      [](const std::filesystem::path& file) {
        const std::string path = file.string();
        // The check and message of `iilfm detect`, which looks before it reads.
        if (!std::filesystem::exists(path)) throw file_error(path, "no such file or folder");
        io::LoadedCloud loaded;
        {
          py::gil_scoped_release release;
          loaded = io::read_cloud(path);
        }
        Cloud c;
        *c.points = std::move(loaded.cloud);
        c.stats = loaded.stats;
        c.path = path;
        return c;
      },
      py::arg("path"),
      "Reads a point cloud file (.pcd, .bin KITTI, ...) with the readers of the `iilfm` program.\n"
      "NaN/Inf and (0, 0, 0) points are skipped and counted in Cloud.stats.\n"
      "Raises InputError (a ValueError) with the program's message for a missing or bad file.");
}

}  // namespace iilfm::python
