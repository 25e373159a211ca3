// Printing and saving render statistics (`--stats`, `--stats-json`).
#pragma once

#include <cstdio>
#include <string>

#include "render_job.h"

namespace rtt::cli {

/// One line: the kd-tree build's phases and their wall seconds (KdStats).
std::string kd_build_phases(const KdStats& s);

/// Writes a table: one row per ray kind (primary, shadow, secondary) with tiles, RTT tiles,
/// rays, traced, answered, average relevant-list length, tracer seconds and Mrays/s.
void print_stats(std::FILE* out, const RenderJobResult& r);
/// One line per rank of a distributed run: tiles, rendering and idle seconds.
void print_rank_stats(std::FILE* out, const std::vector<RankStats>& ranks);

/// The same numbers as JSON, written whole or not at all.
void write_stats_json(const std::string& path, const RenderJob& job, const RenderJobResult& r);

}  // namespace rtt::cli
