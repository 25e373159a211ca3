// Internal: the generator of each built-in scene (dispatched by catalogue.cpp) and the
// office layout that the plants scene furnishes further.
#pragma once

#include <vector>

#include "builtin_scenes/procedural.h"
#include "rtt/scene.h"

namespace rtt {

Scene make_room_scene();
Scene make_office_scene();
Scene make_plants_scene();

/// A free spot on a horizontal surface: nothing within `reach` of the vertical line through
/// `position` (up to the height a plant there may reach).
struct PlantSpot {
    Vec3f position;
    float reach = 0.f;
};

/// Where the office left room, for scenes built on top of it.
struct OfficeLayout {
    Vec3f size;                          ///< The room is [0, size].
    std::vector<PlantSpot> desk_spots;   ///< On desk tops, beside monitors (about 1.2 m headroom).
    std::vector<PlantSpot> floor_spots;  ///< On the floor, for large pots (up to 2 m tall).
    std::vector<PlantSpot> shelf_spots;  ///< On window sills and cabinet tops.
    std::vector<Vec3f> planter_spots;    ///< Floor strips 0.45 x 1.6 m (long along z), centres.
};

/// Builds the office (shell, furniture, 16 omni lights, camera) into `scene` through `b`.
OfficeLayout build_office(Scene& scene, proc::SceneBuilder& b);

}  // namespace rtt
