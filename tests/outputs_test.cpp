// What `rtt render` writes: images chosen by extension (PNG, EXR with AOV layers, PFM, PPM),
// every destination checked before any work, all outputs or none, and no silent no-op.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <thread>
#include <vector>

#include "cli_run.h"
#include "render/progress.h"
#include "rtt/error.h"
#include "rtt/io.h"
#include "rtt/tracer.h"

namespace rtt {
namespace {

using test::read_text;
using test::run_cli;
using test::TempDir;

const std::string mesh_path = std::string(RTT_TEST_DATA_DIR) + "/render_mesh.obj";

/// One channel of an EXR file, as floats (uint channels converted), or empty when missing.
std::vector<float> exr_channel(const std::string& path, const char* name, int& w, int& h) {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i box = file.header().dataWindow();
    w = box.max.x - box.min.x + 1;
    h = box.max.y - box.min.y + 1;
    if (!file.header().channels().findChannel(name)) return {};
    std::vector<float> values(size_t(w) * size_t(h));
    Imf::FrameBuffer frame;
    frame.insert(name,
                 Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data()), 4, size_t(w) * 4));
    file.setFrameBuffer(frame);
    file.readPixels(box.min.y, box.max.y);
    return values;
}

TEST(Outputs, ExrRoundTripsFloatAndUintChannels) {
    TempDir dir("exr");
    const std::vector<float> r = {0.f, 0.5f, 1.5f, -2.f, 1e30f, pos_inf};
    const std::vector<uint32_t> id = {0, 1, 2, 7, 1u << 24, invalid_triangle - 1};
    const std::vector<ExrChannel> channels = {{"R", r, {}}, {"triangle.id", {}, id}};
    write_exr(dir.file("a.exr"), 3, 2, channels);
    int w = 0, h = 0;
    EXPECT_EQ(exr_channel(dir.file("a.exr"), "R", w, h), r);
    EXPECT_EQ(w, 3);
    EXPECT_EQ(h, 2);
    Imf::InputFile file(dir.file("a.exr").c_str());
    std::vector<uint32_t> back(6);
    Imf::FrameBuffer frame;
    frame.insert("triangle.id", Imf::Slice(Imf::UINT, reinterpret_cast<char*>(back.data()), 4, 12));
    file.setFrameBuffer(frame);
    file.readPixels(0, 1);
    EXPECT_EQ(back, id);
    EXPECT_THROW(write_exr(dir.file("b.exr"), 4, 2, channels), Error);  // sizes must match
    EXPECT_FALSE(std::filesystem::exists(dir.file("b.exr")));
}

TEST(Outputs, PfmAndPnmLayouts) {
    TempDir dir("pfm");
    const std::vector<Vec3f> px = {{1, 2, 3}, {4, 5, 6}};  // a 1x2 image: top row, bottom row
    write_pfm(dir.file("a.pfm"), 1, 2, px);
    const std::string pfm = read_text(dir.file("a.pfm"));
    ASSERT_EQ(pfm.substr(0, 11), "PF\n1 2\n-1.0");
    float first[3];
    std::memcpy(first, pfm.data() + 12, sizeof first);
    EXPECT_EQ(first[0], 4.f);  // rows bottom to top
    write_pnm(dir.file("a.pgm"), 2, 1, 1, std::vector<uint8_t>{7, 9});
    EXPECT_EQ(read_text(dir.file("a.pgm")), std::string("P5\n2 1\n255\n\x07\x09", 13));
}

