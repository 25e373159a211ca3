// JSON scene files: every field reaches the Scene, transforms compose as documented, and every
// kind of bad input is an rtt::Error naming the file and the line or JSON pointer.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "rtt/error.h"
#include "rtt/scene_io.h"

namespace rtt {
namespace {

const std::string data_dir = std::string(RTT_TEST_DATA_DIR) + "/scene_io/";
const std::string source_dir = std::string(RTT_TEST_DATA_DIR) + "/../../";

std::string temp_dir() {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("rtt_scene_json_test_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    return dir.string();
}

// Removes this process's temporary files when the test program exits.
const struct RemoveTempDir {
    ~RemoveTempDir() {
        std::error_code ec;
        std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                                        ("rtt_scene_json_test_" + std::to_string(getpid())),
                                    ec);
    }
} remove_temp_dir;

std::string write(const std::string& name, const std::string& text) {
    const std::string path = temp_dir() + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Loads `text` as a scene file and returns the error message ("" if it loaded).
std::string error_of(const std::string& text, const std::string& name = "bad.json") {
    try {
        load_scene_json(write(name, text));
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

constexpr const char* tri = R"({"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]]})";

std::string with_mesh(const std::string& rest) {
    return std::string(R"({"meshes": [)") + tri + "]" + rest + "}";
}

TEST(SceneJson, EveryFieldReachesTheScene) {
    std::filesystem::copy_file(data_dir + "two_triangles.stl", temp_dir() + "/square.stl",
                               std::filesystem::copy_options::overwrite_existing);
    const std::string path = write("full.json", R"({
  "background": [0.1, 0.2, 0.3],
  "camera": {"position": [1, 2, 3], "target": [0, 0.5, 0], "up": [0, 0, 1], "fovy": 35},
  "materials": [
    {"name": "gold", "diffuse": [0.9, 0.7, 0.2], "specular": [0.5, 0.4, 0.3], "shininess": 64, "mirror": 0.25},
    {"name": "plain"}
  ],
  "lights": [
    {"type": "omni", "position": [4, 5, 6], "color": [1, 0.5, 0.25], "intensity": 7},
    {"type": "spot", "position": [0, 9, 0], "direction": [0, -1, 0.5], "inner_angle": 15,
     "outer_angle": 25, "color": [0.5, 0.5, 1], "intensity": 2},
    {"position": [1, 1, 1]}
  ],
  "meshes": [
    {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "triangles": [[0, 1, 2]],
     "normals": [[0, 0, 1], [0, 0, 1], [0, 0, 1]], "material": "gold",
     "transform": {"translate": [1, 2, 3], "rotate": [90, 0, 0], "scale": 2}},
    {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "triangles": [[2, 1, 0]],
     "material": {"diffuse": [0, 1, 0], "mirror": 1},
     "transform": {"matrix": [0, -1, 0, 5,  1, 0, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1]}},
    {"path": "square.stl", "transform": {"scale": [1, 2, 3], "rotate": [0, 0, 90]}},
    {"path": ")" + data_dir + R"(materials.obj"}
  ]
})");
    const Scene s = load_scene_json(path);
    EXPECT_EQ(s.name, path);
    EXPECT_EQ(s.background, Vec3f(0.1f, 0.2f, 0.3f));
    ASSERT_TRUE(s.camera.has_value());
    EXPECT_EQ(s.camera->position, Vec3f(1, 2, 3));
    EXPECT_EQ(s.camera->target, Vec3f(0, 0.5f, 0));
    EXPECT_EQ(s.camera->up, Vec3f(0, 0, 1));
    EXPECT_EQ(s.camera->fovy_deg, 35.f);

    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[0].kind, LightKind::omni);
    EXPECT_EQ(s.lights[0].position, Vec3f(4, 5, 6));
    EXPECT_EQ(s.lights[0].color, Vec3f(1, 0.5f, 0.25f));
    EXPECT_EQ(s.lights[0].intensity, 7.f);
    EXPECT_EQ(s.lights[1].kind, LightKind::spot);
    EXPECT_EQ(s.lights[1].position, Vec3f(0, 9, 0));
    EXPECT_EQ(s.lights[1].direction, Vec3f(0, -1, 0.5f));
    EXPECT_EQ(s.lights[1].inner_angle_deg, 15.f);
    EXPECT_EQ(s.lights[1].outer_angle_deg, 25.f);
    EXPECT_EQ(s.lights[1].color, Vec3f(0.5f, 0.5f, 1));
    EXPECT_EQ(s.lights[1].intensity, 2.f);
    EXPECT_EQ(s.lights[2].kind, LightKind::omni);  // the default type
    EXPECT_EQ(s.lights[2].color, Vec3f(1.f));
    EXPECT_EQ(s.lights[2].intensity, 1.f);

    // Triangles in mesh order: 1 + 1 + 2 (STL) + 5 (OBJ).
    ASSERT_EQ(s.triangle_count(), 9u);
    const auto corner = [&](size_t t, int k) { return s.vertices[s.triangles[t][size_t(k)]]; };
    const Material& gold = s.materials[s.triangle_material[0]];
    EXPECT_EQ(gold.name, "gold");
    EXPECT_EQ(gold.diffuse, Vec3f(0.9f, 0.7f, 0.2f));
    EXPECT_EQ(gold.specular, Vec3f(0.5f, 0.4f, 0.3f));
    EXPECT_EQ(gold.shininess, 64.f);
    EXPECT_EQ(gold.mirror, 0.25f);
    // p' = T Rx(90) S p: (0,1,0) -> (0,2,0) -> (0,0,2) -> (1,2,5); normal +z -> -y.
    EXPECT_EQ(corner(0, 0), Vec3f(1, 2, 3));
    EXPECT_EQ(corner(0, 1), Vec3f(3, 2, 3));
    EXPECT_EQ(corner(0, 2), Vec3f(1, 2, 5));
    ASSERT_EQ(s.normals.size(), s.vertices.size());
    EXPECT_EQ(s.normals[s.triangles[0][0]], Vec3f(0, -1, 0));
    // Inline material and a row-major matrix (x -> y, y -> -x, then +5 in x).
    const Material& inline_mat = s.materials[s.triangle_material[1]];
    EXPECT_EQ(inline_mat.diffuse, Vec3f(0, 1, 0));
    EXPECT_EQ(inline_mat.mirror, 1.f);
    EXPECT_EQ(inline_mat.specular, Material{}.specular);
    EXPECT_EQ(corner(1, 0), Vec3f(4, 0, 0));              // (0,1,0)
    EXPECT_EQ(corner(1, 1), Vec3f(5, 1, 0));              // (1,0,0)
    EXPECT_EQ(corner(1, 2), Vec3f(5, 0, 0));              // (0,0,0)
    EXPECT_EQ(s.normals[s.triangles[1][0]], Vec3f(0.f));  // no normals given: geometric
    // Mesh file relative to the JSON file, scaled then turned about z: (1,1,0) -> (1,2,0) ->
    // (-2,1,0).
    EXPECT_EQ(corner(2, 2), Vec3f(-2, 1, 0));
    EXPECT_EQ(s.materials[s.triangle_material[2]].name, "default");
    // A mesh file without an override keeps its own materials.
    EXPECT_EQ(s.materials[s.triangle_material[5]].name, "red");
    EXPECT_EQ(s.materials[s.triangle_material[6]].name, "matte");
    EXPECT_EQ(s.materials[s.triangle_material[6]].specular, Vec3f(0.f));
    const Material& plain = s.materials[1];
    EXPECT_EQ(plain.name, "plain");
}

