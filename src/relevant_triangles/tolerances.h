// RTT's tolerances, named, in one place. Each is a chosen margin, not a rounding bound: the
// bounds it must exceed are derived where it is used (the file named with it) and in
// docs/design.md, "RTT exactness". A tolerance decides which rays are answered from a list and
// which are traced; answers never depend on it. Rounding allowances that are part of a
// derivation (the 2^-20 and 2^-21 of make_shaft_quad, the multiples of unit_roundoff in the
// five tests) stay beside their derivation.
#pragma once

namespace rtt::tolerance {

/// Unit roundoff of float: error bounds are written in multiples of it.
inline constexpr float unit_roundoff = 0x1p-24f;

/// Per-ray check (shaft.cpp): a ray whose float slopes lie this far outside the corners' slope
/// quad is still answered from the list (border samples round by a few ulps).
inline constexpr float slope = 0x1p-20f;
/// Largest move (max-norm, slope units) of a corner of the grown slope quad (shaft.cpp): beyond
/// it the quad is so acute that the margins would reject almost nothing, and no shaft is made.
inline constexpr float max_quad_move = 0x1p-10f;
/// Relative widening of the start and end offset ranges a ray must lie in (shaft.cpp, and
/// shadow_tiles.cpp): covers the offsets' rounding in R.
inline constexpr float offset_range = 0x1p-16f;

/// R's box test (region.h, PlaneSet; corner_pass.cpp's "behind the apex" test): a box is
/// declared outside a half-space only beyond this times the scene's extent from the apex, far
/// more than the test's rounding and than the watertight test's fuzz.
inline constexpr float box_test = 0x1p-18f;

/// Primary end (primary_tiles.cpp): R's end offset is the corners' farthest hit offset grown by
/// this relative amount, and R's end plane P is moved beyond the plane by end_plane times
/// (h + the farthest hit's distance), h the apex's height over P.
inline constexpr float end_offset = 0x1p-10f;
inline constexpr float end_plane = 0x1p-14f;

/// Shadow receiver plane (shadow_tiles.cpp): a point may lie beyond the plane by this fraction of
/// the gap (1 - tmax) h the segments leave before it.
inline constexpr float receiver_gap = 0.25f;

}  // namespace rtt::tolerance
