// Mesh import: triangle order and fan splitting per format (CONVENTIONS), exact coordinates,
// cameras, lights and materials from assimp, and an rtt::Error (never a crash) for bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <random>

#include "rtt/error.h"
#include "rtt/io.h"
#include "rtt/scene_io.h"
#include "scene/assimp_sandbox.h"
#include "scene/importers.h"

namespace rtt {
namespace {

const std::string data_dir = std::string(RTT_TEST_DATA_DIR) + "/scene_io/";

std::filesystem::path temp_dir() {
    return std::filesystem::temp_directory_path() / ("rtt_import_test_" + std::to_string(getpid()));
}

// Removes this process's temporary files when the test program exits.
const struct RemoveTempDir {
    ~RemoveTempDir() {
        std::error_code ec;
        std::filesystem::remove_all(temp_dir(), ec);
    }
} remove_temp_dir;

/// A fresh file under the test's own temporary folder.
std::string temp_file(const std::string& name, const std::string& bytes) {
    std::filesystem::create_directories(temp_dir());
    const std::string path = (temp_dir() / name).string();
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return path;
}

using Corners = std::array<Vec3f, 3>;

Corners corners(const Scene& s, size_t i) {
    return {s.vertices[s.triangles[i][0]], s.vertices[s.triangles[i][1]],
            s.vertices[s.triangles[i][2]]};
}

/// Triangles whose corner positions differ (bit for bit) from `expected`, in order.
int count_mismatches(const Scene& s, const std::vector<Corners>& expected) {
    EXPECT_EQ(s.triangle_count(), expected.size());
    int bad = 0;
    for (size_t i = 0; i < std::min(s.triangle_count(), expected.size()); ++i)
        if (corners(s, i) != expected[i]) {
            ++bad;
            ADD_FAILURE() << "triangle " << i << " differs";
        }
    return bad;
}

/// The 0-based polygons of polygons_ascii.ply / polygons.off, fan-split by hand.
std::vector<Corners> polygon_fixture_triangles() {
    const Vec3f v[7] = {{0, 0, 0}, {1, 0, 0},    {1, 1, 0}, {0, 1, 0},
                        {2, 0, 0}, {3, 0.5f, 0}, {2, 1, 0}};
    // quad 0 1 2 3, triangle 1 4 6, pentagon 4 5 6 2 1
    return {{v[0], v[1], v[2]}, {v[0], v[2], v[3]}, {v[1], v[4], v[6]},
            {v[4], v[5], v[6]}, {v[4], v[6], v[2]}, {v[4], v[2], v[1]}};
}

/// Runs `load` and checks it throws a one-line rtt::Error that starts with `path` and
/// contains `needle`.
void expect_error(const std::function<void()>& load, const std::string& path,
                  const std::string& needle) {
    try {
        load();
        ADD_FAILURE() << path << ": no error (expected \"" << needle << "\")";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(path, 0), 0u) << what;
        EXPECT_NE(what.find(needle), std::string::npos) << what << "\n  expected: " << needle;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

void expect_mesh_error(const std::string& path, const std::string& needle) {
    expect_error([&] { load_mesh_file(path); }, path, needle);
}

/// A file whose every triangle lies on a NaN or infinite vertex loads as an empty scene (every
/// ray misses), with one warning that says so (the reading policy, docs/robustness.md).
void expect_nothing_left(const std::string& path) {
    const Scene s = load_mesh_file(path);
    EXPECT_EQ(s.triangle_count(), 0u) << path;
    ASSERT_EQ(s.warnings.size(), 1u) << path;
    EXPECT_NE(s.warnings[0].find("the 1 triangles on them dropped: nothing is left to render"),
              std::string::npos)
        << s.warnings[0];
}

bool is_default_material(const Material& m) {
    const Material d;
    return m.diffuse == d.diffuse && m.specular == d.specular && m.shininess == d.shininess &&
           m.mirror == d.mirror;
}

TEST(Import, ObjKeepsFileOrderAndFanSplitsPolygons) {
    const Scene s = load_mesh_file(data_dir + "mixed_polygons.obj");
    const Vec3f v[10] = {
        {},        {0, 0, 0},    {1, 0, 0}, {1, 1, 0},        {0, 1, 0}, {2, 0, 0},
        {2, 1, 0}, {3, 0.5f, 0}, {0, 0, 1}, {0.25f, 0.75f, 2}};  // 1-based as in the file
    const std::vector<Corners> expected = {
        {v[1], v[2], v[3]},                                          // f 1 2 3
        {v[1], v[2], v[3]}, {v[1], v[3], v[4]},                      // f 1 2 3 4
        {v[2], v[5], v[6]}, {v[2], v[6], v[3]},                      // f 2 5 6 3 (after "l")
        {v[5], v[7], v[6]}, {v[5], v[6], v[3]}, {v[5], v[3], v[2]},  // f 5 7 6 3 2 (after "p")
        {v[8], v[1], v[2]},                                          // f 8 1 2
        {v[9], v[8], v[7]},                                          // f -1 -2 -3
    };
    EXPECT_EQ(count_mismatches(s, expected), 0);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_TRUE(is_default_material(s.materials[0]));
    EXPECT_TRUE(s.normals.empty());
    EXPECT_FALSE(s.camera.has_value());
}

// A float printed with 9 significant digits must read back bit for bit (assimp 5.2's parser
// gets about 5% of these wrong by one ulp; rtt reads OBJ itself for that reason).
TEST(Import, ObjCoordinatesAreCorrectlyRounded) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1000.f, 1000.f);
    std::string obj;
    std::vector<Vec3f> written;
    char buf[128];
    const char* formats[] = {"v %.9g %.9g %.9g\n", "v %.6f %.6f %.6f\n", "v %.3e %.3e %.3e\n"};
    for (int i = 0; i < 6000; ++i) {
        std::snprintf(buf, sizeof buf, formats[i % 3], u(rng), u(rng), u(rng));
        obj += buf;
        float x, y, z;
        ASSERT_EQ(std::sscanf(buf, "v %g %g %g", &x, &y, &z), 3);  // strtof: correctly rounded
        written.push_back({x, y, z});
    }
    for (int i = 0; i < 2000; ++i)
        obj += "f " + std::to_string(3 * i + 1) + " " + std::to_string(3 * i + 2) + " " +
               std::to_string(3 * i + 3) + "\n";
    const Scene s = load_mesh_file(temp_file("rounding.obj", obj));
    ASSERT_EQ(s.vertices.size(), written.size());
    int mismatches = 0;
    for (size_t i = 0; i < written.size(); ++i) mismatches += s.vertices[i] == written[i] ? 0 : 1;
    EXPECT_EQ(mismatches, 0);
}

TEST(Import, ObjMaterialsNormalsAndContinuationLines) {
    const Scene s = load_mesh_file(data_dir + "materials.obj");
    const Vec3f v[5] = {{}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    EXPECT_EQ(count_mismatches(s, {{v[1], v[2], v[3]},
                                   {v[1], v[3], v[4]},
                                   {v[1], v[2], v[4]},
                                   {v[2], v[3], v[4]},
                                   {v[4], v[3], v[1]}}),
              0);
    ASSERT_EQ(s.triangle_material.size(), 5u);
    const auto mat = [&](size_t t) { return s.materials[s.triangle_material[t]]; };
    EXPECT_TRUE(is_default_material(mat(0)));  // before any usemtl
    EXPECT_EQ(mat(1).name, "red");
    EXPECT_EQ(mat(1).diffuse, Vec3f(0.75f, 0.125f, 0.125f));
    EXPECT_EQ(mat(1).specular, Vec3f(0.5f));
    EXPECT_EQ(mat(1).shininess, 40.f);
    EXPECT_EQ(mat(2).name, "matte");
    EXPECT_EQ(mat(2).diffuse, Vec3f(0.25f, 0.5f, 0.25f));
    EXPECT_EQ(mat(2).specular, Vec3f(0.f));    // illum 1: no highlights despite Ks
    EXPECT_TRUE(is_default_material(mat(3)));  // usemtl of an unknown name
    EXPECT_EQ(s.triangle_material[4], s.triangle_material[1]);
    // Per-vertex normals: triangle 2 uses normal 2, triangle 3 none (zero = geometric).
    ASSERT_EQ(s.normals.size(), s.vertices.size());
    EXPECT_EQ(s.normals[s.triangles[0][0]], Vec3f(0, 0, 1));
    EXPECT_EQ(s.normals[s.triangles[2][0]], Vec3f(0, 0, -1));
    EXPECT_EQ(s.normals[s.triangles[3][0]], Vec3f(0.f));
}

TEST(Import, ObjWithByteOrderMarkAndCrLf) {
    const Scene s = load_mesh_file(temp_file(
        "windows.obj",
        "\xEF\xBB\xBFv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 1 1 0\r\nf 1 2 3 \r\nf 2 4 3\r\n"));
    EXPECT_EQ(count_mismatches(s, {{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}},
                                   {Vec3f{1, 0, 0}, Vec3f{1, 1, 0}, Vec3f{0, 1, 0}}}),
              0);
}

TEST(Import, PlyAsciiKeepsFaceOrderAndFans) {
    const Scene s = load_mesh_file(data_dir + "polygons_ascii.ply");
    EXPECT_EQ(count_mismatches(s, polygon_fixture_triangles()), 0);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_TRUE(is_default_material(s.materials[0]));  // assimp's invented white is not used
}

std::string binary_ply(const std::vector<Vec3f>& verts,
                       const std::vector<std::vector<int32_t>>& faces) {
    std::string out =
        "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(verts.size()) +
        "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
        std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3f& v : verts) out.append(reinterpret_cast<const char*>(&v), 12);
    for (const auto& f : faces) {
        out.push_back(char(f.size()));
        out.append(reinterpret_cast<const char*>(f.data()), 4 * f.size());
    }
    return out;
}

