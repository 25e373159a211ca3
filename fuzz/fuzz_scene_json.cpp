// libFuzzer target: bytes as a JSON scene file (load_scene_json). Any input must end in a
// scene or an rtt::Error; a scene that loads is traced by every tracer (fuzz_trace.h). Small
// mesh files sit beside the JSON file so "path" entries can reach the mesh readers.
#include <cstdint>

#include "fuzz_trace.h"
#include "fuzz_util.h"
#include "rtt/scene_io.h"

namespace {

void write_side_files() {
    static const bool done = [] {
        const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n";
        const std::string off = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
        const std::string ply =
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        for (const auto& [name, text] : {std::pair{"a.obj", obj}, {"b.off", off}, {"c.ply", ply}})
            rtt::fuzz::write_file(name, reinterpret_cast<const uint8_t*>(text.data()), text.size());
        return true;
    }();
    (void)done;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    write_side_files();
    const std::string path = rtt::fuzz::write_file("scene.json", data, size);
    rtt::fuzz::expect_only_rtt_errors([&] {
        const rtt::Scene scene = rtt::load_scene_json(path);
        rtt::validate(scene);  // load_scene_json promises a valid scene
        rtt::fuzz::trace_and_compare(scene);
    });
    return 0;
}
