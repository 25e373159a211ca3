// End-to-end tests of the `rtt` program (RTT_CLI_PATH): the buffers it writes against a
// brute-force loop over all triangles, and one-line errors for every kind of bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_run.h"
#include "cli_values.h"
#include "geom/triangle.h"
#include "rtt/camera.h"
#include "rtt/io.h"
#include "rtt/tracer.h"
#include "trace/brute_force.h"

namespace rtt {
namespace {

namespace fs = std::filesystem;
using test::read_text;
using test::run_cli;
using test::RunResult;
using test::TempDir;

const std::string mesh_path = std::string(RTT_TEST_DATA_DIR) + "/render_mesh.obj";

/// The triangles of a triangle-and-polygon OBJ with only `v` and `f` lines, parsed here
/// independently of the importer: faces in file order, polygons split as fans (CONVENTIONS).
std::vector<TriangleVerts> parse_simple_obj(const std::string& path) {
    std::ifstream in(path);
    std::vector<Vec3f> v;
    std::vector<TriangleVerts> tris;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            Vec3f p;
            ls >> p.x >> p.y >> p.z;
            v.push_back(p);
        } else if (tag == "f") {
            std::vector<int> idx;
            int i;
            while (ls >> i) idx.push_back(i - 1);
            for (size_t k = 2; k < idx.size(); ++k)
                tris.push_back({v[idx[0]], v[idx[k - 1]], v[idx[k]]});
        }
    }
    return tris;
}

Bbox3f bounds_of(const std::vector<TriangleVerts>& tris) {
    Bbox3f b;
    for (const TriangleVerts& t : tris) {
        b.extend(t.v0);
        b.extend(t.v1);
        b.extend(t.v2);
    }
    return b;
}

/// The "done when": the CLI's RTTH matches brute force over all triangles on every
/// sample, for every exact tracer this build has; the RTTS follows CONVENTIONS' segments.
TEST(Cli, RenderedBuffersMatchBruteForce) {
    const TempDir dir("buffers");
    const std::vector<TriangleVerts> tris = parse_simple_obj(mesh_path);
    ASSERT_EQ(tris.size(), 257u);
    const int w = 61, h = 47, k = 2;  // not multiples of 4: padded tiles
    const std::vector<Vec3f> lights = {{1.5f, 2.5f, 2.f}, {-3.f, 1.f, 1.f}};
    const std::string camera_text = "0.5,1.6,5,0,0.8,-1,0,1,0,55";
    const Camera given = parse_camera(camera_text);
    const Camera automatic = default_camera_for(bounds_of(tris));
    std::vector<std::string> kinds;
    for (const std::string& kind : tracer_kinds())
        if (kind.rfind("embree", 0) != 0) kinds.push_back(kind);  // Embree is not exact by contract
    // `rtt render`'s default, `auto`, where this build has it: bvh for a single frame.
    if (std::count(kinds.begin(), kinds.end(), "bvh") &&
        std::count(kinds.begin(), kinds.end(), "rtt"))
        kinds.push_back("auto");
    for (const std::string& kind : kinds) {
        for (const bool own_camera : {true, false}) {
            SCOPED_TRACE(kind + (own_camera ? " --camera" : " default camera"));
            const RunResult r = run_cli(
                dir, "render --mesh '" + mesh_path +
                         "' --size 61x47 --aa 2 --light 1.5,2.5,2 --light -3,1,1 "
                         "--tracer " +
                         kind + " --threads 2 -q --hits h.rtth --shadows s.rtts -o image.png" +
                         (own_camera ? " --camera " + camera_text : std::string()));
            ASSERT_EQ(r.exit_code, 0) << r.err;
            const HitBuffer hb = read_hit_buffer(dir.file("h.rtth"));
            const ShadowBuffer sb = read_shadow_buffer(dir.file("s.rtts"));
            ASSERT_EQ(hb.width, uint32_t(w));
            ASSERT_EQ(hb.height, uint32_t(h));
            ASSERT_EQ(hb.spp, uint32_t(k * k));
            ASSERT_EQ(sb.nlights, 2u);
            ASSERT_TRUE(fs::exists(dir.file("image.png")));
            const CameraRays cam(own_camera ? given : automatic, w, h, k);
            uint64_t hit_bad = 0, shadow_bad = 0, hits = 0;
            size_t s = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    for (int j = 0; j < k; ++j)
                        for (int i = 0; i < k; ++i, ++s) {
                            const Ray ray{cam.origin(), cam.direction(x, y, i, j)};
                            const Hit hit = trace_brute_force(tris, ray);
                            hit_bad += hb.hits[s] != hit.tri;
                            uint32_t expected = 0;
                            if (hit.valid()) {
                                ++hits;
                                const Vec3f p = ray.org + hit.t * ray.dir;
                                for (size_t l = 0; l < lights.size(); ++l)
                                    if (!occluded_brute_force(tris, shadow_ray(lights[l], p)))
                                        expected |= 1u << l;
                            }
                            shadow_bad += sb.bits[s] != expected;
                        }
            EXPECT_EQ(hit_bad, 0u);
            EXPECT_EQ(shadow_bad, 0u);
            EXPECT_GT(hits, uint64_t(w * h * k * k / 8));  // the view is not empty
        }
    }
}