const std::vector<Vec3f> fixture_vertices = {{0, 0, 0}, {1, 0, 0},    {1, 1, 0}, {0, 1, 0},
                                             {2, 0, 0}, {3, 0.5f, 0}, {2, 1, 0}};
const std::vector<std::vector<int32_t>> fixture_faces = {{0, 1, 2, 3}, {1, 4, 6}, {4, 5, 6, 2, 1}};

TEST(Import, PlyBinaryKeepsFaceOrderAndFans) {
    const Scene s = load_mesh_file(
        temp_file("polygons_binary.ply", binary_ply(fixture_vertices, fixture_faces)));
    EXPECT_EQ(count_mismatches(s, polygon_fixture_triangles()), 0);
}

/// An ASCII PLY of three float vertices and one face list of uchar counts, with this body.
std::string ascii_triangle(const std::string& body) {
    return "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
           "y\nproperty float z\nelement face 1\nproperty list uchar int "
           "vertex_indices\nend_header\n" +
           body;
}

/// A binary PLY of the given header lines (after "format"), each vertex record and each face
/// record written by the callbacks in the file's byte order.
class PlyWriter {
public:
    explicit PlyWriter(bool big_endian) : big_(big_endian) {
        text_ = std::string("ply\nformat binary_") + (big_ ? "big" : "little") + "_endian 1.0\n";
    }
    PlyWriter& line(const std::string& l) {
        text_ += l + "\n";
        return *this;
    }
    template <typename T>
    PlyWriter& put(T v) {
        char b[sizeof v];
        std::memcpy(b, &v, sizeof v);
        if (big_) std::reverse(b, b + sizeof v);
        text_.append(b, sizeof v);
        return *this;
    }
    std::string bytes() const { return text_; }

private:
    bool big_;
    std::string text_;
};

