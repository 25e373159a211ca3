// Internal: the furniture of the `room` scene, each in a local frame standing on the floor
// (y = 0) at the origin, facing +z.
#pragma once

#include "builtin_scenes/procedural.h"

namespace rtt::proc {

/// A turned (lathe-made) leg of height h and base radius r with beads and a taper.
Mesh turned_leg(float h, float r, int segments);

/// Dining chair: seat 0.46 m square at 0.45 m, turned legs, spindle back towards -z.
void dining_chair(SceneBuilder& b, const Xform& at, uint32_t wood, uint32_t seat);

/// Round pedestal table, radius 0.6 m, top at 0.755 m.
void round_table(SceneBuilder& b, const Xform& at, uint32_t wood);

/// Three-seat sofa 2.1 m wide (x), 0.9 m deep, back towards -z.
void sofa(SceneBuilder& b, const Xform& at, uint32_t fabric, uint32_t cushion, uint32_t pillow,
          uint32_t wood);

/// Floor lamp about 1.7 m tall.
void floor_lamp(SceneBuilder& b, const Xform& at, uint32_t metal, uint32_t shade);

/// Bowl of fruit (spheres) standing at the origin.
void fruit_bowl(SceneBuilder& b, const Xform& at, uint32_t bowl, uint32_t fruit_a,
                uint32_t fruit_b);

/// Low sideboard 1.6 m wide (x in [0, 1.6]), 0.45 m deep (back at z = 0), 0.8 m tall.
void sideboard(SceneBuilder& b, const Xform& at, uint32_t wood, uint32_t metal);

/// A ceiling spot fitting hanging from the ceiling at y = ceiling, centred on the origin's x, z.
void ceiling_spot(SceneBuilder& b, const Vec3f& at, float ceiling, uint32_t metal);

}  // namespace rtt::proc