TEST(Cli, HelpOnEverySubcommand) {
    const TempDir dir("help");
    for (const char* args : {"--help", "render --help", "info --help", "scenes --help"}) {
        const RunResult r = run_cli(dir, args);
        EXPECT_EQ(r.exit_code, 0) << args;
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << args;
    }
    EXPECT_NE(run_cli(dir, "render --help").out.find("--hits"), std::string::npos);
}

TEST(Cli, InfoAndScenes) {
    const TempDir dir("info");
    const RunResult info = run_cli(dir, "info --mesh '" + mesh_path + "'");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find("triangles                     257"), std::string::npos) << info.out;
    EXPECT_NE(info.out.find("SAH cost"), std::string::npos);
    const RunResult scenes = run_cli(dir, "scenes");
    ASSERT_EQ(scenes.exit_code, 0) << scenes.err;
    for (const char* name : {"room", "office", "plants"})
        EXPECT_NE(scenes.out.find(name), std::string::npos);
}

/// A file read with repairs renders with a warning; under --strict it is refused with one line
/// naming the repair, and nothing is written.
TEST(Cli, StrictRefusesRepairedFiles) {
    const TempDir dir("strict");
    {
        std::ofstream out(dir.file("created.obj"));
        out << "mtllib created.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl\nf 1 2 3\n";
        std::ofstream mtl(dir.file("created.mtl"));
        mtl << "newmtl\nKd 1 0 0\n";
    }
    const std::string obj = "'" + dir.file("created.obj") + "'";
    const RunResult ok =
        run_cli(dir, "render --mesh " + obj + " --size 8x8 -q -o '" + dir.file("a.png") + "'");
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_NE(ok.err.find("warning: "), std::string::npos) << ok.err;
    for (const std::string& how : {"--mesh " + obj, obj}) {
        std::string command = "render ";
        command += how;
        command += " --strict --size 8x8 -q -o '" + dir.file("b.png") + "'";
        const RunResult r = run_cli(dir, command);
        EXPECT_EQ(r.exit_code, 1) << how;
        EXPECT_NE(r.err.find("created.mtl:1: newmtl without a name"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("(refused under --strict)"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir.file("b.png")));
    }
    // A file without repairs is not affected.
    EXPECT_EQ(run_cli(dir, "render --mesh '" + mesh_path + "' --strict --size 8x8 -q -o '" +
                               dir.file("c.png") + "'")
                  .exit_code,
              0);
}

/// A file whose every triangle lies on a non-finite vertex renders as an empty scene with one
/// warning (glTF2/BoxWithInfinites.glb of assimp-testmodels is such a file): every sample a
/// miss, with every tracer; --strict refuses it (Cli.BadInputGivesOneLineError).
TEST(Cli, FileWithNothingFiniteRendersEmpty) {
    const TempDir dir("nothing_finite");
    std::ofstream(dir.file("inf.obj")) << "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    for (const char* kind : {"rtt", "ray", "packet", "frustum", "bvh"}) {
        const RunResult r = run_cli(dir, "render --mesh '" + dir.file("inf.obj") + "' --tracer " +
                                             kind + " --size 16x8 -q -o '" + dir.file("a.png") +
                                             "' --hits '" + dir.file("a.rtth") + "'");
        ASSERT_EQ(r.exit_code, 0) << kind << ": " << r.err;
        EXPECT_NE(r.err.find("the 1 triangles on them dropped: nothing is left to render"),
                  std::string::npos)
            << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        const HitBuffer hits = read_hit_buffer(dir.file("a.rtth"));
        EXPECT_EQ(hits.hits.size(), 16u * 8u);
        EXPECT_EQ(std::count(hits.hits.begin(), hits.hits.end(), invalid_triangle),
                  std::ptrdiff_t(hits.hits.size()))
            << kind;
    }
}

