// The rtt Python module: numpy rays in, exact hits out (python/README.md documents the API).
// Every call that traces releases the GIL; errors become Python exceptions with the library's
// one-line message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <filesystem>
#include <memory>

#include "arrays.h"
#include "bound_scene.h"
#include "rtt/builtin_scenes.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/isa.h"
#include "rtt/scene_io.h"
#include "rtt/version.h"

namespace py = pybind11;
using namespace py::literals;

namespace rtt::python {
namespace {

/// Runs f; an rtt::Error (bad values: camera, sizes, limits) becomes ValueError.
template <typename F>
auto values_checked(const F& f) {
    try {
        return f();
    } catch (const Error& e) {
        throw py::value_error(e.what());
    }
}

std::shared_ptr<BoundScene> load(const std::string& source, bool strict) {
    if (is_builtin_scene(source))
        return std::make_shared<BoundScene>(make_builtin_scene(source), false);
    if (!std::filesystem::exists(source)) {
        std::string names;
        for (const BuiltinSceneInfo& s : builtin_scenes())
            names += (names.empty() ? "" : ", ") + s.name;
        const std::string message =
            "no such file or built-in scene: '" + source + "' (built-in: " + names + ")";
        PyErr_SetString(PyExc_FileNotFoundError, message.c_str());
        throw py::error_already_set();
    }
    const bool json = std::filesystem::path(source).extension() == ".json";
    try {
        Scene scene = json ? load_scene_json(source) : load_mesh_file(source);
        // strict: a file read with repairs is refused (docs/robustness.md, "Reading policy").
        if (strict && scene.warning_count > 0)
            throw Error(scene.warnings.front() + " (refused under strict=True)");
        if (json) return std::make_shared<BoundScene>(std::move(scene), false);
        // As `rtt render --mesh` reads a mesh: its materials, not its lights or camera.
        scene.lights.clear();
        scene.camera.reset();
        return std::make_shared<BoundScene>(std::move(scene), true);
    } catch (const Error& e) {
        throw std::runtime_error(e.what());
    }
}

py::dict stats_dict(const CallStats& s) {
    const TraceStats& t = s.trace;
    const RttStats& r = s.rtt;
    py::dict declined;
    for (const auto& [name, field] : declined_fields) declined[name] = r.*field;
    return py::dict("rays"_a = t.rays, "traced"_a = t.traced, "answered"_a = r.answered,
                    "tiles"_a = t.tiles, "rtt_tiles"_a = r.rtt_tiles, "declined"_a = declined,
                    "avg_list"_a = r.avg_relevant(), "seconds"_a = s.seconds,
                    "fallback_seconds"_a = r.fallback_seconds());
}

/// (t, tri) arrays of the given shape from hits, filled on `threads` threads: t = inf and
/// tri = -1 on a miss.
py::tuple hit_arrays(std::span<const Hit> hits, std::vector<py::ssize_t> shape, int threads) {
    py::array_t<float> t(shape);
    py::array_t<int64_t> tri(shape);
    float* pt = t.mutable_data();
    int64_t* pi = tri.mutable_data();
    {
        py::gil_scoped_release unlocked;
        in_arena(threads, [&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, hits.size(), 16384),
                              [&](const tbb::blocked_range<size_t>& r) {
                                  for (size_t i = r.begin(); i != r.end(); ++i) {
                                      pt[i] = hits[i].valid() ? hits[i].t : pos_inf;
                                      pi[i] = hits[i].valid() ? int64_t(hits[i].tri) : -1;
                                  }
                              });
        });
    }
    return py::make_tuple(t, tri);
}

std::shared_ptr<BoundTracer> tracer_of(const std::shared_ptr<BoundScene>& scene,
                                       const std::string& kind) {
    py::gil_scoped_release unlocked;  // the first tracer builds the kd-tree
    return values_checked([&] {
        check_tracer_kind(kind);  // before the kd-tree is built for nothing
        return std::make_shared<BoundTracer>(scene, kind);
    });
}

/// One answer per ray of the arrays, computed by answer(rays, out) without the GIL (other
/// Python threads run meanwhile).
template <typename T, typename Answer>
Unfilled<T> answer_rays(const py::handle& origins, const py::handle& directions,
                        const py::handle& tmin, const py::handle& tmax, int threads,
                        const Answer& answer) {
    const Unfilled<Ray> rays = to_rays(origins, directions, tmin, tmax, threads);
    Unfilled<T> out(rays.size());
    py::gil_scoped_release unlocked;
    values_checked([&] {
        answer(rays.span(), out.span());
        return 0;
    });
    return out;
}

}  // namespace
}  // namespace rtt::python

