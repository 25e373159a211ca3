#include "kdtree/kd_sah.h"

namespace rtt::kd {

SplitChoice find_split_on_axis(int a, std::span<const Event> events, size_t n, const Bbox3f& box,
                               const KdBuildConfig& config) {
    SplitChoice best;
    const AxisCost cost(a, box, n, config);
    if (!cost.has_area()) return best;

    // Sweep: n_left counts triangles starting before p, n_right those ending after p,
    // n_planar those lying in p (Wald & Havran 2006, Algorithm 4).
    size_t n_left = 0, n_right = n;
    const size_t count = events.size();
    for (size_t i = 0; i < count;) {
        const float p = events[i].pos;
        size_t ending = 0, planar = 0, starting = 0;
        while (i < count && events[i].pos == p && events[i].type() == EventType::end) ++ending, ++i;
        while (i < count && events[i].pos == p && events[i].type() == EventType::planar) ++planar, ++i;
        while (i < count && events[i].pos == p && events[i].type() == EventType::start) ++starting, ++i;
        n_right -= planar + ending;

        const auto consider = [&](size_t cl, size_t cr, bool planar_left) {
            const double c = cost(p, cl, cr);
            if (c < best.cost) best = {a, p, planar_left, c, cl, cr};
        };
        consider(n_left + planar, n_right, true);
        if (planar > 0) consider(n_left, n_right + planar, false);
        n_left += starting + planar;
    }
    return best;
}

SplitChoice find_split(const NodeEvents& ev, const Bbox3f& box, const KdBuildConfig& config) {
    SplitChoice best;
    for (int a = 0; a < 3; ++a)
        best = better(best, find_split_on_axis(a, ev.axis[a], ev.triangles, box, config));
    return best;
}

}  // namespace rtt::kd
