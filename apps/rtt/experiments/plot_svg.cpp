#include "experiments/plot_svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rtt/io.h"

namespace rtt::bench {
namespace {

constexpr double svg_width = 640, svg_height = 400;
constexpr double left = 64, right = 170, top = 40, bottom = 56;  // margins; legend on the right

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", v);
    return text;
}

std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '&')
            out += "&amp;";
        else if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else
            out += c;
    }
    return out;
}

/// A tick step of 1, 2 or 5 times a power of ten giving about `target` ticks over `span`.
double nice_step(double span, int target) {
    const double raw = span / target;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * power >= raw) return m * power;
    return 10 * power;
}

std::string text(double x, double y, const std::string& s, const char* anchor, int size = 12,
                 const char* extra = "") {
    return "<text x=\"" + number(x) + "\" y=\"" + number(y) + "\" font-size=\"" +
           std::to_string(size) + "\" text-anchor=\"" + anchor + "\"" + extra + ">" + escape(s) +
           "</text>\n";
}

std::string format_tick(double v, double step) {
    char t[32];
    std::snprintf(t, sizeof t, "%.*f", step >= 1 ? 0 : step >= 0.1 ? 1 : 2, v);
    return t;
}

/// A data point: a small filled circle on a line, or a hollow circle / square (see PlotSeries).
std::string marker(const PlotSeries& s, double x, double y) {
    const std::string stroke = "\" stroke=\"" + s.color + "\" stroke-width=\"1.5\"/>\n";
    if (!s.markers_only)
        return "<circle cx=\"" + number(x) + "\" cy=\"" + number(y) + "\" r=\"3\" fill=\"" +
               s.color + stroke;
    if (s.dashed)
        return "<rect x=\"" + number(x - 4.5) + "\" y=\"" + number(y - 4.5) +
               "\" width=\"9\" height=\"9\" fill=\"white" + stroke;
    return "<circle cx=\"" + number(x) + "\" cy=\"" + number(y) + "\" r=\"5\" fill=\"white" +
           stroke;
}

}  // namespace

std::string render_svg(const LinePlot& plot) {
    double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
    auto cover_x = [&](double x) { x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x); };
    auto cover_y = [&](double y) { y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y); };
    for (const PlotSeries& s : plot.series)
        for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) cover_x(s.x[i]), cover_y(s.y[i]);
    for (double t : plot.x_ticks) cover_x(t);
    if (plot.reference_y) cover_y(*plot.reference_y);
    if (x_lo > x_hi) x_lo = 0, x_hi = 1;
    if (y_lo > y_hi) y_lo = 0, y_hi = 1;
    if (x_hi == x_lo) x_lo -= 0.5, x_hi += 0.5;
    const double y_step = nice_step(std::max(y_hi - y_lo, 1e-3), 5);
    // At least a quarter step of margin above and below the data.
    y_lo = std::floor(y_lo / y_step - 0.25) * y_step;
    y_hi = std::ceil(y_hi / y_step + 0.25) * y_step;
    y_lo = std::max(0.0, y_lo);
    const double x_pad = 0.04 * (x_hi - x_lo);
    x_lo -= x_pad, x_hi += x_pad;

    const double pw = svg_width - left - right, ph = svg_height - top - bottom;
    auto px = [&](double x) { return left + (x - x_lo) / (x_hi - x_lo) * pw; };
    auto py = [&](double y) { return top + (1 - (y - y_lo) / (y_hi - y_lo)) * ph; };

    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + number(svg_width) +
                      "\" height=\"" + number(svg_height) + "\" viewBox=\"0 0 " +
                      number(svg_width) + " " + number(svg_height) +
                      "\" font-family=\"sans-serif\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += text(svg_width / 2, 22, plot.title, "middle", 14, " font-weight=\"bold\"");

    // Grid and y ticks.
    for (double y = y_lo; y <= y_hi + 1e-9; y += y_step) {
        svg += "<line x1=\"" + number(left) + "\" y1=\"" + number(py(y)) + "\" x2=\"" +
               number(left + pw) + "\" y2=\"" + number(py(y)) + "\" stroke=\"#e0e0e0\"/>\n";
        svg += text(left - 6, py(y) + 4, format_tick(y, y_step), "end");
    }
    for (size_t i = 0; i < plot.x_ticks.size(); ++i) {
        const double x = px(plot.x_ticks[i]);
        svg += "<line x1=\"" + number(x) + "\" y1=\"" + number(top + ph) + "\" x2=\"" + number(x) +
               "\" y2=\"" + number(top + ph + 5) + "\" stroke=\"black\"/>\n";
        if (i < plot.x_tick_labels.size())
            svg += text(x, top + ph + 18, plot.x_tick_labels[i], "middle", 11);
    }
    svg += "<rect x=\"" + number(left) + "\" y=\"" + number(top) + "\" width=\"" + number(pw) +
           "\" height=\"" + number(ph) + "\" fill=\"none\" stroke=\"black\"/>\n";
    svg += text(left + pw / 2, svg_height - 14, plot.x_label, "middle");
    svg += text(16, top + ph / 2, plot.y_label, "middle", 12,
                (" transform=\"rotate(-90 16 " + number(top + ph / 2) + ")\"").c_str());
    if (plot.reference_y)
        svg += "<line x1=\"" + number(left) + "\" y1=\"" + number(py(*plot.reference_y)) +
               "\" x2=\"" + number(left + pw) + "\" y2=\"" + number(py(*plot.reference_y)) +
               "\" stroke=\"#888\" stroke-dasharray=\"2,3\"/>\n";

    // Series and legend.
    int legend_row = 0;
    for (const PlotSeries& s : plot.series) {
        const size_t n = std::min(s.x.size(), s.y.size());
        if (n == 0) continue;
        const std::string dash = s.dashed ? " stroke-dasharray=\"6,4\"" : "";
        if (!s.markers_only) {
            std::string points;
            for (size_t i = 0; i < n; ++i)
                points += number(px(s.x[i])) + "," + number(py(s.y[i])) + " ";
            svg += "<polyline fill=\"none\" stroke=\"" + s.color + "\" stroke-width=\"2\"" + dash +
                   " points=\"" + points + "\"/>\n";
        }
        for (size_t i = 0; i < n; ++i) svg += marker(s, px(s.x[i]), py(s.y[i]));
        const double ly = top + 10 + 18 * legend_row++;
        const double lx = left + pw + 12;
        if (s.markers_only)
            svg += marker(s, lx + 12, ly);
        else
            svg += "<line x1=\"" + number(lx) + "\" y1=\"" + number(ly) + "\" x2=\"" +
                   number(lx + 24) + "\" y2=\"" + number(ly) + "\" stroke=\"" + s.color +
                   "\" stroke-width=\"2\"" + dash + "/>\n";
        svg += text(lx + 30, ly + 4, s.label, "start", 11);
    }
    svg += "</svg>\n";
    return svg;
}

void write_svg(const std::string& path, const LinePlot& plot) {
    const std::string svg = render_svg(plot);
    write_file_atomically(path, [&](std::FILE* f) { std::fwrite(svg.data(), 1, svg.size(), f); });
}

}  // namespace rtt::bench
