// Regression tests for the bad inputs that once crashed, hung or silently misbehaved, each with
// how it was found. (Hangs on adversarial files are in limits_test.cpp.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/parse.h"
#include "rtt/scene_io.h"

namespace rtt {
namespace {

namespace fs = std::filesystem;

struct TempFile {
    std::string path;
    TempFile(const std::string& name, const std::string& text)
        : path((fs::temp_directory_path() /
                ("rtt_regress_" + std::to_string(getpid()) + "_" + name))
                   .string()) {
        std::ofstream(path, std::ios::binary) << text;
    }
    ~TempFile() { fs::remove(path); }
};

TEST(Regress, CameraVectorsFloatCannotNormalizeAreRefused) {
    // Found by reading camera.cpp for fuzz_cli_values' property "an accepted camera spreads its
    // rays": an up vector of length 1e20 has a squared length beyond float, `right` normalized
    // to zero, and every ray of the image went straight ahead (a uniform picture, no error).
    for (const char* text : {"0,0,5,0,0,0,0,1e20,0,60",     // up too long
                             "0,0,5,0,0,0,0,1e-25,0,60",    // up too short
                             "3e19,0,0,0,0,0,0,1,0,60",     // target - position too long
                             "1e-22,0,0,0,0,0,0,1,0,60",    // too short (squared: subnormal)
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
    for (const char* bad : {"640", "x480", "640x", "640x480x2", "99999999999x1", "+640x480",
                            "640 x480", "6.5x4"})
        EXPECT_THROW(parse_size(bad, w, h), Error) << bad;
}

}  // namespace
}  // namespace rtt