TEST(SceneJson, MaterialOverrideAndDefaults) {
    const std::string mesh = data_dir + "materials.obj";
    const Scene s = load_scene_json(
        write("override.json", R"({"materials": [{"name": "m", "diffuse": [1, 0, 0]}],
        "meshes": [{"path": ")" + mesh +
                                   R"(", "material": "m"}, )" + tri + "]}"));
    ASSERT_EQ(s.triangle_count(), 6u);
    for (size_t t = 0; t < 5; ++t) EXPECT_EQ(s.materials[s.triangle_material[t]].name, "m");
    EXPECT_EQ(s.materials[s.triangle_material[5]].name, "default");  // inline mesh, no material
    EXPECT_FALSE(s.camera.has_value());
    EXPECT_TRUE(s.lights.empty());
    EXPECT_EQ(s.background, Scene{}.background);
}

TEST(SceneJson, SyntaxErrorsReportTheLine) {
    struct Case {
        const char* text;
        int line;
    };
    const Case cases[] = {
        {"{\n  \"meshes\": [\n    {\"path\": \"a.obj\"}\n    {\"path\": \"b.obj\"}\n  ]\n}\n",
         4},                     // missing comma
        {"{\"meshes\": []", 1},  // unterminated
        {"{\n\n\"meshes\": [1, 2,,]\n}", 3},
        {"{\n\"a\": \"unterminated\n\"}", 2},
        {"\n\n\n\n   @", 5},
        {"{\"meshes\": [],\n}\n", 2},  // trailing comma
    };
    for (const Case& c : cases) {
        const std::string message = error_of(c.text, "syntax.json");
        EXPECT_NE(message.find("syntax.json:" + std::to_string(c.line) + ": JSON syntax error"),
                  std::string::npos)
            << c.text << "\n -> " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST(SceneJson, SchemaErrorsNameTheJsonPointer) {
    struct Case {
        std::string text, expected;
    };
    const std::vector<Case> cases = {
        {"[]", "bad.json: /: expected an object"},
        {"{}", "/: missing key \"meshes\""},
        {R"({"meshes": []})", "/meshes: no meshes"},
        {R"({"meshes": 5})", "/meshes: expected an array"},
        {with_mesh(
             R"(, "lights": [{"position": [0,0,0]}, {"position": [0,0,0]}, {"position": [1, 2]}])"),
         "bad.json: /lights/2/position: expected 3 numbers"},
        {with_mesh(R"(, "lights": [{"position": [0,"1",0]}])"),
         "/lights/0/position: expected 3 numbers"},
        {with_mesh(R"(, "lights": [{"positon": [0,0,0]}])"), "/lights/0: unknown key \"positon\""},
        {with_mesh(R"(, "lights": [{"type": "area", "position": [0,0,0]}])"),
         "/lights/0/type: unknown light type \"area\""},
        {with_mesh(R"(, "lights": [{"type": 3, "position": [0,0,0]}])"),
         "/lights/0/type: expected a string"},
        {with_mesh(R"(, "lights": [{"position": [0,0,0], "inner_angle": 5}])"),
         "/lights/0: unknown key \"inner_angle\""},
        {with_mesh(
             R"(, "lights": [{"type": "spot", "position": [0,0,0], "inner_angle": 50, "outer_angle": 40}])"),
         "/lights/0: inner_angle is larger than outer_angle"},
        {with_mesh(R"(, "lights": [{"type": "spot", "position": [0,0,0], "outer_angle": 190}])"),
         "/lights/0/outer_angle: value 190 outside [0.0, 180.0]"},
        {with_mesh(R"(, "lights": [{"type": "spot", "position": [0,0,0], "direction": [0,0,0]}])"),
         "/lights/0/direction: zero vector"},
        {with_mesh(R"(, "lights": [{"position": [0,0,0], "intensity": -1}])"),
         "/lights/0/intensity: value -1 outside [0.0, inf]"},
        {with_mesh(R"(, "lights": [{"position": [0,0,0], "color": [1, 1, 1e300]}])"),
         "/lights/0/color/2: number out of float range"},
        {with_mesh(R"(, "lights": {})"), "/lights: expected an array"},
        {with_mesh(R"(, "camera": {"position": [0,0,1], "target": [0,0,0], "fovy": 180})"),
         "/camera/fovy: must be strictly between 0 and 180"},
        {with_mesh(R"(, "camera": {"position": [0,0,1], "target": [0,0,1]})"),
         "/camera/target: equals the position"},
        {with_mesh(R"(, "camera": {"position": [0,0,1], "target": [0,0,0], "up": [0,0,2]})"),
         "/camera/up: parallel to the view direction"},
        {with_mesh(R"(, "camera": {"position": [0,0,1]})"),
         "/camera: \"position\" and \"target\" are required"},
        {with_mesh(R"(, "camera": {"position": [0,0,1], "target": [0,0,0], "fov": 40})"),
         "/camera: unknown key \"fov\""},
        {with_mesh(R"(, "background": [0, 0])"), "/background: expected 3 numbers"},
        {with_mesh(R"(, "background": [0, -1, 0])"), "/background/1: value -1 outside [0.0, inf]"},
        {with_mesh(R"(, "materials": [{"diffuse": [1,1,1]}])"),
         "/materials/0: missing key \"name\""},
        {with_mesh(R"(, "materials": [{"name": "a", "diffuse": [1,2,1]}])"),
         "/materials/0/diffuse: colour components must be in [0, 1]"},
        {with_mesh(R"(, "materials": [{"name": "a", "mirror": 2}])"),
         "/materials/0/mirror: value 2 outside [0.0, 1.0]"},
        {with_mesh(R"(, "materials": [{"name": "a", "shininess": "high"}])"),
         "/materials/0/shininess: expected a number"},
        {with_mesh(R"(, "materials": [{"name": "a"}, {"name": "a"}])"),
         "/materials/1/name: material \"a\" defined twice"},
        {with_mesh(R"(, "materials": [{"name": "a", "colour": [1,1,1]}])"),
         "/materials/0: unknown key \"colour\""},
        {with_mesh(R"(, "extra": 1)"), "/: unknown key \"extra\""},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,3]]}]})",
         "/meshes/0/triangles/0/2: vertex 3 out of range (3 vertices)"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,-1,2]]}]})",
         "/meshes/0/triangles/0/1: expected a vertex index (integer >= 0)"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1.5,2]]}]})",
         "/meshes/0/triangles/0/1: expected a vertex index"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1]]}]})",
         "/meshes/0/triangles/0: expected 3 vertex indices"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": []}]})",
         "/meshes/0/triangles: no triangles"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]]}]})",
         "/meshes/0: missing key \"triangles\""},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0]], "triangles": [[0,1,1]], "normals": [[0,0,1]]}]})",
         "/meshes/0/normals: expected one normal per vertex"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]], "material": "nope"}]})",
         "/meshes/0/material: no material named \"nope\""},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]], "material": {"diffuse": 1}}]})",
         "/meshes/0/material/diffuse: expected 3 numbers"},
        {R"({"meshes": [{"path": "x.obj", "vertices": []}]})",
         "/meshes/0: needs either \"path\" or \"vertices\" + \"triangles\""},
        {R"({"meshes": [{"triangles": [[0,1,2]]}]})", "/meshes/0: needs either"},
        {R"({"meshes": [{"path": 7}]})", "/meshes/0/path: expected a string"},
        {R"({"meshes": [{"path": "other.json"}]})",
         "/meshes/0/path: a mesh cannot be another JSON scene"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]], "transform": {"scale": 0}}]})",
         "/meshes/0/transform: singular transform"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]], "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0]}}]})",
         "/meshes/0/transform/matrix: expected 16 numbers"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]], "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]}}]})",
         "/meshes/0/transform/matrix: the last row must be 0 0 0 1"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]], "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "scale": 2}}]})",
         "/meshes/0/transform: \"matrix\" cannot be combined"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]], "transform": {"rotation": [0,0,0]}}]})",
         "/meshes/0/transform: unknown key \"rotation\""},
        {R"({"meshes": [{"vertices": [[0,0,0],[10,0,0],[0,1,0]], "triangles": [[0,1,2]], "transform": {"scale": 1e38}}]})",
         "/meshes/0/transform: moves a vertex to infinity"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1e38,0,0],[0,1,0]], "triangles": [[0,1,2]], "transform": {"translate": [3e38, 0, 0]}}]})",
         "/meshes/0/transform: moves a vertex to infinity"},
        {R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]]}], "meshes": []})",
         "bad.json: duplicate key \"meshes\""},
        {R"({"meshes": [{"vertices": [[0,0,0],[1e999,0,0],[0,1,0]], "triangles": [[0,1,2]]}]})",
         "bad.json: JSON error: number overflow parsing '1e999'"},
    };
    for (const Case& c : cases) {
        const std::string message = error_of(c.text);
        EXPECT_NE(message.find(c.expected), std::string::npos)
            << c.text << "\n -> " << message << "\n expected: " << c.expected;
        EXPECT_EQ(message.rfind(temp_dir() + "/bad.json: ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST(SceneJson, MeshFileErrorsAreWrapped) {
    const std::string message = error_of(R"({"meshes": [{"path": "missing.obj"}]})", "wrap.json");
    EXPECT_EQ(message, temp_dir() + "/wrap.json: /meshes/0/path: " + temp_dir() +
                           "/missing.obj: no such file");
    write("broken.obj", "v 0 0 0\nf 1 2 3\n");
    EXPECT_NE(error_of(R"({"meshes": [{"path": "broken.obj"}]})")
                  .find("/meshes/0/path: " + temp_dir() + "/broken.obj:2: face uses vertex"),
              std::string::npos);
}

TEST(SceneJson, EmptyGarbageAndMissingFiles) {
    EXPECT_NE(error_of("").find("empty file"), std::string::npos);
    EXPECT_NE(error_of(std::string("\x89PNG\r\n\x1a\n\0\0garbage", 17))
                  .find("bad.json:1: JSON syntax error"),
              std::string::npos);
    EXPECT_NE(error_of(std::string(100000, '[')).find("JSON syntax error"),
              std::string::npos);  // deep nesting
    EXPECT_THROW(load_scene_json(temp_dir() + "/absent.json"), Error);
    EXPECT_THROW(load_scene_file(temp_dir() + "/absent.JSON"), Error);
}

TEST(SceneJson, AtMost32Lights) {
    std::string lights;
    for (int i = 0; i < 32; ++i) lights += std::string(i ? "," : "") + R"({"position": [0, 0, 0]})";
    EXPECT_EQ(load_scene_json(write("lights32.json", with_mesh(R"(, "lights": [)" + lights + "]")))
                  .lights.size(),
              32u);
    EXPECT_NE(error_of(with_mesh(R"(, "lights": [)" + lights + R"(, {"position": [1, 1, 1]}])"))
                  .find("/lights: 33 lights; at most 32"),
              std::string::npos);
}

// The shipped example loads, and the schema document shows exactly that file.
TEST(SceneJson, ExampleSceneLoadsAndMatchesTheDocs) {
    const Scene s = load_scene_file(source_dir + "scenes/example.json");
    EXPECT_GT(s.triangle_count(), 0u);
    EXPECT_TRUE(s.camera.has_value());
    EXPECT_FALSE(s.lights.empty());
    const std::string doc = read(source_dir + "docs/scene-format.md");
    const std::string marker = "```json\n";
    const size_t begin = doc.find(marker);
    ASSERT_NE(begin, std::string::npos);
    const size_t end = doc.find("```", begin + marker.size());
    EXPECT_EQ(doc.substr(begin + marker.size(), end - begin - marker.size()),
              read(source_dir + "scenes/example.json"));
}

}  // namespace
}  // namespace rtt