/// Every field of the two scenes, floats bit for bit (NaN-free inputs).
void expect_same_scene(const Scene& a, const Scene& b) {
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.triangle_material, b.triangle_material);
    EXPECT_EQ(a.normals, b.normals);
    ASSERT_EQ(a.materials.size(), b.materials.size());
    for (size_t i = 0; i < a.materials.size(); ++i) {
        EXPECT_EQ(a.materials[i].name, b.materials[i].name);
        EXPECT_EQ(a.materials[i].diffuse, b.materials[i].diffuse);
        EXPECT_EQ(a.materials[i].specular, b.materials[i].specular);
    }
    EXPECT_EQ(a.warnings, b.warnings);
    EXPECT_EQ(a.lights.size(), b.lights.size());
    EXPECT_EQ(a.camera.has_value(), b.camera.has_value());
}

TEST(Import, PlyReadsAsAssimpDoes) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-100.0, 100.0);
    for (const bool big : {false, true}) {
        // Doubles rounded to float, normals among other properties (one not finite), 16-bit
        // counts, unsigned indices, polygons of 3 to 6 corners, an unreferenced vertex.
        PlyWriter w(big);
        const int nv = 40, nf = 30;
        w.line("comment made by a test").line("element vertex " + std::to_string(nv));
        w.line("property double x").line("property float confidence").line("property double y");
        w.line("property double z").line("property float nx").line("property float ny");
        w.line("property float nz").line("property uchar intensity");
        w.line("element face " + std::to_string(nf)).line("property list ushort uint vertex_index");
        w.line("end_header");
        for (int v = 0; v < nv; ++v) {
            w.put(coord(rng)).put(0.5f).put(coord(rng)).put(coord(rng));
            w.put(v == 3 ? std::numeric_limits<float>::quiet_NaN() : float(coord(rng)));
            w.put(float(coord(rng))).put(float(coord(rng))).put(uint8_t(v));
        }
        for (int f = 0; f < nf; ++f) {
            const uint16_t n = uint16_t(3 + f % 4);
            w.put(n);
            for (uint16_t k = 0; k < n; ++k) w.put(uint32_t((f * 7 + k * 3) % (nv - 1)));
        }
        const std::string path = temp_file(big ? "native_be.ply" : "native_le.ply", w.bytes());
        const std::optional<Scene> native = detail::import_ply_native(path);
        ASSERT_TRUE(native.has_value());
        expect_same_scene(*native, detail::import_assimp_isolated(path));
        EXPECT_EQ(native->triangle_count(), size_t(nf / 4 * (1 + 2 + 3 + 4) + 1 + 2));
    }
    // The test fixture as exporters write it: float coordinates, uchar counts, int indices.
    const std::string plain =
        temp_file("native_plain.ply", binary_ply(fixture_vertices, fixture_faces));
    const std::optional<Scene> native = detail::import_ply_native(plain);
    ASSERT_TRUE(native.has_value());
    expect_same_scene(*native, detail::import_assimp_isolated(plain));
    // ASCII, as the Stanford scans: values assimp's fast_atof also reads exactly (eighths),
    // integer and double coordinates, normals, CRLF line ends, blank-padded records.
    std::string ascii =
        "ply\r\nformat ascii 1.0\r\ncomment zipper output\r\nelement vertex 30\r\nproperty "
        "float x\r\nproperty double y\r\nproperty int z\r\nproperty float "
        "confidence\r\nproperty float nx\r\nproperty float ny\r\nproperty float nz\r\nelement "
        "face 20\r\nproperty list uchar int vertex_indices\r\nend_header\r\n";
    std::uniform_int_distribution<int> eighths(-800, 800);
    for (int v = 0; v < 30; ++v)
        ascii += std::to_string(eighths(rng) / 8.0) + " " + std::to_string(eighths(rng) / 8.0) +
                 " " + std::to_string(eighths(rng)) + " 0.5 " + std::to_string(eighths(rng) / 8.0) +
                 " 0.25 -1\r\n";
    for (int f = 0; f < 20; ++f) {
        const int n = 3 + f % 3;
        ascii += std::to_string(n);
        for (int k = 0; k < n; ++k) ascii.append(" ").append(std::to_string((f * 5 + k * 7) % 30));
        ascii += "  \r\n";
    }
    const std::string text = temp_file("native_ascii.ply", ascii);
    const std::optional<Scene> from_text = detail::import_ply_native(text);
    ASSERT_TRUE(from_text.has_value());
    expect_same_scene(*from_text, detail::import_assimp_isolated(text));
    // Where assimp's fast_atof is one ulp off, ours rounds correctly: "%.9g" reads back exactly.
    const float exact = 0.1f + 0x1p-27f;
    char written[32];
    std::snprintf(written, sizeof written, "%.9g", double(exact));
    const std::optional<Scene> round_trip = detail::import_ply_native(temp_file(
        "round_trip.ply", ascii_triangle(std::string(written) + " 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")));
    ASSERT_TRUE(round_trip.has_value());
    EXPECT_EQ(round_trip->vertices[0].x, exact);
}

