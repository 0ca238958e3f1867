#include "points_input.hpp"

#include <cmath>
#include <memory>

#include "iilfm/error.hpp"

namespace iilfm::python {

namespace {

constexpr const char* kWhatPoints =
    "points must be an (N, 4) or (N, >=4) array of x, y, z, intensity[, ...], a dict of 1-D "
    "columns x, y, z, intensity[, ring], or an iilfm.Cloud";

// A float32 view of `a` read in place when its strides allow, else of a float32 copy (kept in
// `owned`). Sets `copied` when it had to convert.
template <typename T>
StridedColumn<T> column_of(const py::array& a, std::vector<py::object>& owned, bool& copied) {
  if (a.dtype().is(py::dtype::of<T>()) && a.strides(0) % static_cast<py::ssize_t>(sizeof(T)) == 0)
    return {static_cast<const T*>(a.data()), a.strides(0) / static_cast<py::ssize_t>(sizeof(T))};
  auto converted = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!converted) throw InputError(std::string(kWhatPoints) + "; a column is not numeric");
  owned.push_back(converted);
  copied = true;
  return {converted.data(), 1};
}

py::array as_array(const py::handle& obj, std::vector<py::object>& owned) {
  py::array a = py::array::ensure(obj);
  if (!a) throw InputError(kWhatPoints);
  owned.push_back(a);
  return a;
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

void from_dict(const py::dict& d, PointsInput& in, std::vector<py::object>& owned) {
  StridedColumn<float>* targets[] = {&in.view.x, &in.view.y, &in.view.z, &in.view.intensity};
  const char* names[] = {"x", "y", "z", "intensity"};
  py::ssize_t n = -1;
  auto check_length = [&](const py::array& a, const char* name) {
    if (a.ndim() != 1)
      throw InputError(std::string("points['") + name + "'] must be 1-D, got shape " +
                       shape_text(a));
    if (n >= 0 && a.shape(0) != n)
      throw InputError(std::string("points['") + name + "'] has " + std::to_string(a.shape(0)) +
                       " values but points['x'] has " + std::to_string(n));
    n = a.shape(0);
  };
  for (int k = 0; k < 4; ++k) {
    if (!d.contains(names[k]))
      throw InputError(std::string(kWhatPoints) + "; the dict has no '" + names[k] + "'");
    const py::array a = as_array(d[names[k]], owned);
    check_length(a, names[k]);
    *targets[k] = column_of<float>(a, owned, in.copied);
  }
  if (d.contains("ring") && !d["ring"].is_none()) {
    const py::array a = as_array(d["ring"], owned);
    check_length(a, "ring");
    in.view.ring = column_of<std::uint16_t>(a, owned, in.copied);
  }
  in.view.count = static_cast<std::size_t>(n);
}

void from_array(const py::handle& obj, PointsInput& in, std::vector<py::object>& owned) {
  py::array a = as_array(obj, owned);
  if (a.ndim() != 2 || a.shape(1) < 4)
    throw InputError(std::string(kWhatPoints) + "; got shape " + shape_text(a));
  const bool in_place =
      a.dtype().is(py::dtype::of<float>()) && a.strides(0) % 4 == 0 && a.strides(1) % 4 == 0;
  if (!in_place) {
    // One copy of the four used columns; the rest of a wide array is never touched.
    const py::object four =
        a[py::make_tuple(py::slice(py::none(), py::none(), py::none()), py::slice(0, 4, 1))];
    a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(four);
    if (!a) throw InputError(std::string(kWhatPoints) + "; the array is not numeric");
    owned.push_back(a);
    in.copied = true;
  }
  const auto* base = static_cast<const float*>(a.data());
  const py::ssize_t row = a.strides(0) / 4, col = a.strides(1) / 4;
  in.view.x = {base, row};
  in.view.y = {base + col, row};
  in.view.z = {base + 2 * col, row};
  in.view.intensity = {base + 3 * col, row};
  in.view.count = static_cast<std::size_t>(a.shape(0));
}

// Skips what the file readers skip, into a copy, only when there is something to skip.
void skip_invalid(PointsInput& in, PointCloud& filtered) {
  const PointView& v = in.view;
  std::size_t non_finite = 0, zero = 0;
  auto classify = [&](std::size_t i) {
    const float x = v.x[i], y = v.y[i], z = v.z[i];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) ||
        !std::isfinite(v.intensity[i]))
      return 1;
    return (x == 0 && y == 0 && z == 0) ? 2 : 0;
  };
  for (std::size_t i = 0; i < v.size(); ++i) {
    const int c = classify(i);
    non_finite += c == 1;
    zero += c == 2;
  }
  in.stats.non_finite += non_finite;
  in.stats.zero += zero;
  in.stats.valid_points -= non_finite + zero;
  if (non_finite + zero == 0) return;

  filtered.reserve(v.size() - non_finite - zero, v.has_ring());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (classify(i) != 0) continue;
    filtered.push_back(v.x[i], v.y[i], v.z[i], v.intensity[i]);
    if (v.has_ring()) filtered.ring.push_back(v.ring[i]);
    in.original_row.push_back(static_cast<std::int32_t>(i));
  }
  in.view = PointView(filtered);
  in.copied = true;
}

}  // namespace

std::unique_ptr<PointsInput> points_from_python(const py::handle& points) {
  auto in = std::make_unique<PointsInput>();
  std::vector<py::object>& owned = in->owned_;
  owned.push_back(py::reinterpret_borrow<py::object>(points));
  if (py::isinstance<Cloud>(points)) {
    const Cloud& cloud = points.cast<const Cloud&>();
    in->view = PointView(*cloud.points);
    in->stats = cloud.stats;
    in->path = cloud.path;
  } else {
    if (py::isinstance<py::dict>(points))
      from_dict(points.cast<py::dict>(), *in, owned);
    else
      from_array(points, *in, owned);
    in->stats.points_in_file = in->stats.valid_points = in->view.size();
  }
  skip_invalid(*in, in->filtered_);
  if (in->view.empty()) {
    const CloudStats& s = in->stats;
    throw file_error(in->path.empty() ? "points" : in->path,
                     "no valid points (" + std::to_string(s.non_finite) + " non-finite, " +
                         std::to_string(s.zero) + " zero, of " + std::to_string(s.points_in_file) +
                         ")");
  }
  return in;
}

std::unique_ptr<PointsInput> points_owning(PointCloud cloud, const CloudStats& stats,
                                           std::string path) {
  auto in = std::make_unique<PointsInput>();
  in->filtered_ = std::move(cloud);
  in->view = PointView(in->filtered_);
  in->stats = stats;
  in->path = std::move(path);
  in->copied = true;
  return in;
}

PointCloud copy_of(const PointView& view) {
  PointCloud cloud;
  cloud.reserve(view.size(), view.has_ring());
  for (std::size_t i = 0; i < view.size(); ++i) {
    cloud.push_back(view.x[i], view.y[i], view.z[i], view.intensity[i]);
    if (view.has_ring()) cloud.ring.push_back(view.ring[i]);
  }
  return cloud;
}

}  // namespace iilfm::python
