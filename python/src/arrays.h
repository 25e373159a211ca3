// numpy arrays in, rtt's types out: shapes, dtypes and values checked, any memory layout
// accepted (pybind11 copies what is not C-contiguous). Bad input raises ValueError with one line.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
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

/// n values of an implicit-lifetime type (Ray, Hit), left unwritten for parallel loops to fill,
/// in memory from numpy's allocator, which advises huge pages for large arrays. A batch of 1M
/// rays is 32 MB: value-initialised on one thread in small pages, its first touch (page faults)
/// cost as much as tracing it (docs/benchmarks.md, "Arbitrary rays"). Made and destroyed with
/// the GIL held.
template <typename T>
class Unfilled {
public:
    explicit Unfilled(size_t n)
        : bytes_(py::ssize_t(n * sizeof(T))),
          data_(reinterpret_cast<T*>(bytes_.mutable_data())),
          size_(n) {}
    std::span<T> span() const { return {data_, size_}; }
    size_t size() const { return size_; }

private:
    py::array_t<uint8_t> bytes_;
    T* data_;
    size_t size_;
};

/// Runs f on `threads` threads (0 = all cores) of a oneTBB arena of its own.
void in_arena(int threads, const std::function<void()>& f);

/// Rays from (R, 3) or (3,) origins, (R, 3) directions, and tmin / tmax given as a number or an
/// (R,) array, made on `threads` threads. Raises ValueError, naming the first bad row, for a
/// NaN or infinite value, a zero direction or tmin > tmax.
Unfilled<Ray> to_rays(const py::handle& origins, const py::handle& directions,
                      const py::handle& tmin, const py::handle& tmax, int threads);

/// A camera from the command line's 10 numbers (a sequence), or from keyword values; nullopt
/// when neither is given.
std::optional<Camera> to_camera(const py::handle& numbers, const py::handle& position,
                                const py::handle& target, const py::handle& up,
                                const py::handle& fovy);

}  // namespace rtt::python