TEST(Import, PlyLeavesOtherFilesToAssimp) {
    const std::string plain = binary_ply(fixture_vertices, fixture_faces);
    const size_t body = plain.find("end_header\n") + 11;
    const auto with_header = [&](const std::string& from, const std::string& to) {
        std::string s = plain;
        s.replace(s.find(from), from.size(), to);
        return s;
    };
    const std::vector<std::pair<std::string, std::string>> others = {
        {"ascii_two_per_line", ascii_triangle("0 0 0\n1 0 0 0 1 0\n3 0 1 2\n")},
        {"ascii_cut", ascii_triangle("0 0 0\n1 0 0\n0 1 0\n3 0 1\n")},
        {"ascii_word", ascii_triangle("0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n")},
        {"ascii_longer", ascii_triangle("0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n")},
        {"ascii_range", ascii_triangle("0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n")},
        {"colour", with_header("property float z\n", "property float z\nproperty uchar red\n")},
        {"cut", plain.substr(0, plain.size() - 1)},
        {"longer", plain + "x"},
        {"cut_header", plain.substr(0, body - 3)},
        {"edge", with_header("end_header", "element edge 0\nproperty int vertex1\nend_header")},
        {"face_flags", with_header("vertex_indices\n", "vertex_indices\nproperty uchar flags\n")},
        {"out_of_range", binary_ply(fixture_vertices, {{0, 1, 7}})},
        {"negative", binary_ply(fixture_vertices, {{0, 1, -5}})},
        {"line", binary_ply(fixture_vertices, {{0, 1}})},
        {"huge_count", with_header("element face 3", "element face 3000000000")},
        {"unknown_line", with_header("element vertex", "Created by a tool\nelement vertex")},
    };
    for (const auto& [name, bytes] : others)
        EXPECT_FALSE(detail::import_ply_native(temp_file(name + ".ply", bytes)).has_value())
            << name;
}

TEST(Import, OffKeepsFaceOrderAndFans) {
    const Scene s = load_mesh_file(data_dir + "polygons.off");
    EXPECT_EQ(count_mismatches(s, polygon_fixture_triangles()), 0);
    // Comments and blank lines between the sections (assimp 5.2 drops every face here).
    const Scene c = load_mesh_file(temp_file(
        "comments.off", "OFF\n# c\n3 1 0\n\n0 0 0\n1 0 0 # x\n0 1 0\n\n# faces\n3 0 1 2\n"));
    EXPECT_EQ(c.triangle_count(), 1u);
    // Variants with normals or colours after the coordinates, counts on the header line.
    const Scene n = load_mesh_file(temp_file(
        "variant.off", "NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2 255 0 0\n"));
    EXPECT_EQ(corners(n, 0), (Corners{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}));
}

TEST(Import, StlAsciiAndBinary) {
    const Vec3f a{0, 0, 0}, b{1, 0, 0}, c{1, 1, 0}, d{0, 1, 0};
    const Scene s = load_mesh_file(data_dir + "two_triangles.stl");
    EXPECT_EQ(count_mismatches(s, {{a, b, c}, {a, c, d}}), 0);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_TRUE(is_default_material(s.materials[0]));
    std::string bin(80, '\0');
    const uint32_t n = 2;
    bin.append(reinterpret_cast<const char*>(&n), 4);
    for (const Corners& t : {Corners{a, b, c}, Corners{a, c, d}}) {
        const float normal[3] = {0, 0, 1};
        bin.append(reinterpret_cast<const char*>(normal), 12);
        for (const Vec3f& v : t) bin.append(reinterpret_cast<const char*>(&v), 12);
        bin.append(2, '\0');
    }
    EXPECT_EQ(
        count_mismatches(load_mesh_file(temp_file("binary.stl", bin)), {{a, b, c}, {a, c, d}}), 0);
}

