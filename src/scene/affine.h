// Affine transforms for placing imported meshes (assimp node transforms, JSON mesh transforms).
// Composed and applied in double precision, rounded to float once per coordinate.
#pragma once

#include <array>
#include <cmath>

#include "rtt/math.h"

namespace rtt::detail {

/// Row-major 3x4 matrix [L | t]: p' = L p + t. The implicit last row is (0 0 0 1).
struct Affine {
    std::array<std::array<double, 4>, 3> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

    bool is_identity() const { return *this == Affine{}; }
    bool operator==(const Affine&) const = default;

    /// this * b: apply b first, then this.
    Affine operator*(const Affine& b) const {
        Affine r;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j)
                r.m[i][j] = m[i][0] * b.m[0][j] + m[i][1] * b.m[1][j] + m[i][2] * b.m[2][j] +
                            (j == 3 ? m[i][3] : 0.0);
        return r;
    }

    Vec3f point(const Vec3f& p) const {
        return {float(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3]),
                float(m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3]),
                float(m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3])};
    }
    Vec3f vector(const Vec3f& v) const {
        return {float(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z),
                float(m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z),
                float(m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z)};
    }

    double determinant() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }

    /// Unit normal transformed by the inverse transpose of L, computed as the cofactor matrix
    /// (inverse transpose times det L) with the sign of det L, so no division by det is needed.
    /// Returns the zero vector, which shading reads as "use the geometric normal", when the
    /// result is degenerate.
    Vec3f normal(const Vec3f& n) const {
        auto c = [&](int r0, int r1, int c0, int c1) {
            return m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
        };
        // Row i of the cofactor matrix, cof(L)_ij = (-1)^(i+j) minor_ij.
        const double x = c(1, 2, 1, 2) * n.x - c(1, 2, 0, 2) * n.y + c(1, 2, 0, 1) * n.z;
        const double y = -c(0, 2, 1, 2) * n.x + c(0, 2, 0, 2) * n.y - c(0, 2, 0, 1) * n.z;
        const double z = c(0, 1, 1, 2) * n.x - c(0, 1, 0, 2) * n.y + c(0, 1, 0, 1) * n.z;
        const double len = std::sqrt(x * x + y * y + z * z) * (determinant() < 0.0 ? -1.0 : 1.0);
        if (!(std::fabs(len) > 0.0) || !std::isfinite(len)) return Vec3f{0.f};
        return {float(x / len), float(y / len), float(z / len)};
    }

    bool is_finite() const {
        for (const auto& row : m)
            for (double v : row)
                if (!std::isfinite(v)) return false;
        return true;
    }
};

inline Affine translation(double x, double y, double z) {
    Affine a;
    a.m[0][3] = x;
    a.m[1][3] = y;
    a.m[2][3] = z;
    return a;
}

inline Affine scaling(double x, double y, double z) {
    Affine a;
    a.m[0][0] = x;
    a.m[1][1] = y;
    a.m[2][2] = z;
    return a;
}

/// Right-handed rotation by `degrees` about coordinate axis 0 (x), 1 (y) or 2 (z). Multiples
/// of 90 degrees are exact (cos(pi/2) in floating point is 6e-17, not 0).
inline Affine rotation(int axis, double degrees) {
    double c, s;
    const double quarter = degrees / 90.0;
    if (quarter == std::floor(quarter) && std::fabs(quarter) < 1e9) {
        static constexpr double cos_q[4] = {1, 0, -1, 0}, sin_q[4] = {0, 1, 0, -1};
        const auto q = static_cast<long long>(quarter);
        const int k = int(((q % 4) + 4) % 4);
        c = cos_q[k];
        s = sin_q[k];
    } else {
        const double r = degrees * (3.14159265358979323846 / 180.0);
        c = std::cos(r);
        s = std::sin(r);
    }
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    Affine a;
    a.m[i][i] = c;
    a.m[i][j] = -s;
    a.m[j][i] = s;
    a.m[j][j] = c;
    return a;
}

}  // namespace rtt::detail
