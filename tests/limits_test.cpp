// Limits: requests that cannot fit in memory are refused with a clear message before anything
// is allocated; the kd-tree's depth stays bounded on adversarial input; nothing is quadratic
// (or endless) on adversarial files; outputs are whole or absent, even when the program is
// killed while rendering or writing.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bvh/bvh.h"
#include "core/large_arrays.h"
#include "geom/triangle.h"
#include "rtt/error.h"
#include "rtt/kdtree.h"
#include "rtt/memory_budget.h"
#include "rtt/render.h"
#include "rtt/scene_io.h"
#include "temp_dir.h"
#include "test_env.h"
#include "triangle_soup.h"

namespace rtt {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using test::scene_of;
using test_env::time_slack;
using test_env::under_asan;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

using test::TempDir;

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct RunResult {
    int exit_code = -1;
    std::string err;
    double seconds = 0;
};

/// Runs `rtt <args>` in `dir` through the shell, after `prefix` (e.g. "ulimit -v 3000000;").
RunResult run_cli(const TempDir& dir, const std::string& args, const std::string& prefix = "") {
    const std::string err =
        (dir.path.parent_path() / (dir.path.filename().string() + ".err")).string();
    const std::string cmd = "cd '" + dir.path.string() + "' && " + prefix + " '" +
                            std::string(RTT_CLI_PATH) + "' " + args + " >/dev/null 2>'" + err + "'";
    const auto start = Clock::now();
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.seconds = seconds_since(start);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.err = read_text(err);
    fs::remove(err);
    return r;
}

const std::string mesh_path = std::string(RTT_TEST_DATA_DIR) + "/render_mesh.obj";

// ---- memory ------------------------------------------------------------------------------

TEST(Limits, MemoryBudgetRefusesWithAClearMessage) {
    const uint64_t budget = memory_budget();
    EXPECT_GT(budget, uint64_t(64) << 20) << "a machine that runs the tests has more than 64 MiB";
    EXPECT_NO_THROW(require_memory(budget, "exactly the budget"));
    try {
        require_memory(budget + 1, "a test request");
        ADD_FAILURE() << "a request above the budget was accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind("a test request needs about ", 0), 0u) << what;
        EXPECT_NE(what.find("GiB is available"), std::string::npos) << what;
    }
}

TEST(Limits, MemoryEstimatesSaturateInsteadOfWrapping) {
    RenderOptions o;
    o.width = 100;
    o.height = 10;
    o.aa = 2;
    EXPECT_EQ(render_memory_bytes(o), 1000u * 15u);
    o.hits_buffer = o.shadow_buffer = true;
    EXPECT_EQ(render_memory_bytes(o, AnswerMaps{true, 0}), 1000u * 17u + 4000u * 16u);
    // Counts from a hostile file: no wrap-around to a small number.
    EXPECT_EQ(scene_memory_bytes(UINT64_MAX / 2, UINT64_MAX / 2), UINT64_MAX);
    EXPECT_GT(scene_memory_bytes(0, uint64_t(1) << 40), uint64_t(1) << 40);
    o.width = o.height = INT32_MAX;
    o.aa = INT32_MAX;
    EXPECT_EQ(render_memory_bytes(o), UINT64_MAX);
}

TEST(Limits, HugeImageRefusedBeforeAllocatingUnderUlimit) {
    if (under_asan)
        GTEST_SKIP()
            << "AddressSanitizer reserves terabytes of address space: ulimit -v cannot work";
    const TempDir dir("ulimit");
    const std::string limit = "ulimit -v 3000000;";  // 2.9 GiB of address space
    // 16384 x 16384 x 4 samples with both buffers: about 20 GiB.
    const RunResult big = run_cli(dir,
                                  "render --mesh '" + mesh_path +
                                      "' --size 16384x16384 --aa 2 -q --hits h.rtth --shadows "
                                      "s.rtts -o big.png",
                                  limit);
    EXPECT_EQ(big.exit_code, 1) << big.err;
    EXPECT_NE(big.err.find("rtt: error: image 16384x16384 with 2x2 antialiasing"),
              std::string::npos)
        << big.err;
    EXPECT_NE(big.err.find("needs about"), std::string::npos) << big.err;
    EXPECT_LT(big.seconds, 10.0 * time_slack) << "refused only after trying";
    EXPECT_EQ(dir.entries().size(), 0u);
    // The budget is not so conservative that ordinary work fails under the same limit.
    const RunResult small =
        run_cli(dir, "render --mesh '" + mesh_path + "' --size 64x48 -q -o small.png", limit);
    EXPECT_EQ(small.exit_code, 0) << small.err;
    EXPECT_TRUE(fs::exists(dir.file("small.png")));
}

/// A glTF file whose one mesh of `tris` triangles is instanced by `nodes` nodes.
std::string instanced_gltf(int tris, int nodes) {
    // Triangle strip-like soup: vertex i = (i, i % 7, 0), triangle k = (k, k + 1, k + 2).
    const int verts = tris + 2;
    std::string bin;
    const auto put = [&](const void* p, size_t n) { bin.append(static_cast<const char*>(p), n); };
    for (int i = 0; i < verts; ++i) {
        const float v[3] = {float(i), float(i % 7), 0.f};
        put(v, sizeof v);
    }
    for (int k = 0; k < tris; ++k) {
        const uint32_t idx[3] = {uint32_t(k), uint32_t(k + 1), uint32_t(k + 2)};
        put(idx, sizeof idx);
    }
    static const char* b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string enc;
    for (size_t i = 0; i < bin.size(); i += 3) {
        uint32_t n = uint32_t(uint8_t(bin[i])) << 16;
        if (i + 1 < bin.size()) n |= uint32_t(uint8_t(bin[i + 1])) << 8;
        if (i + 2 < bin.size()) n |= uint32_t(uint8_t(bin[i + 2]));
        enc += b64[n >> 18 & 63];
        enc += b64[n >> 12 & 63];
        enc += i + 1 < bin.size() ? b64[n >> 6 & 63] : '=';
        enc += i + 2 < bin.size() ? b64[n & 63] : '=';
    }
    const size_t vbytes = size_t(verts) * 12, ibytes = size_t(tris) * 12;
    std::string node_list, node_refs;
    for (int n = 0; n < nodes; ++n) {
        node_list += std::string(n ? "," : "") + "{\"mesh\":0,\"translation\":[0,0," +
                     std::to_string(n) + "]}";
        node_refs += std::string(n ? "," : "") + std::to_string(n);
    }
    return "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[" + node_refs +
           "]}],\"nodes\":[" + node_list +
           "],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
           "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":" +
           std::to_string(verts) + ",\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[" +
           std::to_string(verts - 1) +
           ",6,0]},{\"bufferView\":1,\"componentType\":5125,\"count\":" + std::to_string(3 * tris) +
           ",\"type\":\"SCALAR\"}],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,"
           "\"byteLength\":" +
           std::to_string(vbytes) + "},{\"buffer\":0,\"byteOffset\":" + std::to_string(vbytes) +
           ",\"byteLength\":" + std::to_string(ibytes) +
           "}],\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) +
           ",\"uri\":\"data:application/octet-stream;base64," + enc + "\"}]}";
}

TEST(Limits, InstancedSceneRefusedBeforeAllocatingUnderUlimit) {
    if (under_asan)
        GTEST_SKIP()
            << "AddressSanitizer reserves terabytes of address space: ulimit -v cannot work";
    const TempDir dir("instances");
    // 300 KB of glTF asking for 20000 x 2000 = 40 million triangles (about 10 GB with the tree).
    dir.write("many.gltf", instanced_gltf(20000, 2000));
    const RunResult r = run_cli(dir, "info --mesh many.gltf", "ulimit -v 3000000;");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("triangles needs about"), std::string::npos) << r.err;
    EXPECT_LT(r.seconds, 20.0 * time_slack);
    // Without the limit, a few instances load fine (the file itself is sound).
    const Scene few = load_mesh_file(dir.write("few.gltf", instanced_gltf(100, 3)));
    EXPECT_EQ(few.triangle_count(), 300u);
}