TEST(Outputs, ExrLayersAgreeWithTheHitBuffer) {
    TempDir dir("aov");
    const auto r = run_cli(dir,
                           "render --scene room --size 24x16 --aa 2 -q -o out.exr "
                           "--aov depth,normal,triangle,rtt --hits h.rtth --tracer rtt");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    int w = 0, h = 0;
    const std::vector<float> red = exr_channel(dir.file("out.exr"), "R", w, h);
    const std::vector<float> depth = exr_channel(dir.file("out.exr"), "depth.Z", w, h);
    const std::vector<float> nx = exr_channel(dir.file("out.exr"), "N.X", w, h);
    const std::vector<float> ny = exr_channel(dir.file("out.exr"), "N.Y", w, h);
    const std::vector<float> nz = exr_channel(dir.file("out.exr"), "N.Z", w, h);
    const std::vector<float> answered = exr_channel(dir.file("out.exr"), "rtt.Y", w, h);
    ASSERT_EQ(w, 24);
    ASSERT_EQ(h, 16);
    ASSERT_EQ(red.size(), 24u * 16u);
    ASSERT_EQ(depth.size(), red.size());
    ASSERT_EQ(answered.size(), red.size());
    // triangle.id is a uint layer: read it as such.
    Imf::InputFile file(dir.file("out.exr").c_str());
    std::vector<uint32_t> tri(red.size());
    Imf::FrameBuffer frame;
    frame.insert("triangle.id",
                 Imf::Slice(Imf::UINT, reinterpret_cast<char*>(tri.data()), 4, 24 * 4));
    file.setFrameBuffer(frame);
    file.readPixels(0, 15);
    const HitBuffer hits = read_hit_buffer(dir.file("h.rtth"));
    for (size_t p = 0; p < tri.size(); ++p) {
        EXPECT_EQ(tri[p], hits.hits[p * 4]) << p;  // the pixel's first sample (i = j = 0)
        if (tri[p] == invalid_triangle) {
            EXPECT_TRUE(std::isinf(depth[p]));
        } else {
            EXPECT_GT(depth[p], 0.f);
            EXPECT_NEAR(nx[p] * nx[p] + ny[p] * ny[p] + nz[p] * nz[p], 1.f, 1e-5f);
        }
        EXPECT_GE(answered[p], 0.f);
        EXPECT_LE(answered[p], 1.f);
    }
}

TEST(Outputs, EveryDestinationIsCheckedBeforeWork) {
    TempDir dir("check");
    struct Case {
        const char* args;
        const char* message;
    } cases[] = {
        {"-o out.png --hits /nonexistent/dir/h.rtth",
         "--hits: cannot write /nonexistent/dir/h.rtth: folder"},
        {"-o out.tiff", "unknown extension '.tiff'"},
        {"-o out.png --hits ./out.png", "is also the file of -o"},
        {"-o out.png --rtt-map-primary m.jpg", "--rtt-map-primary"},
        {"-o out.png --aov depth", "--aov writes EXR layers"},
        {"-o out.exr --aov depth,colour", "unknown output variable 'colour'"},
        {"-o out.png --hits sub", "--hits: cannot write sub: it is a folder"},
    };
    std::filesystem::create_directory(dir.file("sub"));
    for (const Case& c : cases) {
        // A scene that does not exist: the outputs must fail first, before any loading.
        const auto r = run_cli(dir, std::string("render --mesh missing.obj --size 8x8 ") + c.args);
        EXPECT_EQ(r.exit_code, 1) << c.args;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << ": " << r.err;
        const auto entries = dir.entries();
        EXPECT_EQ(std::count_if(entries.begin(), entries.end(),
                                [](const std::string& e) { return e != "sub"; }),
                  0)
            << c.args;
    }
}

TEST(Outputs, NoOutputWritesTheSceneImageAndSaysSo) {
    TempDir dir("default");
    const auto r = run_cli(dir, "render --mesh '" + mesh_path + "' --size 16x12 -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("wrote render_mesh.png"), std::string::npos) << r.out;
    EXPECT_TRUE(std::filesystem::exists(dir.file("render_mesh.png")));
    std::filesystem::remove(dir.file("render_mesh.png"));
    // Statistics alone are an output: no image then.
    const auto s = run_cli(dir, "render --mesh '" + mesh_path + "' --size 16x12 -q --stats");
    ASSERT_EQ(s.exit_code, 0) << s.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("render_mesh.png")));
}

TEST(Outputs, FloatFormatsByExtension) {
    TempDir dir("formats");
    const auto r = run_cli(
        dir, "render --mesh '" + mesh_path + "' --size 16x12 -q -o a.pfm --rtt-map-primary m.pgm");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_text(dir.file("a.pfm")).substr(0, 3), "PF\n");
    EXPECT_EQ(read_text(dir.file("m.pgm")).substr(0, 3), "P5\n");
    const auto p = run_cli(dir, "render --mesh '" + mesh_path + "' --size 16x12 -q -o a.ppm");
    ASSERT_EQ(p.exit_code, 0) << p.err;
    EXPECT_EQ(read_text(dir.file("a.ppm")).size(),
              std::string("P6\n16 12\n255\n").size() + 16 * 12 * 3);
}

}  // namespace
}  // namespace rtt

