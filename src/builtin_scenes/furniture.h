// Furnishings shared by the built-in interiors: the room shell, windows, bookshelves with
// books, vases, picture frames, doors and ceiling fittings. Each is built in its own local
// frame (documented per function) and placed with an Xform.
#pragma once

#include <span>

#include "builtin_scenes/procedural.h"

namespace rtt::proc {

/// Materials a closed room shell uses.
struct ShellMaterials {
    uint32_t floor, walls, ceiling, skirting;
};

/// Closed box room [0, size] seen from inside (faces point inward), floor and ceiling split
/// into cells of about `cell` metres, walls likewise, with a skirting board along the walls.
void room_shell(SceneBuilder& b, const Vec3f& size, const ShellMaterials& m, float cell);

/// A wall's frame: local x along the wall, y up, z pointing into the room; the wall surface is
/// the local plane z = 0 and the local origin sits at floor level.
/// Walls of a room [0, size]: 0 = back (z = 0), 1 = left (x = 0), 2 = right (x = size.x),
/// 3 = front (z = size.z). Local x runs left to right seen from inside the room.
Xform wall_frame(const Vec3f& size, int wall, float along);

struct WindowMaterials {
    uint32_t frame, glass, sill;
};

/// A window in local wall coordinates (see wall_frame): lower-left corner of the opening at
/// (0, 0), `w` x `h` metres, a cross of mullions, a sill below; the glass is a bright panel
/// 1 cm in front of the wall (the room stays closed).
void window(SceneBuilder& b, const Xform& at, float w, float h, const WindowMaterials& m);

/// A gathered curtain hanging from y = top down to y = 0, `w` wide, in local wall coordinates
/// starting at x = 0, standing `offset` in front of the wall.
void curtain(SceneBuilder& b, const Xform& at, float w, float top, float offset, uint32_t mat);

/// A bookshelf against a wall: local x in [0, w], y in [0, h], back at z = 0, front at z = d,
/// with `shelves` boards; books (random but seeded) on every board but the top, and some
/// ornaments (vases, spheres) from `ornament` materials.
void bookshelf(SceneBuilder& b, const Xform& at, float w, float h, float d, int shelves,
               uint32_t wood, std::span<const uint32_t> book_materials,
               std::span<const uint32_t> ornament_materials, SceneRng& rng);

/// A vase of height h standing on the local origin; style 0..3 picks the profile.
Mesh vase(float h, int style, int segments);

/// A rectangular frame on a wall: local x in [0, w], y in [0, h], 5 cm wide, standing out
/// 3.5 cm from z = 0; its opening is x in [0.05, w - 0.05], y in [0.05, h - 0.05].
void frame(SceneBuilder& b, const Xform& at, float w, float h, uint32_t mat);

/// A framed picture (frame plus canvas 1.2 cm in front of the wall).
void picture(SceneBuilder& b, const Xform& at, float w, float h, uint32_t frame, uint32_t canvas);

/// A panel door with frame and handle in local wall coordinates, x in [0, 0.9], y in [0, 2.05].
void door(SceneBuilder& b, const Xform& at, uint32_t wood, uint32_t metal);

}  // namespace rtt::proc
