#pragma once

// numpy arrays over buffers the C++ side owns: the array takes the buffer over (moved into a
// capsule that frees it with the array), so nothing is copied on the way out.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace cleanmap::python {
namespace py = pybind11;

template <typename T>
py::array_t<T> take_vector(std::vector<T> v) {
  auto* owned = new std::vector<T>(std::move(v));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>({static_cast<py::ssize_t>(owned->size())}, {static_cast<py::ssize_t>(sizeof(T))},
                        owned->data(), free);
}

// A 3 x N column-major matrix is N x 3 row-major in memory: the (N, 3) float32 array users expect.
inline py::array_t<float> take_points(Eigen::Matrix3Xf m) {
  auto* owned = new Eigen::Matrix3Xf(std::move(m));
  py::capsule free(owned, [](void* p) { delete static_cast<Eigen::Matrix3Xf*>(p); });
  return py::array_t<float>({static_cast<py::ssize_t>(owned->cols()), py::ssize_t{3}},
                            {static_cast<py::ssize_t>(3 * sizeof(float)), static_cast<py::ssize_t>(sizeof(float))},
                            owned->data(), free);
}

inline py::array_t<double> pose_array(const Eigen::Isometry3d& pose) {
  py::array_t<double> a({4, 4});
  auto m = a.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = pose.matrix()(r, c);
  }
  return a;
}

}  // namespace cleanmap::python
