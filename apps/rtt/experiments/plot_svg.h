// Small hand-written SVG line plots for the paper's Figures 7 and 8 (speed-up against
// antialiasing and against resolution). No dependency: a few hundred bytes of SVG per series.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace rtt::bench {

struct PlotSeries {
    std::string label;
    std::vector<double> x, y;  ///< Same length; points are joined in order.
    std::string color = "#1f77b4";
    bool dashed = false;
    /// Hollow markers without a line (reference points): circles, or squares when `dashed`
    /// (the plots draw shadow rays dashed, so a square marks a shadow-ray reference).
    bool markers_only = false;
};

struct LinePlot {
    std::string title;
    std::string x_label;
    std::string y_label;
    std::vector<double> x_ticks;             ///< Positions of the x tick marks.
    std::vector<std::string> x_tick_labels;  ///< One per tick ("1x1", "640x480", ...).
    std::vector<PlotSeries> series;
    std::optional<double> reference_y;  ///< A thin horizontal line (e.g. speed-up 1).
};

/// The plot as a standalone SVG document (640 x 400 user units). Empty series are skipped; the
/// y range covers every point and the reference line with a margin.
std::string render_svg(const LinePlot& plot);

/// Writes render_svg(plot) to `path` whole or not at all; throws rtt::Error on I/O failure.
void write_svg(const std::string& path, const LinePlot& plot);

}  // namespace rtt::bench