// ---- kd-tree depth and adversarial builds --------------------------------------------------

std::vector<TriangleVerts> nested_towards_a_point(int n) {
    // Triangles at scales 2^-k around the origin: the SAH keeps wanting to split towards the
    // origin, one level per scale, far beyond any sensible depth.
    std::vector<TriangleVerts> t;
    for (int k = 0; k < n; ++k) {
        const float s = std::ldexp(1.f, -k % 120);
        t.push_back({{s, 0, 0}, {0, s, 0}, {0, 0, s}});
        t.push_back({{-s, 0, 0}, {0, -s, 0}, {0, 0, -s}});
    }
    return t;
}

std::vector<TriangleVerts> crossing_needles(int n) {
    // n thin triangles along x and n along y in the same plane: every split separating one
    // family cuts through all of the other (the classic kd-tree reference blow-up).
    std::vector<TriangleVerts> t;
    for (int i = 0; i < n; ++i) {
        const float c = float(i) / float(n);
        t.push_back({{0, c, 0}, {1, c, 0}, {1, c + 1e-4f, 0}});
        t.push_back({{c, 0, 0}, {c, 1, 0}, {c + 1e-4f, 1, 0}});
    }
    return t;
}

struct AdversarialCase {
    const char* name;
    std::vector<TriangleVerts> tris;
};

