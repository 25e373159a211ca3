// Regression tests for the bad inputs that once crashed, hung or silently misbehaved, each with
// how it was found. (Hangs on adversarial files are in limits_test.cpp.)
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_values.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/io.h"
#include "rtt/scene_io.h"
#include "scene/assimp_sandbox.h"
#include "scene/importers.h"

namespace rtt {
namespace {

namespace fs = std::filesystem;

struct TempFile {
    std::string path;
    TempFile(const std::string& name, const std::string& text)
        : path(
              (fs::temp_directory_path() / ("rtt_regress_" + std::to_string(getpid()) + "_" + name))
                  .string()) {
        std::ofstream(path, std::ios::binary) << text;
    }
    ~TempFile() { fs::remove(path); }
};

TEST(Regress, CameraVectorsFloatCannotNormalizeAreRefused) {
    // Found by reading camera.cpp for fuzz_cli_values' property "an accepted camera spreads its
    // rays": an up vector of length 1e20 has a squared length beyond float, `right` normalized
    // to zero, and every ray of the image went straight ahead (a uniform picture, no error).
    for (const char* text : {"0,0,5,0,0,0,0,1e20,0,60",         // up too long
                             "0,0,5,0,0,0,0,1e-25,0,60",        // up too short
                             "3e19,0,0,0,0,0,0,1,0,60",         // target - position too long
                             "1e-22,0,0,0,0,0,0,1,0,60",        // too short (squared: subnormal)
                             "-3e38,0,0,3e38,0,0,0,1,0,60"}) {  // difference overflows
        const Camera c = parse_camera(text);
        EXPECT_THROW(CameraRays(c, 8, 8, 1), Error) << text;
    }
    // Long but representable vectors still work, with unit directions.
    const CameraRays ok(parse_camera("1e17,0,0,0,0,0,0,1e15,0,60"), 8, 8, 1);
    EXPECT_NEAR(length(ok.direction(0, 0, 0, 0)), 1.f, 1e-6f);
    EXPECT_NE(ok.direction(0, 0, 0, 0), ok.direction(7, 7, 0, 0));
}

TEST(Regress, ObjIndexOfTheLowestInt64IsAnError) {
    // Found by reading import_obj.cpp: "-v > count" negated INT64_MIN (undefined behaviour,
    // UBSan: "negation of -9223372036854775808 cannot be represented").
    const TempFile f("lowest.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n");
    EXPECT_THROW(load_mesh_file(f.path), Error);
}

TEST(Regress, BufferHeaderWhoseSampleCountWrapsIsRefused) {
    // Found by fuzz_buffers in its first 21 s: width * height * spp wrapped around 2^64 (and 4 *
    // count once more), so a 24-byte RTTS file passed the size check and the reader asked for a
    // vector of 2^62 elements (std::length_error, not rtt::Error). The same wrap let a header
    // claiming 2^31 x 2^31 pixels with 4 samples "match" an empty payload.
    const std::string wrapped("RTTS\x01\0\0\0\0\0\0\x01\0\x80\0\x01\0\0\0\x03\0\0\0\0", 24);
    const TempFile a("wrapped.rtts", wrapped);
    EXPECT_THROW(read_shadow_buffer(a.path), Error);
    const std::string empty("RTTH\x01\0\0\0\0\0\0\x80\0\0\0\x80\x04\0\0\0", 20);
    const TempFile b("empty.rtth", empty);
    EXPECT_THROW(read_hit_buffer(b.path), Error);
    // A header whose count fits is still read.
    const TempFile c("ok.rtth",
                     std::string("RTTH\x01\0\0\0\x01\0\0\0\x01\0\0\0\x01\0\0\0\x07\0\0\0", 24));
    EXPECT_EQ(read_hit_buffer(c.path).hits, std::vector<uint32_t>{7u});
}

TEST(Regress, FileOnWhichAssimpAllocatesWithoutEndIsAnError) {
    // Found by fuzz_mesh (CI, 2026-12-04): a 3 KB COLLADA file with a polygon index out of range
    // made assimp 5.2 allocate for minutes, gigabytes, until std::bad_alloc. Its child process
    // may now grow by 1 GiB (scene/assimp_sandbox.cpp); the sanitizer build has no such cap, so
    // the test also caps the child's CPU time.
    setenv("RTT_IMPORT_CPU_SECONDS", "20", 1);
    const std::string path = std::string(RTT_TEST_DATA_DIR) + "/robust/assimp_collada_runaway.dae";
    const auto start = std::chrono::steady_clock::now();
    EXPECT_THROW(load_mesh_file(path), Error);
    unsetenv("RTT_IMPORT_CPU_SECONDS");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              60.0);
}

TEST(Regress, FileThatCrashesAssimpIsAnError) {
    // Found by fuzz_mesh after 18 s: in a COLLADA file whose <float_array> says "lount" instead
    // of "count", Debian's assimp 5.2 dereferences a null pointer, and `rtt render` died with
    // SIGSEGV. assimp now runs in a child process (scene/assimp_sandbox.h).
    const std::string path = std::string(RTT_TEST_DATA_DIR) + "/robust/assimp_collada_crash.dae";
    try {
        load_mesh_file(path);
        ADD_FAILURE() << "a file assimp crashes on loaded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("crashed on this file"), std::string::npos)
            << e.what();
        EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
    }
    // The same through the program: one line, exit status 1.
    const std::string err =
        (fs::temp_directory_path() / ("rtt_regress_" + std::to_string(getpid()) + ".err")).string();
    const int status = std::system(
        ("'" + std::string(RTT_CLI_PATH) + "' render -q --mesh '" + path + "' 2>'" + err + "'")
            .c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
    std::ifstream in(err);
    std::string line, extra;
    std::getline(in, line);
    EXPECT_EQ(line.rfind("rtt: error: ", 0), 0u) << line;
    EXPECT_FALSE(std::getline(in, extra)) << extra;
    fs::remove(err);
}

TEST(Regress, SandboxedImportGivesTheDirectImportsScene) {
    // Everything assimp's side of the import produces crosses the pipe: geometry, normals,
    // materials, camera and lights, bit for bit; and assimp's own errors keep their text.
    for (const char* name : {"camera_light.dae", "camera_light.gltf", "camera_light.glb",
                             "polygons_ascii.ply", "two_triangles.stl"}) {
        const std::string path = std::string(RTT_TEST_DATA_DIR) + "/scene_io/" + name;
        const Scene direct = detail::import_assimp(path);
        const Scene isolated = detail::import_assimp_isolated(path);
        EXPECT_EQ(detail::serialize_scene(direct), detail::serialize_scene(isolated)) << name;
        EXPECT_EQ(detail::deserialize_scene(detail::serialize_scene(direct)).triangles,
                  direct.triangles)
            << name;
    }
    const TempFile bad("bad.stl", "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0\n");
    std::string direct_error, isolated_error;
    try {
        detail::import_assimp(bad.path);
    } catch (const Error& e) {
        direct_error = e.what();
    }
    try {
        detail::import_assimp_isolated(bad.path);
    } catch (const Error& e) {
        isolated_error = e.what();
    }
    EXPECT_FALSE(direct_error.empty());
    EXPECT_EQ(isolated_error, direct_error);
}

TEST(Regress, CommandLineValuesAreStrict) {
    // parse_vec3 moved from the program into the library (for fuzz_cli_values); it now refuses
    // a trailing comma, which the old std::getline loop dropped silently.
    EXPECT_EQ(parse_vec3(" 1, +2 ,-3e-2", "--light"), (Vec3f{1.f, 2.f, -0.03f}));
    for (const char* bad : {"1,2,3,", ",1,2,3", "1,,2,3", "1,2", "1,2,3,4", "1,2,nan", "1,2,inf",
                            "1,2,1e39", "1,2,3x", "", "1 2 3", "0x1p3,0,0"})
        EXPECT_THROW(parse_vec3(bad, "--light"), Error) << bad;
    int w = 0, h = 0;
    parse_size("640x480", w, h);
    EXPECT_EQ(w, 640);
    EXPECT_EQ(h, 480);
    for (const char* bad :
         {"640", "x480", "640x", "640x480x2", "99999999999x1", "+640x480", "640 x480", "6.5x4"})
        EXPECT_THROW(parse_size(bad, w, h), Error) << bad;
}

TEST(Regress, OutputOntoAFolderSaysSo) {
    // Found while listing bad inputs for docs/robustness.md: `rtt render --shadows .` rendered,
    // then failed with "cannot write file: Device or resource busy" (rename onto ".").
    const fs::path dir =
        fs::temp_directory_path() / ("rtt_regress_" + std::to_string(getpid()) + "_dir");
    fs::create_directories(dir);
    for (const std::string& path : {dir.string(), dir.string() + "/."}) {
        try {
            write_hit_buffer(path, HitBuffer{1, 1, 1, {0u}});
            ADD_FAILURE() << "wrote onto a folder: " << path;
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), path + ": is a directory, not a file");
        }
    }
    EXPECT_TRUE(fs::is_empty(dir)) << "a temporary was left behind";
    fs::remove_all(dir);
}

}  // namespace
}  // namespace rtt