// camera_light.glb is the same scene packed as binary glTF.
TEST(Import, GltfNodesInstancesCameraAndLights) {
    for (const char* file : {"camera_light.gltf", "camera_light.glb"}) {
        SCOPED_TRACE(file);
        const Scene s = load_mesh_file(data_dir + file);
        // Node "quad" (identity), then node "quad2" under a parent scaled by 2:
        // p' = 2 (p + (0,0,-2)).
        const Vec3f q[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
        const auto placed = [&](int i) { return q[i] * 2.f + Vec3f{0, 0, -4}; };
        EXPECT_EQ(count_mismatches(s, {{q[0], q[1], q[2]},
                                       {q[0], q[2], q[3]},
                                       {placed(0), placed(1), placed(2)},
                                       {placed(0), placed(2), placed(3)}}),
                  0);
        ASSERT_EQ(s.materials.size(), 1u);
        EXPECT_EQ(s.materials[0].name, "red");
        EXPECT_EQ(s.materials[0].diffuse, Vec3f(1, 0, 0));

        ASSERT_TRUE(s.camera.has_value());
        EXPECT_EQ(s.camera->position, Vec3f(0.5f, 0.5f, 5));  // not doubled (assimp issue #5054)
        const Vec3f dir = normalize(s.camera->target - s.camera->position);
        EXPECT_NEAR(dir.z, -1.f, 1e-6f);
        EXPECT_NEAR(s.camera->up.y, 1.f, 1e-6f);
        EXPECT_NEAR(s.camera->fovy_deg, 0.7 * 180 / M_PI, 1e-4);  // the file's yfov

        ASSERT_EQ(s.lights.size(), 2u);
        const Light& lamp = s.lights[0];
        EXPECT_EQ(lamp.kind, LightKind::omni);
        EXPECT_EQ(lamp.position, Vec3f(1, 2, 3));
        EXPECT_EQ(lamp.intensity, 4.f);
        EXPECT_EQ(lamp.color, Vec3f(1, 0.5f, 0.25f));
        const Light& spot = s.lights[1];
        EXPECT_EQ(spot.kind, LightKind::spot);
        EXPECT_NEAR(length(spot.position - Vec3f(0, 5, 0)), 0.f, 1e-6f);
        EXPECT_NEAR(length(normalize(spot.direction) - Vec3f(0, -1, 0)), 0.f,
                    1e-6f);                                         // -z turned down
        EXPECT_NEAR(spot.inner_angle_deg, 0.2 * 180 / M_PI, 1e-4);  // glTF angles are half angles
        EXPECT_NEAR(spot.outer_angle_deg, 0.6 * 180 / M_PI, 1e-4);
        EXPECT_EQ(spot.intensity, 2.f);
        EXPECT_EQ(spot.color, Vec3f(1.f));
    }
}

TEST(Import, ColladaCameraLightsAndMaterials) {
    const Scene s = load_mesh_file(data_dir + "camera_light.dae");
    // polylist "4 3": quad 0 1 2 3 then triangle 3 2 4; node "quad" then node "quad2" (z - 3).
    const Vec3f v[5] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 2, 0}};
    const auto w = [&](int i) { return v[i] + Vec3f{0, 0, -3}; };
    EXPECT_EQ(count_mismatches(s, {{v[0], v[1], v[2]},
                                   {v[0], v[2], v[3]},
                                   {v[3], v[2], v[4]},
                                   {w(0), w(1), w(2)},
                                   {w(0), w(2), w(3)},
                                   {w(3), w(2), w(4)}}),
              0);
    const Material& red = s.materials[s.triangle_material[0]];
    EXPECT_EQ(red.name, "red");
    EXPECT_EQ(red.diffuse, Vec3f(0.8f, 0.1f, 0.1f));
    EXPECT_EQ(red.specular, Vec3f(0.5f));
    EXPECT_EQ(red.shininess, 50.f);
    EXPECT_EQ(red.mirror, 0.25f);  // <reflectivity>
    const Material& plain = s.materials[s.triangle_material[3]];
    EXPECT_EQ(plain.name, "plain");
    EXPECT_EQ(plain.diffuse, Vec3f(0.2f, 0.6f, 0.2f));
    EXPECT_EQ(plain.specular, Vec3f(0.f));  // <lambert> has no highlights

    ASSERT_TRUE(s.camera.has_value());
    EXPECT_EQ(s.camera->position, Vec3f(0.5f, 0.5f, 6));
    EXPECT_NEAR(s.camera->fovy_deg, 40.0, 1e-3);  // yfov 40 with aspect 1.5, via assimp's xfov
    ASSERT_EQ(s.lights.size(), 2u);
    EXPECT_EQ(s.lights[0].kind, LightKind::omni);
    EXPECT_EQ(s.lights[0].position, Vec3f(1, 2, 3));
    EXPECT_EQ(s.lights[0].intensity, 2.f);
    EXPECT_EQ(s.lights[0].color, Vec3f(1, 0.5f, 0.25f));
    EXPECT_EQ(s.lights[1].kind, LightKind::spot);
    EXPECT_NEAR(length(normalize(s.lights[1].direction) - Vec3f(0, -1, 0)), 0.f, 1e-6f);
    EXPECT_NEAR(s.lights[1].inner_angle_deg, 30.f, 1e-4);  // falloff_angle 60 is a full angle
    // assimp derives the outer cone from falloff_exponent: here 60 + acos(0.1) degrees, full.
    EXPECT_NEAR(s.lights[1].outer_angle_deg, (60.0 + std::acos(0.1) * 180 / M_PI) / 2, 1e-3);
}

TEST(Import, MissingUnreadableAndEmptyFiles) {
    expect_mesh_error(data_dir + "does_not_exist.obj", "no such file");
    expect_mesh_error(data_dir, "is a directory");
    expect_mesh_error("/dev/zero", "not a regular file");
    for (const char* name : {"empty.obj", "empty.ply", "empty.stl", "empty.gltf", "empty.off"})
        expect_mesh_error(temp_file(name, ""), "empty file");
    const std::string locked = temp_file("locked.obj", "v 0 0 0\n");
    std::filesystem::permissions(locked, std::filesystem::perms::none);
    if (geteuid() != 0) expect_mesh_error(locked, "cannot open");  // root reads anything
}