std::vector<AdversarialCase> adversarial_cases() {
    return {{"nested towards a point", nested_towards_a_point(20000)},
            {"crossing needles", crossing_needles(20000)},
            {"identical", std::vector<TriangleVerts>(200000, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})}};
}

TEST(Limits, KdTreeDepthAndSizeStayBoundedOnAdversarialInput) {
    for (const AdversarialCase& c : adversarial_cases()) {
        const auto start = Clock::now();
        const KdTree tree = build_kdtree(scene_of(c.tris));
        const double s = seconds_since(start);
        const double n = double(c.tris.size());
        std::printf(
            "[ limits ] %-24s %7zu triangles: depth %2d, %8zu nodes, %9zu references, %.2f s\n",
            c.name, c.tris.size(), tree.stats.max_depth, tree.stats.nodes,
            tree.stats.triangle_references, s);
        EXPECT_LE(tree.stats.max_depth, std::min(kd_max_depth, int(8 + 1.3 * std::log2(n))))
            << c.name;
        // The reference count can grow with depth, never quadratically.
        EXPECT_LT(double(tree.stats.triangle_references), 40.0 * n) << c.name;
        EXPECT_LT(s, 20.0 * time_slack) << c.name;
    }
    KdBuildConfig deep;
    deep.max_depth = kd_max_depth + 1;
    EXPECT_THROW(build_kdtree(scene_of(crossing_needles(10)), deep), Error);
}

TEST(Limits, BvhSizeStaysBoundedOnAdversarialInput) {
    // Spatial splits copy triangles that cross their planes: never beyond the build's budget,
    // and every triangle stays listed.
    for (const AdversarialCase& c : adversarial_cases()) {
        for (const BvhBuildOptions& options : {BvhBuildOptions{}, bvh_high_quality}) {
            const auto start = Clock::now();
            const Bvh<8> bvh = build_bvh<8>(c.tris, options);
            const double s = seconds_since(start);
            size_t slots = 0;
            for (const BvhTriangles4& q : bvh.blocks)
                for (uint32_t id : q.id) slots += id != invalid_triangle;
            const double n = double(c.tris.size());
            std::printf(
                "[ limits ] %-24s BVH, spatial split budget %.2f: %8zu nodes, %9zu "
                "references, %.2f s\n",
                c.name, double(options.spatial_split_budget), bvh.nodes.size(), slots, s);
            EXPECT_GE(double(slots), n) << c.name;
            EXPECT_LE(double(slots), n * (1.0 + double(options.spatial_split_budget))) << c.name;
            EXPECT_LT(s, 20.0 * time_slack) << c.name;
        }
    }
}

// ---- adversarial files: nothing endless or quadratic ---------------------------------------

