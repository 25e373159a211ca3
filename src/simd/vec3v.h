// Vec3<T>: a 3-vector over any arithmetic-like T; Vec3<vfloat<K>> holds K vectors in
// structure-of-arrays form (one register per coordinate), the layout of ray packets.
#pragma once

#include "rtt/math.h"
#include "simd/isa.h"
#include "simd/varying.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <typename T>
struct Vec3 {
    T x, y, z;

    Vec3() = default;
    RTT_FORCEINLINE Vec3(const T& x_, const T& y_, const T& z_) : x(x_), y(y_), z(z_) {}
    /// Broadcasts a scalar vector to every lane.
    RTT_FORCEINLINE explicit Vec3(const Vec3f& v) : x(v.x), y(v.y), z(v.z) {}

    RTT_FORCEINLINE const T& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    RTT_FORCEINLINE T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

template <typename T>
RTT_FORCEINLINE Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <typename T>
RTT_FORCEINLINE Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <typename T>
RTT_FORCEINLINE Vec3<T> operator*(const Vec3<T>& a, const T& s) {
    return {a.x * s, a.y * s, a.z * s};
}
/// Same operation order as the scalar dot() of math.h: (x*x + y*y) + z*z.
template <typename T>
RTT_FORCEINLINE T dot(const Vec3<T>& a, const Vec3<T>& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
/// Same operation order as the scalar cross() of math.h.
template <typename T>
RTT_FORCEINLINE Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Lane by lane m ? t : f.
template <typename T, typename M>
RTT_FORCEINLINE Vec3<T> select(const M& m, const Vec3<T>& t, const Vec3<T>& f) {
    return {select(m, t.x, f.x), select(m, t.y, f.y), select(m, t.z, f.z)};
}

template <int K>
using Vec3v = Vec3<vfloat<K>>;

}  // namespace RTT_ISA_NS
}  // namespace rtt