TEST(Import, GarbageBytesGiveErrors) {
    std::mt19937 rng(3);
    for (const char* ext : {"obj", "ply", "stl", "off", "gltf", "glb", "dae", "3ds", "fbx", "xyz"})
        for (int size : {1, 7, 300, 5000}) {
            std::string bytes(size_t(size), '\0');
            for (char& c : bytes) c = char(rng());
            const std::string path =
                temp_file(std::string("garbage_") + std::to_string(size) + "." + ext, bytes);
            EXPECT_THROW(load_mesh_file(path), Error) << path;
        }
    // Plausible starts followed by garbage.
    for (const std::string& start :
         {std::string("ply\nformat ascii 1.0\n"), std::string("solid x\n"),
          std::string("OFF\n3 1 0\n"), std::string("{\"asset\":{\"version\":\"2.0\"}")})
        EXPECT_THROW(load_mesh_file(temp_file("start.ply", start + "\x01\xff garbage")), Error);
}

TEST(Import, ObjErrorsCarryLineNumbers) {
    expect_mesh_error(temp_file("oob.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
                      "oob.obj:4: face uses vertex 9 but the file has 3");
    expect_mesh_error(temp_file("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
                      "zero.obj:4: vertex index 0");
    expect_mesh_error(temp_file("rel.obj", "v 0 0 0\nf -1 -2 -3\n"),
                      "rel.obj:2: relative index -2");
    expect_nothing_left(temp_file("nan.obj", "v 1 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"));
    expect_nothing_left(temp_file("inf.obj", "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    expect_mesh_error(temp_file("big.obj", "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
                      "big.obj:1: number out of float range");
    expect_mesh_error(temp_file("text.obj", "v 1 zero 0\n"),
                      "text.obj:1: expected a number, got 'zero'");
    expect_mesh_error(temp_file("short.obj", "v 1 2\n"), "short.obj:1: expected 3 coordinates");
    expect_mesh_error(temp_file("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\np 1\nf 1 2\n"),
                      "no triangles (skipped 1 points and 2 lines)");
    expect_mesh_error(temp_file("points.obj", "v 0 0 0\n"), "no triangles");
    expect_mesh_error(
        temp_file("badnormal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n"),
        "badnormal.obj:5: face uses normal 2");
    // An mtllib after the faces that use it still applies (as in assimp).
    temp_file("late.mtl", "newmtl m\nKd 0.5 0.25 1\n");
    const Scene late = load_mesh_file(
        temp_file("late.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\nmtllib late.mtl\n"));
    EXPECT_EQ(late.materials.at(late.triangle_material.at(0)).diffuse, Vec3f(0.5f, 0.25f, 1));
    // A missing MTL file is tolerated (default material); a malformed one is an error.
    const Scene no_mtl = load_mesh_file(temp_file(
        "nomtl.obj", "mtllib absent.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n"));
    EXPECT_TRUE(is_default_material(no_mtl.materials.at(0)));
    const std::string mtl = temp_file("bad.mtl", "newmtl a\nKd 1 x 0\n");
    const std::string obj =
        temp_file("badmtl.obj", "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_error([&] { load_mesh_file(obj); }, mtl, "bad.mtl:2: expected a number, got 'x'");
}

// Textures count as their mean colour (times the material's own colour when the file gives
// one), vertex colours as each triangle's mean; both in the OBJ reader and the assimp path.
TEST(Import, TexturesAndVertexColoursBecomeColours) {
    // Two texels, sRGB red and blue: mean linear colour (0.5, 0, 0.5).
    const std::vector<uint8_t> texels = {255, 0, 0, 0, 0, 255};
    std::filesystem::create_directories(temp_dir());
    write_png((temp_dir() / "tex.png").string(), 2, 1, 3, texels);
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    temp_file("tex.mtl",
              "newmtl plain\nmap_Kd tex.png\nnewmtl tinted\nKd 0.5 1 1\nmap_Kd -s 1 1 1 "
              "tex.png\nnewmtl lost\nmap_Kd absent.png\nKd 0.2 0.3 0.4\n");
    const Scene o = load_mesh_file(temp_file(
        "tex.obj", "mtllib tex.mtl\n" + tri +
                       "usemtl plain\nf 1 2 3\nusemtl tinted\nf 1 2 3\nusemtl lost\nf 1 2 3\n"));
    const auto diffuse = [](const Scene& s, size_t t) {
        return s.materials.at(s.triangle_material.at(t)).diffuse;
    };
    EXPECT_EQ(diffuse(o, 0), Vec3f(0.5f, 0.f, 0.5f));
    EXPECT_EQ(diffuse(o, 1), Vec3f(0.25f, 0.f, 0.5f));
    EXPECT_EQ(diffuse(o, 2), Vec3f(0.2f, 0.3f, 0.4f));
    ASSERT_EQ(o.warning_count, 1u);
    EXPECT_NE(o.warnings[0].find("absent.png cannot be read"), std::string::npos) << o.warnings[0];

    // glTF through assimp: the base colour texture (an external file) times baseColorFactor.
    const std::string gltf =
        temp_file("tex.gltf",
                  R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 1, 1],
                                                    "baseColorTexture": {"index": 0}}}],
            "textures": [{"source": 0}], "images": [{"uri": "tex.png"}],
            "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/"}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]}]})");
    const Scene g = load_mesh_file(gltf);
    ASSERT_EQ(g.triangle_count(), 1u);
    EXPECT_EQ(diffuse(g, 0), Vec3f(0.5f, 0.f, 0.5f));

    // PLY vertex colours: each triangle its vertices' mean, times the default grey.
    const Scene p = load_mesh_file(temp_file(
        "colours.ply",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 255 0 0\n1 0 0 255 0 0\n0 1 0 255 0 0\n1 1 0 0 0 0\n3 0 1 2\n3 1 3 2\n"));
    ASSERT_EQ(p.triangle_count(), 2u);
    const float grey = Material{}.diffuse.x;
    EXPECT_EQ(diffuse(p, 0), Vec3f(grey, 0.f, 0.f));
    EXPECT_NEAR(diffuse(p, 1).x, grey * 2.f / 3.f, 1e-6f);
    EXPECT_EQ(diffuse(p, 1).y, 0.f);
}

TEST(Import, EveryCameraOfAFileInOrder) {
    // One triangle seen by two named perspective cameras, on the +z and +x axes.
    const Scene s = load_mesh_file(data_dir + "two_cameras.gltf");
    ASSERT_EQ(s.file_cameras.size(), 2u);
    EXPECT_EQ(s.file_cameras[0].name, "front");
    EXPECT_EQ(s.file_cameras[1].name, "side");
    ASSERT_TRUE(s.camera);
    EXPECT_EQ(s.camera->position, s.file_cameras[0].camera.position);
    EXPECT_NEAR(s.file_cameras[0].camera.position.z, 3.f, 1e-6f);
    EXPECT_NEAR(s.file_cameras[1].camera.position.x, 3.f, 1e-6f);
    // The side camera looks down -x (its node turns -z into -x).
    const Camera& side = s.file_cameras[1].camera;
    EXPECT_LT(side.target.x - side.position.x, 0.f);
    EXPECT_GT(s.file_cameras[0].camera.fovy_deg, s.file_cameras[1].camera.fovy_deg);
}

// The reading policy (docs/robustness.md): what other viewers open is repaired with a
// warning, and the rest of the file read as it is.
TEST(Import, RepairsWarnAndKeepTheRest) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    // A PLY header line that is no keyword (exporters write "Created by ...").
    std::string ply = binary_ply(fixture_vertices, fixture_faces);
    ply.insert(ply.find("element"), "Created by a tool\n");
    const Scene p = load_mesh_file(temp_file("created.ply", ply));
    EXPECT_EQ(count_mismatches(p, polygon_fixture_triangles()), 0);
    ASSERT_EQ(p.warning_count, 1u);
    EXPECT_NE(p.warnings[0].find("created.ply:3: unknown PLY header line 'Created'"),
              std::string::npos);
    // An unnamed material, picked by an unnamed usemtl.
    temp_file("unnamed.mtl", "newmtl\nKd 1 0 0\n");
    const Scene o = load_mesh_file(
        temp_file("unnamed.obj", "mtllib unnamed.mtl\n" + tri + "usemtl\nf 1 2 3\n"));
    ASSERT_EQ(o.warning_count, 1u);
    EXPECT_NE(o.warnings[0].find("unnamed.mtl:1: newmtl without a name"), std::string::npos);
    EXPECT_EQ(o.materials[o.triangle_material[0]].diffuse, Vec3f(1, 0, 0));
    // An empty STL solid beside a full one.
    const Scene e = load_mesh_file(
        temp_file("empty_solid.stl",
                  "solid full\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 "
                  "0\nvertex 0 1 0\nendloop\nendfacet\nendsolid full\nsolid empty\n"
                  "endsolid empty\n"));
    EXPECT_EQ(e.triangles.size(), 1u);
    ASSERT_EQ(e.warning_count, 1u);
    EXPECT_NE(e.warnings[0].find("no vertices, skipped"), std::string::npos) << e.warnings[0];
    // A NaN vertex: the triangles on it go, the others keep their order.
    const Scene n =
        load_mesh_file(temp_file("nan_one.obj", tri + "v nan 0 0\nf 1 2 3\nf 1 2 4\nf 3 2 1\n"));
    ASSERT_EQ(n.triangles.size(), 2u);
    EXPECT_EQ(n.triangles[1], (TriangleIndices{2, 1, 0}));
    EXPECT_EQ(n.bounds().hi, Vec3f(1, 1, 0));  // the NaN vertex is no longer anywhere
    ASSERT_EQ(n.warning_count, 1u);
}

