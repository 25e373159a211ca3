// The list of built-in scenes and the dispatch to their generators.
#include "builtin_scenes/makers.h"
#include "rtt/builtin_scenes.h"
#include "rtt/error.h"

namespace rtt {

namespace {

struct Entry {
    const char* name;
    const char* description;
    Scene (*make)();
};

constexpr Entry entries[] = {
    {"room",
     "furnished living room, one planar mirror, 7 spot lights (analogue of the paper's ROOM)",
     make_room_scene},
    {"office", "office with desks, chairs, monitors and keyboards, 16 omni lights (paper's OFFICE)",
     make_office_scene},
    {"plants", "the office filled with potted plants of many small leaves (paper's PLANTS)",
     make_plants_scene},
};

}  // namespace

std::vector<BuiltinSceneInfo> builtin_scenes() {
    std::vector<BuiltinSceneInfo> list;
    for (const Entry& e : entries) list.push_back({e.name, e.description});
    return list;
}

bool is_builtin_scene(const std::string& name) {
    for (const Entry& e : entries)
        if (name == e.name) return true;
    return false;
}

Scene make_builtin_scene(const std::string& name) {
    for (const Entry& e : entries)
        if (name == e.name) return e.make();
    std::string known;
    for (const Entry& e : entries) known += std::string(known.empty() ? "" : ", ") + e.name;
    throw Error("unknown built-in scene '" + name + "' (known: " + known + ")");
}

}  // namespace rtt
