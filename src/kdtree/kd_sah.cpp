#include "kdtree/kd_sah.h"

namespace rtt::kd {

SplitChoice find_split(const NodeEvents& ev, const Bbox3f& box, const KdBuildConfig& config) {
    SplitChoice best;
    const Vec3f diag = box.diagonal();
    const double area = double(diag.x) * diag.y + double(diag.y) * diag.z + double(diag.z) * diag.x;
    // A box that is a segment or a point holds only degenerate triangles no ray can tell
    // apart; and area ratios are undefined there.
    if (!(area > 0.0)) return best;
    const double inv_area = 1.0 / area;
    const size_t n = ev.triangles;
    const double trav = config.trav_cost, isect = config.isect_cost;
    const double bonus_factor = 1.0 - double(config.empty_bonus);

    for (int a = 0; a < 3; ++a) {
        const EventList& events = ev.axis[a];
        const double lo = box.lo[a], hi = box.hi[a];
        // Half area of a child of extent w along a: w * (d1 + d2) + d1 * d2.
        const double d1 = diag[(a + 1) % 3], d2 = diag[(a + 2) % 3];
        const double cap = d1 * d2, perimeter = d1 + d2;

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

            const double pl = (cap + (double(p) - lo) * perimeter) * inv_area;
            const double pr = (cap + (hi - double(p)) * perimeter) * inv_area;
            const auto consider = [&](size_t cl, size_t cr, bool planar_left) {
                // A split at the node's face leaves the other child equal to the node; it
                // is progress only if that child loses triangles (a flat cell took them).
                if ((double(p) == hi && cl == n) || (double(p) == lo && cr == n)) return;
                double cost = trav + isect * (pl * double(cl) + pr * double(cr));
                if (cl == 0 || cr == 0) cost *= bonus_factor;
                if (cost < best.cost) best = {a, p, planar_left, cost, cl, cr};
            };
            consider(n_left + planar, n_right, true);
            if (planar > 0) consider(n_left, n_right + planar, false);
            n_left += starting + planar;
        }
    }
    return best;
}

}  // namespace rtt::kd
