#include "arrays.h"

#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdint>

namespace rtt::python {
namespace {

std::string shape_of(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

py::array as_array(const py::handle& h, const char* what) {
    try {
        return py::array::ensure(h);
    } catch (const py::error_already_set&) {
        throw py::value_error(std::string(what) + ": not an array");
    }
}

/// An (n, 3) array (or (3,) when `single` is allowed) of float32/float64 read as float32 rows
/// (float64 converted once by numpy), values not yet checked.
struct Rows3 {
    py::array_t<float> array;  ///< Keeps the rows alive.
    const float* p = nullptr;
    size_t n = 0;
    Vec3f operator[](size_t i) const { return {p[3 * i], p[3 * i + 1], p[3 * i + 2]}; }
};

Rows3 view_rows3(const py::handle& h, const char* what, bool single_ok, bool& single) {
    py::array a = as_array(h, what);
    if (!a) throw py::value_error(std::string(what) + ": not an array");
    const char kind = a.dtype().kind();
    if (kind != 'f' || (a.itemsize() != 4 && a.itemsize() != 8))
        throw py::value_error(std::string(what) + ": expected float32 or float64, got " +
                              std::string(py::str(a.dtype())));
    single = single_ok && a.ndim() == 1 && a.shape(0) == 3;
    if (!single && (a.ndim() != 2 || a.shape(1) != 3))
        throw py::value_error(std::string(what) + ": expected shape (N, 3), got " + shape_of(a));
    Rows3 rows;
    rows.array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    rows.p = rows.array.data();
    rows.n = single ? 1 : size_t(a.shape(0));
    return rows;
}

std::string non_finite_row(const char* what, size_t i) {
    return std::string(what) + ": row " + std::to_string(i) +
           " has a NaN or infinite value (or one beyond float32 range)";
}

/// A number, or an (n,) float array, as n floats: value when `p` is null, else p[i].
struct PerRay {
    py::array_t<float> array;  ///< Keeps the values alive.
    const float* p = nullptr;
    float value = 0.f;
    float operator[](size_t i) const { return p ? p[i] : value; }
};

PerRay view_per_ray(const py::handle& h, size_t n, const char* what) {
    PerRay v;
    if (py::isinstance<py::float_>(h) || py::isinstance<py::int_>(h)) {
        v.value = h.cast<float>();
        return v;
    }
    py::array a = as_array(h, what);
    if (a.ndim() == 0) {
        v.value = a.cast<float>();
        return v;
    }
    if (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
        throw py::value_error(std::string(what) + ": expected a number or a float array");
    if (a.ndim() != 1 || size_t(a.shape(0)) != n)
        throw py::value_error(std::string(what) + ": expected a number or shape (" +
                              std::to_string(n) + ",), got " + shape_of(a));
    v.array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    v.p = v.array.data();
    return v;
}

}  // namespace

std::vector<Vec3f> to_points(const py::handle& array, const char* what) {
    bool single = false;
    const Rows3 rows = view_rows3(array, what, false, single);
    std::vector<Vec3f> out(rows.n);
    for (size_t i = 0; i < rows.n; ++i) {
        out[i] = rows[i];
        if (!is_finite(out[i])) throw py::value_error(non_finite_row(what, i));
    }
    return out;
}

void in_arena(int threads, const std::function<void()>& f) {
    if (threads < 0) throw py::value_error("threads must be at least 0 (0 = all cores)");
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute(f);
}

std::vector<TriangleIndices> to_triangles(const py::handle& h, size_t vertex_count) {
    py::array a = as_array(h, "triangles");
    const char kind = a.dtype().kind();
    if (kind != 'i' && kind != 'u')
        throw py::value_error("triangles: expected an integer array, got " +
                              std::string(py::str(a.dtype())));
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw py::value_error("triangles: expected shape (M, 3), got " + shape_of(a));
    const auto v = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    if (kind == 'u' && a.itemsize() == 8) {
        // uint64 beyond int64 would wrap in the cast: check on the original values.
        const auto u = py::array_t<uint64_t, py::array::c_style | py::array::forcecast>::ensure(a);
        for (py::ssize_t i = 0; i < u.size(); ++i)
            if (u.data()[i] >= vertex_count)
                throw py::value_error("triangles: index " + std::to_string(u.data()[i]) +
                                      " out of range for " + std::to_string(vertex_count) +
                                      " vertices");
    }
    const size_t m = size_t(a.shape(0));
    std::vector<TriangleIndices> out(m);
    for (size_t i = 0; i < m; ++i)
        for (int k = 0; k < 3; ++k) {
            const int64_t x = v.data()[3 * i + size_t(k)];
            if (x < 0 || uint64_t(x) >= vertex_count)
                throw py::value_error("triangles: row " + std::to_string(i) + " has index " +
                                      std::to_string(x) + ", out of range for " +
                                      std::to_string(vertex_count) + " vertices");
            out[i][size_t(k)] = uint32_t(x);
        }
    return out;
}

Unfilled<Ray> to_rays(const py::handle& origins, const py::handle& directions,
                      const py::handle& tmin, const py::handle& tmax, int threads) {
    bool one_origin = false, unused = false;
    const Rows3 org = view_rows3(origins, "origins", true, one_origin);
    const Rows3 dir = view_rows3(directions, "directions", false, unused);
    if (!one_origin && org.n != dir.n)
        throw py::value_error("origins and directions differ in length (" + std::to_string(org.n) +
                              " and " + std::to_string(dir.n) + ")");
    const size_t n = dir.n;
    const PerRay t0 = view_per_ray(tmin, n, "tmin"), t1 = view_per_ray(tmax, n, "tmax");
    const auto ray = [&](size_t i) { return Ray{org[one_origin ? 0 : i], dir[i], t0[i], t1[i]}; };
    const auto good = [](const Ray& r) {
        return is_finite(r.org) && is_finite(r.dir) && r.dir != Vec3f{0.f} && !std::isnan(r.tmin) &&
               !std::isnan(r.tmax) && r.tmin <= r.tmax;
    };
    Unfilled<Ray> rays(n);
    bool all_good = true;
    {
        py::gil_scoped_release unlocked;  // the arrays stay referenced by org, dir, t0, t1
        in_arena(threads, [&] {
            all_good = tbb::parallel_reduce(
                tbb::blocked_range<size_t>(0, n, 4096), true,
                [&](const tbb::blocked_range<size_t>& r, bool ok) {
                    for (size_t i = r.begin(); i != r.end(); ++i) {
                        rays.span()[i] = ray(i);
                        ok &= good(rays.span()[i]);
                    }
                    return ok;
                },
                std::logical_and<>());
        });
    }
    if (all_good) return rays;
    // The first fault in the order the checks have always run: every origin, every direction,
    // then each ray's direction and interval.
    for (size_t i = 0; i < org.n; ++i)
        if (!is_finite(org[i])) throw py::value_error(non_finite_row("origins", i));
    for (size_t i = 0; i < n; ++i)
        if (!is_finite(dir[i])) throw py::value_error(non_finite_row("directions", i));
    for (size_t i = 0; i < n; ++i) {
        if (dir[i] == Vec3f{0.f})
            throw py::value_error("directions: row " + std::to_string(i) + " is zero");
        if (!good(ray(i)))
            throw py::value_error("ray " + std::to_string(i) + ": tmin > tmax or a NaN bound");
    }
    return rays;
}

std::optional<Camera> to_camera(const py::handle& numbers, const py::handle& position,
                                const py::handle& target, const py::handle& up,
                                const py::handle& fovy) {
    const bool keywords =
        !position.is_none() || !target.is_none() || !up.is_none() || !fovy.is_none();
    if (!numbers.is_none() && keywords)
        throw py::value_error(
            "camera: give the 10 numbers or position=, target=, up=, fovy=, not both");
    const auto vec = [](const py::handle& h, const char* what) {
        const std::vector<float> v = h.cast<std::vector<float>>();
        if (v.size() != 3)
            throw py::value_error(std::string("camera: ") + what + " needs 3 numbers");
        return Vec3f{v[0], v[1], v[2]};
    };
    Camera c;
    if (!numbers.is_none()) {
        std::vector<float> v;
        try {
            v = numbers.cast<std::vector<float>>();
        } catch (const py::cast_error&) {
            throw py::value_error("camera: expected 10 numbers px,py,pz,tx,ty,tz,ux,uy,uz,fovy");
        }
        if (v.size() != 10)
            throw py::value_error(
                "camera: expected 10 numbers px,py,pz,tx,ty,tz,ux,uy,uz,fovy, got " +
                std::to_string(v.size()));
        c = Camera{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9]};
    } else if (keywords) {
        if (position.is_none() || target.is_none())
            throw py::value_error("camera: position= and target= are required");
        c.position = vec(position, "position");
        c.target = vec(target, "target");
        if (!up.is_none()) c.up = vec(up, "up");
        if (!fovy.is_none()) c.fovy_deg = fovy.cast<float>();
    } else {
        return std::nullopt;
    }
    if (!is_finite(c.position) || !is_finite(c.target) || !is_finite(c.up) ||
        !std::isfinite(c.fovy_deg))
        throw py::value_error("camera: NaN or infinite value");
    return c;
}

}  // namespace rtt::python