/// The file's cameras: --list-cameras prints them, --camera N renders from one.
TEST(Cli, CamerasOfTheFileAreListedAndPicked) {
    const TempDir dir("cameras");
    const std::string gltf = "'" + std::string(RTT_TEST_DATA_DIR) + "/scene_io/two_cameras.gltf'";
    const RunResult list = run_cli(dir, "render " + gltf + " --list-cameras");
    ASSERT_EQ(list.exit_code, 0) << list.err;
    EXPECT_NE(list.out.find("0 \"front\": --camera 0,0,3,"), std::string::npos) << list.out;
    EXPECT_NE(list.out.find("1 \"side\": --camera 3,0,0,"), std::string::npos) << list.out;
    // --camera N renders from camera N: 1 differs from 0, which is the file's default.
    const auto hits = [&](const std::string& extra, const std::string& name) {
        const RunResult r = run_cli(
            dir, "render " + gltf + extra + " --size 24x24 -q --hits '" + dir.file(name) + "'");
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return read_text(dir.file(name));
    };
    EXPECT_EQ(hits("", "default.rtth"), hits(" --camera 0", "zero.rtth"));
    EXPECT_NE(hits("", "default.rtth"), hits(" --camera 1", "one.rtth"));
    const RunResult bad = run_cli(dir, "render " + gltf + " --camera 2 -q");
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.err.find("has 2 cameras (0 to 1; --list-cameras)"), std::string::npos) << bad.err;
}

/// `rtt render FILE` is `rtt render --scene FILE`: the same hit buffer; with --mesh or --scene
/// as well it is an error.
TEST(Cli, PositionalInputIsTheScene) {
    const TempDir dir("positional");
    const std::string quoted = "'" + mesh_path + "'";
    const RunResult a =
        run_cli(dir, "render " + quoted + " --size 40x30 -q --hits '" + dir.file("a.rtth") + "'");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const RunResult b = run_cli(
        dir, "render --scene " + quoted + " --size 40x30 -q --hits '" + dir.file("b.rtth") + "'");
    ASSERT_EQ(b.exit_code, 0) << b.err;
    EXPECT_EQ(read_text(dir.file("a.rtth")), read_text(dir.file("b.rtth")));
    // A coloured glTF given alone renders with its own camera and red material; with --mesh,
    // from the default camera, in red too.
    const std::string glb = "'" + std::string(RTT_TEST_DATA_DIR) + "/scene_io/camera_light.glb'";
    const auto red_pixels = [&](const std::string& args) {
        std::string command = "render ";
        command += args;
        command += " --size 40x30 -q -o '" + dir.file("gl.ppm") + "'";
        const RunResult r = run_cli(dir, command);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        const std::string ppm = read_text(dir.file("gl.ppm"));
        EXPECT_EQ(ppm.rfind("P6", 0), 0u);
        int red = 0;
        // The header ends where the 40 x 30 RGB pixels start.
        for (size_t i = ppm.size() - std::min(ppm.size(), size_t(3 * 40 * 30)); i + 2 < ppm.size();
             i += 3)
            red += uint8_t(ppm[i]) > 2 * uint8_t(ppm[i + 1]) + 16 &&
                   uint8_t(ppm[i]) > 2 * uint8_t(ppm[i + 2]) + 16;
        return red;
    };
    EXPECT_GT(red_pixels(glb), 40 * 30 / 20);  // the two quads cover about a tenth of it
    EXPECT_GT(red_pixels("--mesh " + glb), 40 * 30 / 20);
    const RunResult info = run_cli(dir, "info room");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find("room"), std::string::npos);
    const std::vector<std::string> both_given = {"render --mesh " + quoted + " room",
                                                 "render --scene office room"};
    for (const std::string& both : both_given) {
        const RunResult r = run_cli(dir, both + " -q -o '" + dir.file("c.png") + "'");
        EXPECT_NE(r.exit_code, 0) << both;
        EXPECT_NE(r.err.find("exactly one scene"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir.file("c.png"))) << both;
    }
}

