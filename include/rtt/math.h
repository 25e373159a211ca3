// Scalar vector maths shared by every part of rtt: plain structs, no SIMD.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rtt {

inline constexpr float pos_inf = std::numeric_limits<float>::infinity();
inline constexpr float neg_inf = -std::numeric_limits<float>::infinity();

/// Triangle index that means "no triangle" (also the miss value of RTTH buffers).
inline constexpr uint32_t invalid_triangle = 0xFFFFFFFFu;

struct Vec3f {
    float x = 0.f, y = 0.f, z = 0.f;

    constexpr Vec3f() = default;
    constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    explicit constexpr Vec3f(float s) : x(s), y(s), z(s) {}

    constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3f operator-() const { return {-x, -y, -z}; }
    constexpr Vec3f& operator+=(const Vec3f& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    constexpr Vec3f& operator-=(const Vec3f& o) {
        x -= o.x;
        y -= o.y;
        z -= o.z;
        return *this;
    }
    constexpr Vec3f& operator*=(float s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
    constexpr bool operator==(const Vec3f&) const = default;
};

constexpr Vec3f operator+(const Vec3f& a, const Vec3f& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
constexpr Vec3f operator-(const Vec3f& a, const Vec3f& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
constexpr Vec3f operator*(const Vec3f& a, const Vec3f& b) {
    return {a.x * b.x, a.y * b.y, a.z * b.z};
}
constexpr Vec3f operator*(const Vec3f& a, float s) {
    return {a.x * s, a.y * s, a.z * s};
}
constexpr Vec3f operator*(float s, const Vec3f& a) {
    return {s * a.x, s * a.y, s * a.z};
}
constexpr Vec3f operator/(const Vec3f& a, float s) {
    return {a.x / s, a.y / s, a.z / s};
}

constexpr float dot(const Vec3f& a, const Vec3f& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3f cross(const Vec3f& a, const Vec3f& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(const Vec3f& a) {
    return std::sqrt(dot(a, a));
}
/// a / |a|, computed as written (CONVENTIONS: ray directions are normalized this way).
inline Vec3f normalize(const Vec3f& a) {
    return a / length(a);
}
inline Vec3f abs(const Vec3f& a) {
    return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)};
}
inline Vec3f min(const Vec3f& a, const Vec3f& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3f max(const Vec3f& a, const Vec3f& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline bool is_finite(const Vec3f& a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
/// Index of the component with the largest magnitude; ties go to the lower axis (x, then y).
/// Every tracer uses this rule, so the watertight test permutes axes identically everywhere.
inline int max_abs_axis(const Vec3f& a) {
    float ax = std::fabs(a.x), ay = std::fabs(a.y), az = std::fabs(a.z);
    if (ax >= ay && ax >= az) return 0;
    return ay >= az ? 1 : 2;
}

struct Bbox3f {
    Vec3f lo{pos_inf}, hi{neg_inf};

    void extend(const Vec3f& p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    void extend(const Bbox3f& b) {
        lo = min(lo, b.lo);
        hi = max(hi, b.hi);
    }
    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    Vec3f diagonal() const { return hi - lo; }
    Vec3f center() const { return (lo + hi) * 0.5f; }
    /// Half the surface area (the SAH only needs ratios of areas).
    float half_area() const {
        Vec3f d = diagonal();
        return d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

/// A ray or segment: points org + t * dir for t in [tmin, tmax].
struct Ray {
    Vec3f org;
    Vec3f dir;
    float tmin = 0.f;
    float tmax = pos_inf;
};

/// Closest hit along a ray. Ties at equal t go to the smaller triangle index.
struct Hit {
    float t = pos_inf;
    uint32_t tri = invalid_triangle;
    bool valid() const { return tri != invalid_triangle; }
    bool operator==(const Hit&) const = default;
};

/// The one ordering of hits every tracer uses: nearer first, then smaller triangle index.
inline bool closer(float t, uint32_t tri, const Hit& best) {
    return t < best.t || (t == best.t && tri < best.tri);
}

}  // namespace rtt
