// What travels between ranks in a distributed render (apps/rtt/mpi_render.h): a band's or a
// whole frame's arrays, a frame's ray statistics and the kd-tree, as bytes in one fixed order.
// Sizes follow from the render options and the rows, so only the bytes are sent. No MPI here.
#pragma once

#include <cstddef>
#include <vector>

#include "rtt/kdtree.h"
#include "rtt/render.h"

namespace rtt::cli {

/// The per-pixel and per-sample arrays of a band, in one fixed order: what travels between
/// ranks. Sizes follow from the options and the band's rows, so only the bytes are sent.
struct BandLayout {
    size_t pixels, samples;
    BandLayout(const RenderOptions& o, int rows)
        : pixels(size_t(o.width) * size_t(rows)), samples(pixels * size_t(o.aa) * size_t(o.aa)) {}
};

/// The band's arrays (pixels, hits, shadows, maps, depth, triangles: those asked for).
std::vector<char> pack(const RenderResult& band);
/// Copies a packed band of rows [first_row, first_row + band rows) into `whole`'s arrays
/// (allocated by allocate_whole).
void unpack(const char* bytes, RenderResult& whole, int first_row, const BandLayout& band);
/// The arrays of a whole image, as render() allocates them for `options` and `maps`.
void allocate_whole(RenderResult& out, const RenderOptions& options, const AnswerMaps& maps);

/// A frame's ray statistics.
std::vector<char> pack_stats(const RenderStats& stats);
/// The inverse of pack_stats; `stats.rays_by_depth` must already have its size.
void unpack_stats(const char* bytes, RenderStats& stats);

/// The whole tree: nodes, leaf lists, bounds and statistics.
std::vector<char> pack_tree(const KdTree& tree);
/// The inverse of pack_tree. Throws rtt::Error when the bytes are not a whole packed tree.
KdTree unpack_tree(const std::vector<char>& bytes);

/// A 64-bit hash of the scene's geometry (vertices and triangles), to check that ranks loaded
/// the same scene before they share one tree.
uint64_t geometry_hash(const Scene& scene);

}  // namespace rtt::cli