/// --save-tree then --load-tree: the same tree statistics and the same hits; a tree file for
/// another mesh, or a damaged one, is refused with one line and nothing written.
TEST(Cli, SavedTreeLoadsBack) {
    const TempDir dir("tree_file");
    const std::string mesh = "--mesh '" + mesh_path + "'";
    const RunResult saved = run_cli(dir, "info " + mesh + " --save-tree t.kdtree");
    ASSERT_EQ(saved.exit_code, 0) << saved.err;
    const RunResult loaded = run_cli(dir, "info " + mesh + " --load-tree t.kdtree");
    ASSERT_EQ(loaded.exit_code, 0) << loaded.err;
    EXPECT_NE(loaded.out.find("load time"), std::string::npos) << loaded.out;
    const auto lines_until_sah = [](const std::string& out) {
        return out.substr(0, out.find("build time") == std::string::npos ? out.find("load time")
                                                                         : out.find("build time"));
    };
    EXPECT_EQ(lines_until_sah(saved.out), lines_until_sah(loaded.out));

    const std::string render = "render " + mesh + " -q --size 37x29 --aa 2 --hits ";
    ASSERT_EQ(run_cli(dir, render + "built.rtth --save-tree r.kdtree").exit_code, 0);
    const RunResult rendered = run_cli(dir, render + "loaded.rtth --load-tree r.kdtree --stats");
    ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
    const std::string report = rendered.out + rendered.err;
    EXPECT_NE(report.find("kd-tree loaded in"), std::string::npos) << report;
    EXPECT_EQ(report.find("kd-tree build:"), std::string::npos) << report;  // no build phases
    EXPECT_EQ(read_hit_buffer(dir.file("built.rtth")).hits,
              read_hit_buffer(dir.file("loaded.rtth")).hits);
    EXPECT_EQ(read_text(dir.file("t.kdtree")), read_text(dir.file("r.kdtree")));

    std::string bytes = read_text(dir.file("t.kdtree"));
    std::ofstream(dir.file("short.kdtree"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    bytes[bytes.size() / 2] ^= 0x10;
    std::ofstream(dir.file("flipped.kdtree"), std::ios::binary) << bytes;
    const std::string other = dir.write("other.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"another mesh", "render --mesh '" + other + "' --load-tree t.kdtree"},
        {"truncated", "render " + mesh + " --load-tree short.kdtree"},
        {"bit flipped", "info " + mesh + " --load-tree flipped.kdtree"},
        {"not a tree", "info " + mesh + " --load-tree '" + other + "'"},
        {"missing", "info " + mesh + " --load-tree nowhere.kdtree"},
        {"save and load", "info " + mesh + " --load-tree t.kdtree --save-tree u.kdtree"},
    };
    const size_t files_before = dir.entries().size();
    for (const auto& [what, args] : cases) {
        const RunResult r =
            run_cli(dir, args + (args.rfind("render", 0) == 0 ? " -q -o x.png" : ""));
        EXPECT_NE(r.exit_code, 0) << what;
        EXPECT_LT(r.exit_code, 128) << what << ": crashed";
        EXPECT_EQ(r.err.rfind("rtt: error: ", 0), 0u) << what << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << ": " << r.err;
        EXPECT_EQ(dir.entries().size(), files_before) << what << ": left a file behind";
    }
}

TEST(Cli, StatsAndMaps) {
    const TempDir dir("stats");
    const RunResult r =
        run_cli(dir, "render --mesh '" + mesh_path +
                         "' --size 32x24 -q --stats --stats-json s.json "
                         "--rtt-map-primary p.png --rtt-map-shadow m.png --rtt-map-light 0");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("primary"), std::string::npos);
    EXPECT_NE(r.out.find("Mrays/s"), std::string::npos);
    const std::string json = read_text(dir.file("s.json"));
    for (const char* key : {"\"primary\"", "\"shadow\"", "\"secondary\"", "\"mrays_per_second\"",
                            "\"rays_by_depth\""})
        EXPECT_NE(json.find(key), std::string::npos) << key;
    EXPECT_TRUE(fs::exists(dir.file("p.png")));
    EXPECT_TRUE(fs::exists(dir.file("m.png")));
}

/// Each kind of bad input: non-zero exit, exactly one line on stderr starting "rtt: error:",
/// and no output file left behind.
TEST(Cli, BadInputGivesOneLineError) {
    const TempDir dir("errors");
    auto write = [&](const std::string& name, const std::string& text) {
        std::ofstream(dir.file(name)) << text;
        // Built up with += : `"'" + std::string&&` trips GCC 12's false -Wrestrict (PR 105329).
        std::string quoted = "'";
        quoted += dir.file(name);
        quoted += "'";
        return quoted;
    };
    const std::string bad_obj = write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n");
    const std::string bad_ply =
        write("bad.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n1 1\n");
    const std::string bad_json = write("bad.json", "{ \"meshes\": [ ");
    const std::string no_tris = write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    const std::string nan_obj = write("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string inf_obj = write("inf.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n");
    const std::string mesh = "--mesh '" + mesh_path + "'";
    std::string many_lights;
    for (int i = 0; i < 33; ++i) many_lights += " --light 0," + std::to_string(i) + ",1";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"missing file", "render --mesh '" + dir.file("nowhere.obj") + "'"},
        {"unreadable file (a folder)", "render --mesh '" + dir.path.string() + "'"},
        {"malformed OBJ", "render --mesh " + bad_obj},
        {"malformed PLY", "render --mesh " + bad_ply},
        {"malformed JSON", "render --scene " + bad_json},
        {"no triangles", "render --mesh " + no_tris},
        {"NaN in file, strict", "render --mesh " + nan_obj + " --strict"},
        {"inf in file, strict", "render --mesh " + inf_obj + " --strict"},
        {"NaN camera", "render " + mesh + " --camera 0,0,5,0,0,0,0,1,0,nan"},
        {"inf camera", "render " + mesh + " --camera 0,inf,5,0,0,0,0,1,0,60"},
        {"short camera", "render " + mesh + " --camera 0,0,5,0,0,0,0,1,0"},
        {"degenerate camera", "render " + mesh + " --camera 1,1,1,1,1,1,0,1,0,60"},
        {"NaN light", "render " + mesh + " --light 1,nan,0"},
        {"inf light", "render " + mesh + " --light 1,inf,0"},
        {"zero size", "render " + mesh + " --size 0x480"},
        {"absurd size", "render " + mesh + " --size 100000x100000"},
        {"absurd sample count", "render " + mesh + " --size 16384x16384 --aa 16"},
        {"malformed size", "render " + mesh + " --size 640by480"},
        {"K = 0", "render " + mesh + " --aa 0"},
        {"K = 17", "render " + mesh + " --aa 17"},
        {"K not a number", "render " + mesh + " --aa two"},
        {"33 lights", "render " + mesh + many_lights},
        {"unknown tracer", "render " + mesh + " --tracer warp"},
        {"unknown option", "render " + mesh + " --frobnicate"},
        {"unknown subcommand", "frobnicate"},
        {"unknown scene", "render --scene nowhere"},
        {"mesh and scene", "render " + mesh + " --scene room"},
        {"neither mesh nor scene", "render"},
        {"zero threads", "render " + mesh + " --threads 0"},
        {"absurd threads", "render " + mesh + " --threads 100000"},
        {"negative depth", "render " + mesh + " --max-depth -1"},
        {"missing map light", "render " + mesh + " --rtt-map-shadow m.png --rtt-map-light 5"},
        {"unwritable output",
         "render " + mesh + " --size 8x8 -o '" + dir.file("no/such/dir/x.png") + "'"},
        {"info on a missing file", "info --mesh '" + dir.file("nowhere.obj") + "'"},
    };
    const size_t files_before = dir.entries().size();
    for (const auto& [what, args] : cases) {
        // Render cases also ask for every output, to check none is left behind.
        const bool render = args.rfind("render", 0) == 0 && what != "unwritable output";
        const RunResult r =
            run_cli(dir, args + (render ? " -q -o out.png --hits h.rtth --shadows s.rtts" : ""));
        EXPECT_NE(r.exit_code, 0) << what;
        EXPECT_LT(r.exit_code, 128) << what << ": crashed";
        EXPECT_EQ(r.err.rfind("rtt: error: ", 0), 0u) << what << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << ": " << r.err;
        EXPECT_EQ(dir.entries().size(), files_before) << what << ": left a file behind";
    }
}

}  // namespace
}  // namespace rtt

namespace rtt {
namespace {

TEST(Cli, ErrorsSayHowToFixThem) {
    TempDir dir("hints");
    const auto typo = run_cli(dir, "render --scene room --sise 8x8");
    EXPECT_EQ(typo.exit_code, 2);
    EXPECT_NE(typo.err.find("Did you mean --size instead of --sise?"), std::string::npos)
        << typo.err;
    EXPECT_NE(typo.err.find("See 'rtt render --help'."), std::string::npos) << typo.err;
    const auto command = run_cli(dir, "rendr --scene room");
    EXPECT_EQ(command.exit_code, 2);
    EXPECT_NE(command.err.find("Did you mean render instead of rendr?"), std::string::npos)
        << command.err;
    const auto bench = run_cli(dir, "bench");
    EXPECT_EQ(bench.exit_code, 2);
    EXPECT_NE(bench.err.find("needs one of: table1, fig7"), std::string::npos) << bench.err;
    // Far from every option: no guess, only the help.
    const auto far = run_cli(dir, "render --scene room --zzzzzzzzzz");
    EXPECT_EQ(far.err.find("Did you mean"), std::string::npos) << far.err;
    EXPECT_NE(far.err.find("See 'rtt render --help'."), std::string::npos) << far.err;
    EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace rtt