namespace rtt {
namespace {

TEST(Outputs, SkippedInputIsReportedWithItsLine) {
    TempDir dir("warnings");
    std::ofstream(dir.file("w.obj")) << "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"
                                        "usemtl shiny\nf 1 2 3\nf\n";
    const auto r = test::run_cli(dir, "render --mesh w.obj --size 8x8 -q --stats -o w.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("w.obj:1: material library missing.mtl not found"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("w.obj:5: face with 2 vertices skipped"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("w.obj:8: face with 0 vertices skipped"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("w.obj:6: material 'shiny' is in no material library"), std::string::npos)
        << r.err;
    EXPECT_NE(r.out.find("input warnings: 4"), std::string::npos) << r.out;
    // Zero-area triangles are kept (a ray can hit one edge-on) and counted in one line.
    std::ofstream(dir.file("d.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
                                        "f 1 2 3\nf 1 2 4\nf 3 3 1\n";
    const auto d = test::run_cli(dir, "render --mesh d.obj --size 8x8 -q --stats -o d.png");
    ASSERT_EQ(d.exit_code, 0) << d.err;
    EXPECT_NE(d.err.find("d.obj: 2 degenerate (zero-area) triangles kept, the first is triangle 1"),
              std::string::npos)
        << d.err;
    EXPECT_NE(d.out.find("input warnings: 1"), std::string::npos) << d.out;
}

}  // namespace
}  // namespace rtt

namespace rtt {
namespace {

bool has_auto() {
    const std::vector<std::string> kinds = tracer_kinds();
    return std::count(kinds.begin(), kinds.end(), "bvh") &&
           std::count(kinds.begin(), kinds.end(), "rtt");
}

/// The "tracer" of a --stats-json file (the kind that traced the frame).
std::string tracer_in(const std::string& path) {
    const std::string json = read_text(path);
    const size_t at = json.find("\"tracer\": \"");
    return at == std::string::npos ? json : json.substr(at + 11, 3);
}

TEST(Outputs, CameraPathRendersNumberedFramesLikeSingleRenders) {
    TempDir dir("path");
    dir.write("path.txt",
              "# three cameras\n1,1.6,4.5,3,1.2,0,0,1,0,60\n\n2,1.6,4.5,3,1.2,0,0,1,0,60\n"
              "3,1.6,4.5,3,1.2,0,0,1,0,50\n");
    const std::string common = "render --scene room --size 24x16 -q ";
    const auto r = run_cli(dir, common +
                                    "--camera-path path.txt -o f_%03d.png --hits h_%03d.rtth "
                                    "--stats-json s_%d.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto one =
        run_cli(dir, common + "--camera 2,1.6,4.5,3,1.2,0,0,1,0,60 -o one.png --hits one.rtth");
    ASSERT_EQ(one.exit_code, 0) << one.err;
    EXPECT_EQ(read_text(dir.file("f_001.png")), read_text(dir.file("one.png")));
    EXPECT_EQ(read_text(dir.file("h_001.rtth")), read_text(dir.file("one.rtth")));
    if (has_auto()) {  // the default: so few rays that every frame stays with bvh
        for (const char* f : {"s_0.json", "s_1.json", "s_2.json"})
            EXPECT_EQ(tracer_in(dir.file(f)), "bvh") << f;
    }
    EXPECT_NE(read_text(dir.file("f_000.png")), read_text(dir.file("f_001.png")));
    EXPECT_TRUE(std::filesystem::exists(dir.file("f_002.png")));
    // Names without a frame number, other '%' directives, bad lines: errors before any work.
    const auto shared = run_cli(dir, common + "--camera-path path.txt -o same.png");
    EXPECT_EQ(shared.exit_code, 1);
    EXPECT_NE(shared.err.find("3 frames need a frame number"), std::string::npos) << shared.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("same.png")));
    EXPECT_EQ(run_cli(dir, common + "--camera-path path.txt -o f%s.png").exit_code, 1);
    dir.write("bad.txt", "1,2,3\n");
    const auto bad = run_cli(dir, common + "--camera-path bad.txt -o b_%d.png");
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.err.find("bad.txt:1: camera"), std::string::npos) << bad.err;
    // Without a camera path a '%' in a name is just a character.
    EXPECT_EQ(run_cli(dir, common + "-o 'p%d.png'").exit_code, 0);
    EXPECT_TRUE(std::filesystem::exists(dir.file("p%d.png")));
}

/// `--tracer auto` renders with bvh until 300 rays per triangle have been traced, then builds
/// the kd-tree and goes on with rtt; each frame's hits and shadows equal `--tracer rtt`'s.
TEST(Outputs, AutoTracerSwitchesToRttWithTheSameFrames) {
    if (!has_auto()) GTEST_SKIP() << "this build has no bvh or rtt kind";
    TempDir dir("auto");
    // 257 triangles: 77,100 rays. A frame of 64x48 at K = 4 has 49,152 camera rays and about
    // as many shadow segments, so frame 0 pays and frames 1 and 2 come from rtt.
    dir.write("path.txt",
              "0.5,1.6,5,0,0.8,-1,0,1,0,55\n0.6,1.6,5,0,0.8,-1,0,1,0,55\n"
              "0.7,1.5,5,0,0.8,-1,0,1,0,50\n");
    const std::string common = "render --mesh '" + std::string(RTT_TEST_DATA_DIR) +
                               "/render_mesh.obj' --size 64x48 --aa 4 --light 1.5,2.5,2 -q "
                               "--camera-path path.txt ";
    const auto a =
        run_cli(dir, common + "--hits a_%d.rtth --shadows a_%d.rtts --stats-json a_%d.json");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const auto r = run_cli(dir, common + "--tracer rtt --hits r_%d.rtth --shadows r_%d.rtts");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const std::string f : {"0", "1", "2"}) {
        EXPECT_EQ(tracer_in(dir.file("a_" + f + ".json")), f == "0" ? "bvh" : "rtt") << f;
        EXPECT_EQ(read_text(dir.file("a_" + f + ".rtth")), read_text(dir.file("r_" + f + ".rtth")));
        EXPECT_EQ(read_text(dir.file("a_" + f + ".rtts")), read_text(dir.file("r_" + f + ".rtts")));
    }
}

TEST(Outputs, CameraPathAsAJsonListGivesTheSameFrames) {
    TempDir dir("json_path");
    dir.write("path.txt", "1,1.6,4.5,3,1.2,0,0,1,0,60\n2,1.6,4.5,3,1.2,0,0,1,0,50\n");
    dir.write("path.json",
              " [[1, 1.6, 4.5, 3, 1.2, 0, 0, 1, 0, 60],\n"
              "  {\"position\": [2, 1.6, 4.5], \"target\": [3, 1.2, 0], \"fovy\": 50}]\n");
    const std::string common = "render --scene room --size 24x16 -q ";
    ASSERT_EQ(run_cli(dir, common + "--camera-path path.txt -o t_%d.png").exit_code, 0);
    const auto r = run_cli(dir, common + "--camera-path path.json -o j_%d.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* f : {"0", "1"})
        EXPECT_EQ(read_text(dir.file(std::string("t_") + f + ".png")),
                  read_text(dir.file(std::string("j_") + f + ".png")));
    const auto fails = [&](const std::string& json, const std::string& message) {
        dir.write("bad.json", json);
        const auto b = run_cli(dir, common + "--camera-path bad.json -o b_%d.png");
        EXPECT_EQ(b.exit_code, 1) << json;
        EXPECT_NE(b.err.find(message), std::string::npos) << json << ": " << b.err;
    };
    fails("[[1, 2, 3]]", "bad.json: camera 1: camera: expected 10 numbers");
    fails("[{\"position\": [0, 0, 1]}]", "\"position\" and \"target\"");
    fails("[{\"position\": [0, 0, 1], \"target\": [0, 0, 0], \"zoom\": 2}]",
          "unknown camera key \"zoom\"");
    fails("[[1, 2, ", "not valid JSON");
    fails("[]", "no camera");
}

}  // namespace
}  // namespace rtt

namespace rtt::test {
namespace {

TEST(Progress, LogsGetOneLinePerLongPhaseAndNothingForShortOnes) {
    // gtest's capture sends stderr to a file: the case of a log, not a terminal.
    testing::internal::CaptureStderr();
    { const render_detail::ProgressBar quick(0, true, "loading the scene"); }
    {
        const render_detail::ProgressBar slow(0, true, "building the kd-tree");
        std::this_thread::sleep_for(std::chrono::milliseconds(1050));
    }
    {
        const render_detail::ProgressBar quiet(0, false, "rendering");
        std::this_thread::sleep_for(std::chrono::milliseconds(1050));
    }
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(err.rfind("rtt: building the kd-tree took 1.", 0), 0u) << err;
    EXPECT_EQ(err.find("loading"), std::string::npos) << err;
    EXPECT_EQ(err.find("rendering"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

}  // namespace
}  // namespace rtt::test