TEST(Limits, PlyWithAHugeEmptyElementIsNotWalked) {
    // Regression: the PLY structure check looped over 10^15 property-less records (a hang).
    const TempDir dir("ply");
    const std::string path = dir.write(
        "empty_element.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement junk 999999999999999\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    const auto start = Clock::now();
    try {
        const Scene s = load_mesh_file(path);
        EXPECT_EQ(s.triangle_count(), 1u);
    } catch (const Error&) {
        // Refusing it is fine too; hanging is not.
    }
    EXPECT_LT(seconds_since(start), 5.0 * time_slack);
}

TEST(Limits, RepeatedMtllibReadsTheFileOnce) {
    // Regression: each "mtllib" line re-read its file, so a 26 KB OBJ naming a 0.5 MB MTL 2000
    // times took minutes.
    const TempDir dir("mtllib");
    std::string mtl, obj;
    for (int i = 0; i < 20000; ++i) mtl += "newmtl m" + std::to_string(i) + "\nKd 0.5 0.25 1\n";
    for (int i = 0; i < 2000; ++i) obj += "mtllib m.mtl\n";
    obj += "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m7\nf 1 2 3\n";
    dir.write("m.mtl", mtl);
    const auto start = Clock::now();
    const Scene s = load_mesh_file(dir.write("many.obj", obj));
    EXPECT_LT(seconds_since(start), 5.0 * time_slack);
    ASSERT_EQ(s.triangle_count(), 1u);
    EXPECT_EQ(s.materials[s.triangle_material[0]].diffuse, (Vec3f{0.5f, 0.25f, 1.f}));
}

TEST(Limits, DeeplyNestedJsonIsAnErrorNotAStackOverflow) {
    const TempDir dir("json");
    for (const char* open_close : {"[]", "{}"}) {
        std::string text;
        const int depth = 200000;
        for (int i = 0; i < depth; ++i)
            text += open_close[0] == '[' ? std::string("[") : std::string("{\"a\":");
        for (int i = 0; i < depth; ++i) text += open_close[1];
        const auto start = Clock::now();
        EXPECT_THROW(load_scene_json(dir.write("deep.json", text)), Error) << open_close;
        EXPECT_LT(seconds_since(start), 10.0 * time_slack) << open_close;
    }
}

TEST(Limits, HugeCountsInSmallFilesAreRefusedQuickly) {
    const TempDir dir("counts");
    const std::vector<std::pair<std::string, std::string>> files = {
        {"huge.off", "OFF\n4000000000 4000000000 0\n0 0 0\n"},
        {"huge_faces.off", "OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"huge_ascii.ply",
         "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\n"
         "property float y\nproperty float z\nend_header\n0 0 0\n"},
        {"huge_binary.ply",
         "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
         "property float x\nproperty float y\nproperty float z\nend_header\n"},
        {"lowest_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n"},
        {"huge_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n"},
    };
    for (const auto& [name, text] : files) {
        const auto start = Clock::now();
        EXPECT_THROW(load_mesh_file(dir.write(name, text)), Error) << name;
        EXPECT_LT(seconds_since(start), 5.0 * time_slack) << name;
    }
}

// ---- outputs whole or absent -----------------------------------------------------------------

TEST(Limits, FailedOutputsLeaveNothingBehindAndKeepExistingFiles) {
    const TempDir dir("outputs");
    const std::string mesh = "render --mesh '" + mesh_path + "' --size 16x12 -q ";
    dir.write("old.png", "old image");
    dir.write("a_file", "not a folder");
    fs::create_directories(dir.file("a_folder"));
    const size_t before = dir.entries().size();
    struct Case {
        const char* what;
        std::string args;
    };
    const std::vector<Case> cases = {
        {"missing folder", mesh + "-o missing/x.png"},
        {"parent is a file", mesh + "--hits a_file/h.rtth"},
        {"target is a folder", mesh + "--shadows a_folder"},
        {"bad input after an existing output name", mesh + "-o old.png --camera 1,2,3"},
        {"bad K with an existing output", mesh + "-o old.png --aa 0"},
    };
    for (const Case& c : cases) {
        const RunResult r = run_cli(dir, c.args);
        EXPECT_EQ(r.exit_code, 1) << c.what << ": " << r.err;
        EXPECT_EQ(r.err.rfind("rtt: error: ", 0), 0u) << c.what << ": " << r.err;
        EXPECT_EQ(dir.entries().size(), before) << c.what << ": left a file behind";
        EXPECT_EQ(read_text(dir.file("old.png")), "old image") << c.what;
        EXPECT_TRUE(fs::is_directory(dir.file("a_folder"))) << c.what;
    }
    if (geteuid() != 0) {  // root writes into read-only folders anyway
        fs::create_directories(dir.file("locked"));
        fs::permissions(dir.file("locked"), fs::perms::owner_read | fs::perms::owner_exec);
        const RunResult r = run_cli(dir, mesh + "-o locked/x.png");
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_TRUE(fs::is_empty(dir.file("locked")));
        fs::permissions(dir.file("locked"), fs::perms::owner_all);
    }
}

/// True when `bytes` is a whole PNG: signature first, IEND chunk (and its CRC) last.
bool whole_png(const std::string& bytes) {
    static const std::string signature = "\x89PNG\r\n\x1a\n";
    static const std::string iend("\0\0\0\0IEND\xae\x42\x60\x82", 12);
    return bytes.size() > signature.size() + iend.size() && bytes.rfind(signature, 0) == 0 &&
           bytes.compare(bytes.size() - iend.size(), iend.size(), iend) == 0;
}

TEST(Limits, KilledRunNeverLeavesATruncatedOutput) {
    // The program is killed (SIGKILL: no handler runs) at moments spread over a render that
    // writes a large PNG and hit buffer. Each output must then be its old content or a whole
    // new file; at most hidden temporaries may remain.
    const TempDir dir("kill");
    const std::string old_png = "old image", old_hits = "old hits";
    const std::vector<std::string> argv_strings = {
        RTT_CLI_PATH, "render", "--mesh", mesh_path,           "--size", "1200x900",          "-q",
        "--threads",  "2",      "-o",     dir.file("out.png"), "--hits", dir.file("out.rtth")};
    const auto run = [&](double kill_after) {
        std::ofstream(dir.file("out.png"), std::ios::binary) << old_png;
        std::ofstream(dir.file("out.rtth"), std::ios::binary) << old_hits;
        const pid_t pid = fork();
        if (pid == 0) {
            std::vector<char*> argv;
            for (const std::string& a : argv_strings) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            std::freopen("/dev/null", "w", stderr);
            execv(argv[0], argv.data());
            _exit(127);
        }
        const auto start = Clock::now();
        int status = 0;
        if (kill_after >= 0) {
            while (seconds_since(start) < kill_after && waitpid(pid, &status, WNOHANG) == 0)
                std::this_thread::sleep_for(std::chrono::milliseconds(2));
            kill(pid, SIGKILL);
        }
        waitpid(pid, &status, 0);
        return seconds_since(start);
    };
    const double full = run(-1.0);  // measures a whole run
    ASSERT_TRUE(whole_png(read_text(dir.file("out.png"))));
    int killed_mid_write = 0;
    for (int i = 1; i <= 12; ++i) {
        run(full * i / 12.0);
        const std::string png = read_text(dir.file("out.png"));
        const std::string hits = read_text(dir.file("out.rtth"));
        EXPECT_TRUE(png == old_png || whole_png(png)) << "kill " << i << ": truncated PNG";
        EXPECT_TRUE(hits == old_hits || hits.size() == 20 + 4 * 1200 * 900)
            << "kill " << i << ": truncated hit buffer (" << hits.size() << " bytes)";
        killed_mid_write += (png != old_png) != (hits != old_hits);
        for (const auto& e : fs::directory_iterator(dir.path)) {
            const std::string name = e.path().filename().string();
            // Hidden temporaries of the outputs: ".out.png.XXXX" (the file writer's) or
            // "..out.png.rtt-PID.XXXX" (the output set's, written through the file writer).
            const bool hidden_temporary = name[0] == '.' && name.find(".out.") != std::string::npos;
            EXPECT_TRUE(name == "out.png" || name == "out.rtth" || hidden_temporary)
                << "unexpected file " << name;
        }
    }
    std::printf("[ limits ] full run %.2f s; %d of 12 kills fell between the two outputs\n", full,
                killed_mid_write);
}

}  // namespace
}  // namespace rtt

// The build's large arrays (core/large_arrays.h): 2 MiB-aligned above the threshold, their
// element type's alignment below it, and ordinary vectors either way.
TEST(Limits, LargeArraysKeepAlignmentAndContents) {
    struct alignas(64) Line {
        uint32_t v[16];
    };
    rtt::large_vector<Line> small(8), large(rtt::large_array_bytes / sizeof(Line) + 1);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(small.data()) % 64, 0u);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(large.data()) % (uintptr_t(2) << 20), 0u);
    for (size_t i = 0; i < large.size(); ++i) large[i].v[i % 16] = uint32_t(i);
    large.push_back(large[7]);  // grows: a new array, contents moved
    size_t wrong = 0;
    for (size_t i = 0; i + 1 < large.size(); ++i) wrong += large[i].v[i % 16] != uint32_t(i);
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(large.back().v[7], 7u);
}