PYBIND11_MODULE(_rtt, m) {
    using namespace rtt;
    using namespace rtt::python;
    m.doc() = "rtt: exact visibility for coherent rays (SAH kd-tree, SIMD packets, RTT shafts)";
    m.attr("__version__") = version_string;
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {
            PyErr_SetString(PyExc_RuntimeError, e.what());
        }
    });

    m.def(
        "isa", [] { return std::string(isa_name(active_isa())); },
        "The SIMD kernels tracers made now use: 'sse4.2', 'avx2' or 'avx512' (the widest this "
        "CPU runs, capped by RTT_ISA or limit_isa).");
    m.def(
        "limit_isa", [](const std::string& isa) { limit_isa(parse_isa(isa)); }, py::arg("isa"),
        "Caps the SIMD kernels of tracers made from now on ('sse4.2', 'avx2' or 'avx512'). "
        "Results are the same bits at every ISA; only speed differs.");
    m.def("tracer_kinds", &tracer_kinds,
          "Tracer kinds this build offers ('ray', 'packet', 'rtt', ...).");
    m.def(
        "builtin_scenes",
        [] {
            std::vector<std::string> names;
            for (const BuiltinSceneInfo& s : builtin_scenes()) names.push_back(s.name);
            return names;
        },
        "Names of the built-in scenes.");
    m.def(
        "camera_rays",
        [](const py::object& camera, int width, int height, int aa, const py::object& position,
           const py::object& target, const py::object& up, const py::object& fovy) {
            const std::optional<Camera> cam = to_camera(camera, position, target, up, fovy);
            if (!cam) throw py::value_error("camera_rays: a camera is required");
            if (width < 1 || height < 1 || aa < 1)
                throw py::value_error("width, height and aa must be at least 1");
            return values_checked([&] {
                RenderOptions limits;
                limits.width = width, limits.height = height, limits.aa = aa;
                limits.validate(0);
                const CameraRays rays(*cam, width, height, aa);
                py::array_t<float> dirs(
                    {py::ssize_t(height) * aa, py::ssize_t(width) * aa, py::ssize_t(3)});
                float* d = dirs.mutable_data();
                for (int y = 0; y < height; ++y)
                    for (int j = 0; j < aa; ++j)
                        for (int x = 0; x < width; ++x)
                            for (int i = 0; i < aa; ++i, d += 3) {
                                const Vec3f v = rays.direction(x, y, i, j);
                                d[0] = v.x, d[1] = v.y, d[2] = v.z;
                            }
                const Vec3f o = rays.origin();
                return py::make_tuple(py::array_t<float>(3, &o.x), dirs);
            });
        },
        "camera"_a = py::none(), "width"_a = 640, "height"_a = 480, "aa"_a = 1, py::kw_only(),
        "position"_a = py::none(), "target"_a = py::none(), "up"_a = py::none(),
        "fovy"_a = py::none(),
        "The primary rays of CONVENTIONS: (origin (3,), directions (H*aa, W*aa, 3)) float32, "
        "sample "
        "(i, j) of pixel (x, y) at [y*aa + j, x*aa + i], bit-identical to the renderer's.");
    m.def(
        "load", &load, "source"_a, "strict"_a = false,
        "Loads a mesh file (any format assimp reads; its geometry and materials, as `rtt render "
        "--mesh`), a JSON scene file or a built-in scene name (as `rtt render --scene`). What was "
        "repaired while reading is in Scene.warnings; strict=True refuses such a file.");

    py::class_<BoundScene, std::shared_ptr<BoundScene>>(m, "Scene")
        .def_static(
            "from_arrays",
            [](const py::handle& vertices, const py::handle& triangles) {
                const std::vector<Vec3f> v = to_points(vertices, "vertices");
                const std::vector<TriangleIndices> t = to_triangles(triangles, v.size());
                return values_checked(
                    [&] { return std::make_shared<BoundScene>(Scene::from_mesh(v, t), true); });
            },
            "vertices"_a, "triangles"_a,
            "A scene from (N, 3) float32/float64 vertices (stored as float32) and (M, 3) integer "
            "triangles; triangle i keeps index i.")
        .def_property_readonly("triangle_count",
                               [](const BoundScene& s) { return s.scene().triangle_count(); })
        .def_property_readonly(
            "warnings", [](const BoundScene& s) { return s.scene().warnings; },
            "What the reader repaired or skipped (the first 16 messages)")
        .def_property_readonly("bounds",
                               [](const BoundScene& s) {
                                   const Bbox3f b = s.scene().bounds();
                                   return py::make_tuple(py::array_t<float>(3, &b.lo.x),
                                                         py::array_t<float>(3, &b.hi.x));
                               })
        .def_property_readonly("name", [](const BoundScene& s) { return s.scene().name; })
        .def("tracer", &tracer_of, "kind"_a = "rtt",
             "A tracer of this kind; the scene's kd-tree is built on the first call and kept.")
        .def_property_readonly(
            "auto_kind", &BoundScene::auto_kind,
            "The kind rtt.render's 'auto' tracer renders this scene's next frame with: 'bvh' "
            "(its BVH builds soonest) or 'rtt' (once frames have paid for the kd-tree).")
        .def("__repr__", [](const BoundScene& s) {
            return "<rtt.Scene '" + s.scene().name + "' with " +
                   std::to_string(s.scene().triangle_count()) + " triangles>";
        });

    py::class_<BoundTracer, std::shared_ptr<BoundTracer>>(m, "Tracer")
        .def_property_readonly("kind", &BoundTracer::kind)
        .def_property_readonly("scene", &BoundTracer::scene)
        .def(
            "intersect",
            [](BoundTracer& t, const py::handle& origins, const py::handle& directions,
               const py::handle& tmin, const py::handle& tmax, int threads) {
                const Unfilled<Hit> hits =
                    answer_rays<Hit>(origins, directions, tmin, tmax, threads,
                                     [&](std::span<const Ray> rays, std::span<Hit> out) {
                                         t.intersect(rays, out, threads);
                                     });
                return hit_arrays(hits.span(), {py::ssize_t(hits.size())}, threads);
            },
            "origins"_a, "directions"_a, "tmin"_a = 0.0, "tmax"_a = INFINITY, "threads"_a = 0,
            "Closest hits of arbitrary rays: (t float32, inf on a miss; tri int64, -1 on a miss).")
        .def(
            "visible",
            [](BoundTracer& t, const py::handle& origins, const py::handle& directions,
               const py::handle& tmin, const py::handle& tmax, int threads) {
                const Unfilled<Ray> rays = to_rays(origins, directions, tmin, tmax, threads);
                py::array_t<bool> out(py::ssize_t(rays.size()));
                // numpy's bool is one byte holding 0 or 1, as visible_rays writes: no copy.
                static_assert(sizeof(bool) == sizeof(uint8_t));
                const std::span<uint8_t> vis(reinterpret_cast<uint8_t*>(out.mutable_data()),
                                             rays.size());
                {
                    py::gil_scoped_release unlocked;
                    values_checked([&] {
                        t.visible(rays.span(), vis, threads);
                        return 0;
                    });
                }
                return out;
            },
            "origins"_a, "directions"_a, "tmin"_a = 0.0, "tmax"_a = INFINITY, "threads"_a = 0,
            "True where no triangle meets the ray for t in [tmin, tmax].")
        .def(
            "camera_hits",
            [](BoundTracer& t, const py::object& camera, int width, int height, int aa,
               const py::object& position, const py::object& target, const py::object& up,
               const py::object& fovy, int threads, bool with_answers) {
                const Camera cam = to_camera(camera, position, target, up, fovy)
                                       .value_or(t.scene()->default_camera());
                if (width < 1 || height < 1 || aa < 1)
                    throw py::value_error("width, height and aa must be at least 1");
                std::vector<Hit> hits;
                std::vector<SampleAnswer> answers;
                {
                    py::gil_scoped_release unlocked;
                    values_checked([&] {
                        RenderOptions limits;
                        limits.width = width, limits.height = height, limits.aa = aa;
                        limits.validate(0);
                        hits.resize(size_t(width) * size_t(height) * size_t(aa) * size_t(aa));
                        if (with_answers) answers.resize(hits.size());
                        t.camera_hits(cam, width, height, aa, hits, answers, threads);
                        return 0;
                    });
                }
                const std::vector<py::ssize_t> shape = {py::ssize_t(height) * aa,
                                                        py::ssize_t(width) * aa};
                py::tuple result = hit_arrays(hits, shape, threads);
                if (!with_answers) return result;
                py::array_t<uint8_t> how(shape);
                for (size_t i = 0; i < answers.size(); ++i)
                    how.mutable_data()[i] = uint8_t(answers[i]);
                return py::make_tuple(result[0], result[1], how);
            },
            "camera"_a = py::none(), "width"_a = 640, "height"_a = 480, "aa"_a = 1, py::kw_only(),
            "position"_a = py::none(), "target"_a = py::none(), "up"_a = py::none(),
            "fovy"_a = py::none(), "threads"_a = 0, "answers"_a = false,
            "Every primary sample of the image, traced as the renderer's shaft regions: (t, tri) "
            "arrays of "
            "shape (H*aa, W*aa), sample (i, j) of pixel (x, y) at [y*aa + j, x*aa + i]. "
            "answers=True "
            "adds a uint8 array of how each sample was answered: 0 traced, 1 RTT with an empty "
            "relevant list, 2 RTT from a list (the paper's Figure 5b).")
        .def_property_readonly("last_stats",
                               [](const BoundTracer& t) { return stats_dict(t.last_stats()); })
        .def("__repr__", [](const BoundTracer& t) { return "<rtt.Tracer '" + t.kind() + "'>"; });

    m.def(
        "render",
        [](const std::shared_ptr<BoundScene>& scene, const py::object& camera, int width,
           int height, int aa, const py::object& tracer, const py::object& lights, int max_depth,
           int threads, const py::object& position, const py::object& target, const py::object& up,
           const py::object& fovy) {
            // A tracer, a kind, or "auto": the scene's own tracer of the soonest image.
            std::shared_ptr<BoundTracer> bound;
            const bool automatic =
                !py::isinstance<BoundTracer>(tracer) && tracer.cast<std::string>() == auto_tracer;
            if (!automatic) {
                bound = py::isinstance<BoundTracer>(tracer)
                            ? tracer.cast<std::shared_ptr<BoundTracer>>()
                            : tracer_of(scene, tracer.cast<std::string>());
                if (bound->scene() != scene)
                    throw py::value_error("render: the tracer belongs to another scene");
            }
            const std::optional<Camera> cam = to_camera(camera, position, target, up, fovy);
            std::optional<std::vector<Vec3f>> light_positions;
            if (!lights.is_none()) {
                py::array a = py::array::ensure(lights);
                light_positions = a && a.ndim() == 1 && a.size() == 3
                                      ? to_points(a.reshape({1, 3}), "lights")
                                      : to_points(lights, "lights");
            }
            RenderOptions options;
            options.width = width, options.height = height, options.aa = aa;
            options.max_depth = max_depth, options.threads = threads;
            RenderResult r;
            {
                py::gil_scoped_release unlocked;
                r = values_checked([&] {
                    if (bound)
                        return render_like_cli(*scene, bound->tracer(), cam, light_positions,
                                               options);
                    const std::shared_ptr<const Tracer> own = scene->auto_tracer();
                    RenderResult frame =
                        render_like_cli(*scene, *own, cam, light_positions, options);
                    scene->auto_rendered(frame.stats.rays());
                    return frame;
                });
            }
            const std::vector<uint8_t> srgb = encode_srgb8(r.pixels);
            py::array_t<uint8_t> image(
                {py::ssize_t(r.height), py::ssize_t(r.width), py::ssize_t(3)});
            std::copy(srgb.begin(), srgb.end(), image.mutable_data());
            return image;
        },
        "scene"_a, "camera"_a = py::none(), "width"_a = 640, "height"_a = 480, "aa"_a = 1,
        "tracer"_a = auto_tracer, "lights"_a = py::none(), "max_depth"_a = 4, "threads"_a = 0,
        py::kw_only(), "position"_a = py::none(), "target"_a = py::none(), "up"_a = py::none(),
        "fovy"_a = py::none(),
        "Renders like `rtt render`: (H, W, 3) uint8 sRGB, the same pixels for the same scene, "
        "camera, size, aa and lights (positions; they replace the scene's). `tracer`: a Tracer, "
        "a kind, or 'auto' (the default), the soonest image: frames from the scene's own 'bvh' "
        "tracer until its frames have traced 300 rays per triangle (or the scene's kd-tree was "
        "built for another tracer), then from its own 'rtt' (Scene.auto_kind says which is next); "
        "every kind gives the same pixels.");
}