TEST(Import, MalformedPlyOffStlGiveErrors) {
    const std::string ply = binary_ply(fixture_vertices, fixture_faces);
    // Binary PLY cut at every length inside the body: always an error, never a crash.
    const size_t body = ply.find("end_header\n") + 11;
    int accepted = 0;
    for (size_t len = body; len < ply.size(); ++len) {
        try {
            load_mesh_file(temp_file("cut.ply", ply.substr(0, len)));
            ++accepted;
        } catch (const Error&) {
        }
    }
    EXPECT_EQ(accepted, 0);
    const std::string ascii = [] {
        std::ifstream in(data_dir + "polygons_ascii.ply");
        return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    // Cut inside the vertex list and inside the face list (assimp alone repeats the last face).
    expect_mesh_error(temp_file("cut_vertices.ply", ascii.substr(0, ascii.find("2 0 0"))),
                      "truncated PLY: the file ends in vertex 4 of 7");
    expect_mesh_error(temp_file("cut_faces.ply", ascii.substr(0, ascii.find("3 1 4 6"))),
                      "truncated PLY: the file ends in face 1 of 3");
    // Headers assimp 5.2 would loop on forever (found by mutating the fixtures).
    expect_mesh_error(temp_file("hang.ply",
                                "ply}\nformat binary_little_endian 1.0\nelement verr"
                                "operty float x\nproperty f"),
                      "hang.ply:1: a PLY file starts with a line \"ply\"");
    expect_mesh_error(
        temp_file("keyword.ply", "ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n"),
        "keyword.ply:3: unknown PLY header line 'elemnt'");
    expect_mesh_error(temp_file("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"),
                      "PLY header without end_header");
    std::string bad_index = ascii;
    bad_index.replace(bad_index.find("3 1 4 6"), 7, "3 1 4 60");
    expect_mesh_error(temp_file("bad_index.ply", bad_index),
                      "face 1 uses vertex 60 but the mesh has 7 vertices");
    std::string nan_vertex = ascii;
    nan_vertex.replace(nan_vertex.find("3 0.5 0"), 7, "nan 0.5 0");
    {
        // Repaired (docs/robustness.md, "Reading policy"): the one triangle on vertex 5 goes.
        const Scene s = load_mesh_file(temp_file("nan.ply", nan_vertex));
        EXPECT_EQ(s.triangles.size(), polygon_fixture_triangles().size() - 1);
        ASSERT_EQ(s.warning_count, 1u);
        EXPECT_NE(s.warnings[0].find("1 vertices with a NaN or infinite coordinate; the 1 "
                                     "triangles on them dropped"),
                  std::string::npos)
            << s.warnings[0];
    }
    expect_mesh_error(temp_file("negative.ply", binary_ply(fixture_vertices, {{0, 1, -5}})),
                      "uses vertex 4294967291");

    expect_mesh_error(temp_file("cut.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n"),
                      "truncated: 2 of 4 vertices");
    expect_mesh_error(temp_file("cut_faces.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                      "truncated: 1 of 2 faces");
    expect_mesh_error(temp_file("oob.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
                      "oob.off:6: face uses vertex 7 but the file has 3");
    expect_mesh_error(temp_file("short_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
                      "short_face.off:6: face has 2 values");
    expect_mesh_error(temp_file("huge.off", "OFF\n4000000000 1 0\n0 0 0\n"),
                      "truncated: 1 of 4000000000 vertices");
    expect_mesh_error(temp_file("huger.off", "OFF\n5000000000 1 0\n0 0 0\n"),
                      "huger.off:2: vertex or face count out of range");
    expect_nothing_left(temp_file("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"));
    expect_mesh_error(temp_file("binary.off", "OFF BINARY\n"), "");
    expect_mesh_error(temp_file("lines.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
                      "no triangles");

    expect_nothing_left(temp_file("nan.stl",
                                  "solid s\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex "
                                  "1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n"));
    std::string stl(80, '\0');
    const uint32_t many = 1000000;
    stl.append(reinterpret_cast<const char*>(&many), 4).append(50, '\0');
    EXPECT_THROW(load_mesh_file(temp_file("short.stl", stl)), Error);
}

TEST(Import, GltfWithBadIndicesOrNoTriangles) {
    std::ifstream in(data_dir + "camera_light.gltf");
    const std::string good(std::istreambuf_iterator<char>(in), {});
    // Points primitive: nothing triangular remains.
    std::string points = good;
    points.replace(points.find("\"indices\": 1,"), 13, "\"mode\": 0,");
    expect_mesh_error(temp_file("points.gltf", points),
                      "no triangles (skipped 4 points and 0 lines)");
    // An index accessor pointing at the vertex buffer: indices read from float bits are huge.
    std::string bad = good;
    bad.replace(bad.find("\"indices\": 1"), 12, "\"indices\": 0");
    EXPECT_THROW(load_mesh_file(temp_file("bad_indices.gltf", bad)), Error);
}

TEST(Import, AssimpWritesNothingToStdoutOrStderr) {
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    load_mesh_file(data_dir + "camera_light.dae");
    EXPECT_THROW(load_mesh_file(temp_file("broken.dae",
                                          "<?xml version=\"1.0\"?><COLLADA><library_geometries>")),
                 Error);
    const std::string out = testing::internal::GetCapturedStdout();
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(out, "");
    EXPECT_EQ(err, "");
}

TEST(Import, SceneFileDispatchesOnExtension) {
    const std::string json = temp_file(
        "tiny.JSON",
        R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]]}]})");
    EXPECT_EQ(load_scene_file(json).triangle_count(), 1u);
    EXPECT_EQ(load_scene_file(data_dir + "two_triangles.stl").triangle_count(), 2u);
    EXPECT_EQ(load_scene_file(data_dir + "mixed_polygons.obj").triangle_count(), 10u);
}

}  // namespace
}  // namespace rtt
