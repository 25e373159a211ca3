// numpy arrays in, rtt's types out: shapes, dtypes and values checked, any memory layout
// accepted (pybind11 copies what is not C-contiguous). Bad input raises ValueError with one line.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt::python {

namespace py = pybind11;

/// (N, 3) float32 or float64 -> Vec3f (float64 rounded to the nearest float32).
std::vector<Vec3f> to_points(const py::handle& array, const char* what);

/// (M, 3) integers in [0, vertex_count) -> triangle indices.
std::vector<TriangleIndices> to_triangles(const py::handle& array, size_t vertex_count);

/// Rays from (R, 3) or (3,) origins, (R, 3) directions, and tmin / tmax given as a number or an
/// (R,) array. Values are checked by intersect_rays.
std::vector<Ray> to_rays(const py::handle& origins, const py::handle& directions,
                         const py::handle& tmin, const py::handle& tmax);

/// A camera from the command line's 10 numbers (a sequence), or from keyword values; nullopt
/// when neither is given.
std::optional<Camera> to_camera(const py::handle& numbers, const py::handle& position,
                                const py::handle& target, const py::handle& up,
                                const py::handle& fovy);

}  // namespace rtt::python
