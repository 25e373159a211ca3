// The SIMD value types and the K-wide watertight test, lane by lane against the scalar C++
// they stand for, bit for bit (NaN, infinities, signed zeros and denormals included).
#include "simd/simd.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include "geom/triangle_simd.h"
#include "simd/lane_bytes.h"

namespace rtt {
namespace {

template <typename T>
class Simd : public ::testing::Test {};
using Widths = ::testing::Types<std::integral_constant<int, 4>
#ifdef RTT_HAVE_SIMD8
                                ,
                                std::integral_constant<int, 8>
#endif
#ifdef RTT_HAVE_SIMD16
                                ,
                                std::integral_constant<int, 16>
#endif
                                >;
TYPED_TEST_SUITE(Simd, Widths);

bool same_bits(float a, float b) {
    return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
}

/// Test values: ordinary, tiny, huge, and every special case, in a shuffled order.
std::vector<float> test_values(int count, unsigned seed) {
    const float specials[] = {0.f,
                              -0.f,
                              1.f,
                              -1.f,
                              0.5f,
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              std::numeric_limits<float>::quiet_NaN(),
                              -std::numeric_limits<float>::quiet_NaN(),
                              std::numeric_limits<float>::denorm_min(),
                              -std::numeric_limits<float>::denorm_min(),
                              std::numeric_limits<float>::max(),
                              std::numeric_limits<float>::min(),
                              3.f,
                              3.f};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-4.f, 4.f);
    std::uniform_int_distribution<int> pick(0, 3);
    std::vector<float> v;
    for (int i = 0; i < count; ++i) {
        switch (pick(rng)) {
            case 0:
                v.push_back(specials[rng() % std::size(specials)]);
                break;
            case 1:
                v.push_back(u(rng) * 1e-30f);
                break;
            default:
                v.push_back(u(rng));
                break;
        }
    }
    return v;
}

TYPED_TEST(Simd, FloatArithmeticMatchesScalarBitForBit) {
    constexpr int K = TypeParam::value;
    using vf = vfloat<K>;
    const std::vector<float> a = test_values(K * 400, 1), b = test_values(K * 400, 2);
    int mismatches = 0;
    for (size_t base = 0; base < a.size(); base += K) {
        const vf x = vf::loadu(&a[base]), y = vf::loadu(&b[base]);
        const vf sum = x + y, diff = x - y, prod = x * y, quot = x / y, neg = -x;
        const vf mn = min(x, y), mx = max(x, y), ab = abs(x), inv = rcp(x), root = sqrt(x);
        const vf sel = select(x < y, x, y);
        const vf fms = fused_mul_sub(x, y, sum);
        for (int i = 0; i < K; ++i) {
            const float s = a[base + i], t = b[base + i];
            // One rounding on every ISA (emulated through double without FMA): std::fma's bits.
            const float f = std::fma(s, t, -(s + t));
            mismatches += std::isnan(f) ? !std::isnan(fms[i]) : !same_bits(fms[i], f);
            // With two NaN operands IEEE 754 leaves open which one propagates, and GCC treats
            // the add and multiply intrinsics as commutative (it may swap their operands, as it
            // did at -O1): only NaN-ness is compared then. (Not a question for tracing: a NaN
            // never reaches an answer.)
            const bool two_nans = std::isnan(s) && std::isnan(t);
            mismatches += two_nans ? !std::isnan(sum[i]) : !same_bits(sum[i], s + t);
            mismatches += !same_bits(diff[i], s - t);
            mismatches += two_nans ? !std::isnan(prod[i]) : !same_bits(prod[i], s * t);
            mismatches += !same_bits(quot[i], s / t);
            mismatches += !same_bits(neg[i], -s);
            // min(x, y) is std::min(y, x); max(x, y) is std::max(y, x) (vfloat4.h).
            mismatches += !same_bits(mn[i], std::min(t, s));
            mismatches += !same_bits(mx[i], std::max(t, s));
            mismatches += !same_bits(ab[i], std::fabs(s));
            mismatches += !same_bits(inv[i], 1.f / s);
            mismatches += !std::isnan(s) && !same_bits(root[i], std::sqrt(s));
            mismatches += std::isnan(s) && !std::isnan(root[i]);
            mismatches += !same_bits(sel[i], s < t ? s : t);
        }
    }
    EXPECT_EQ(mismatches, 0);
}

// The triangle test's edge functions (geom/triangle.h): every width gives the scalar form's
// bits, and the result keeps the exact difference's sign and lies within 1.5 ulps of it, also
// where the two products cancel to a few bits (thin triangles met at grazing angles).
TYPED_TEST(Simd, DifferenceOfProductsIsExactInSignAndSameInEveryWidth) {
    constexpr int K = TypeParam::value;
    using vf = vfloat<K>;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-4.f, 4.f);
    std::uniform_int_distribution<int> ulps(-3, 3);
    const auto nudge = [&](float x) {
        for (int n = ulps(rng); n != 0; n += n > 0 ? -1 : 1)
            x = std::nextafter(x, n > 0 ? INFINITY : -INFINITY);
        return x;
    };
    int mismatches = 0, wrong_sign = 0, inaccurate = 0, cancelling = 0;
    for (int round = 0; round < 2000; ++round) {
        alignas(64) float a[K], b[K], c[K], d[K];
        for (int i = 0; i < K; ++i) {
            a[i] = u(rng), b[i] = u(rng);
            // Half the lanes: c * d within a few ulps of a * b, so the difference cancels.
            const bool cancel = (round + i) % 2 == 0;
            c[i] = cancel ? nudge(a[i]) : u(rng);
            d[i] = cancel ? nudge(b[i]) : u(rng);
        }
        const vf r = difference_of_products(vf::load(a), vf::load(b), vf::load(c), vf::load(d));
        for (int i = 0; i < K; ++i) {
            const float s = difference_of_products(a[i], b[i], c[i], d[i]);
            mismatches += !same_bits(r[i], s);
            // Products of floats are exact in double, and their difference is rounded once.
            const double exact = double(a[i]) * b[i] - double(c[i]) * d[i];
            wrong_sign += (s > 0) != (exact > 0) || (s < 0) != (exact < 0);
            if (exact != 0) {
                const double ulp = std::ldexp(1.0, std::ilogb(float(exact)) - 23);
                inaccurate += std::fabs(s - exact) > 1.5 * ulp;
            }
            cancelling += std::fabs(exact) < 1e-4 * std::fabs(double(a[i]) * b[i]);
        }
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_EQ(wrong_sign, 0);
    EXPECT_EQ(inaccurate, 0);
    EXPECT_GT(cancelling, 100) << "the test should cancel products to a few bits";
}

TYPED_TEST(Simd, FloatComparisonsFollowCpp) {
    constexpr int K = TypeParam::value;
    using vf = vfloat<K>;
    const std::vector<float> a = test_values(K * 400, 3), b = test_values(K * 400, 4);
    int mismatches = 0;
    for (size_t base = 0; base < a.size(); base += K) {
        const vf x = vf::loadu(&a[base]), y = vf::loadu(&b[base]);
        const uint32_t lt = movemask(x < y), le = movemask(x <= y), gt = movemask(x > y);
        const uint32_t ge = movemask(x >= y), eq = movemask(x == y), ne = movemask(x != y);
        const uint32_t nan = movemask(isnan(x)), sign = signbits(x);
        const uint32_t m = uint32_t(base * 2654435761u) & all_lanes<K>;  // some lanes masked off
        const uint32_t ng = movemask(not_greater(vbool<K>::from_bits(m), x, y));
        for (int i = 0; i < K; ++i) {
            const float s = a[base + i], t = b[base + i];
            mismatches += ((ng >> i) & 1) != uint32_t(((m >> i) & 1) && !(s > t));
            mismatches += ((lt >> i) & 1) != uint32_t(s < t);
            mismatches += ((le >> i) & 1) != uint32_t(s <= t);
            mismatches += ((gt >> i) & 1) != uint32_t(s > t);
            mismatches += ((ge >> i) & 1) != uint32_t(s >= t);
            mismatches += ((eq >> i) & 1) != uint32_t(s == t);
            mismatches += ((ne >> i) & 1) != uint32_t(s != t);
            mismatches += ((nan >> i) & 1) != uint32_t(std::isnan(s));
            mismatches += ((sign >> i) & 1) != uint32_t(std::signbit(s));
        }
    }
    EXPECT_EQ(mismatches, 0);
}

TYPED_TEST(Simd, LoadsStoresLanesAndReductions) {
    constexpr int K = TypeParam::value;
    using vf = vfloat<K>;
    alignas(64) float in[K], out[K];
    for (int i = 0; i < K; ++i) in[i] = float(i * 7 % K) - 2.5f;
    const vf x = vf::load(in);
    store(out, x);
    for (int i = 0; i < K; ++i) EXPECT_EQ(out[i], in[i]);
    EXPECT_EQ(reduce_min(x)[K - 1], *std::min_element(in, in + K));
    EXPECT_EQ(reduce_max(x)[0], *std::max_element(in, in + K));

    vf y(9.f);
    y.set(K - 1, -1.f);
    EXPECT_EQ(y[K - 1], -1.f);
    EXPECT_EQ(y[0], 9.f);

    // Masked store writes exactly the lanes of the mask.
    const uint32_t bits = 0xA5A5u & all_lanes<K>;
    for (int i = 0; i < K; ++i) out[i] = 100.f;
    store(vbool<K>::from_bits(bits), out, x);
    for (int i = 0; i < K; ++i) EXPECT_EQ(out[i], (bits >> i) & 1 ? in[i] : 100.f) << "lane " << i;

    // Lane masks to and from one byte per lane (activity and visibility arrays).
    {
        const uint8_t bytes[17] = {0, 1, 0, 2, 255, 0, 0, 1, 1, 0, 1, 0, 0, 0, 7, 1, 9};
        for (int n = 0; n <= 16; ++n) {
            uint32_t expect = 0;
            for (int i = 0; i < n; ++i) expect |= bytes[i] != 0 ? 1u << i : 0u;
            EXPECT_EQ(nonzero_bytes(bytes, n), expect) << n;
        }
        uint8_t out[K + 1];
        out[K] = 77;
        const uint32_t bits = 0xB5C3u & all_lanes<K>;
        store_bits_as_bytes<K>(out, bits);
        for (int i = 0; i < K; ++i) EXPECT_EQ(out[i], (bits >> i) & 1u) << i;
        EXPECT_EQ(out[K], 77);
    }

    // Pairs stored interleaved, bit for bit, at an unaligned address.
    {
        const std::vector<float> a = test_values(K, 13), b = test_values(K, 14);
        std::vector<float> pairs(2 * K + 1, 100.f);
        storeu_pairs(pairs.data() + 1, vf::loadu(a.data()), vf::loadu(b.data()));
        EXPECT_EQ(pairs[0], 100.f);
        for (int i = 0; i < K; ++i) {
            EXPECT_TRUE(same_bits(pairs[size_t(1 + 2 * i)], a[size_t(i)])) << i;
            EXPECT_TRUE(same_bits(pairs[size_t(2 + 2 * i)], b[size_t(i)])) << i;
        }
    }

    // Records of 8 and of 3 floats read as structure of arrays, bit for bit (NaN payloads,
    // signed zeros), from an unaligned address.
    const std::vector<float> pool = test_values(8 * K + 1, 11);
    vf rec8[8], rec3[3];
    load_records8(pool.data() + 1, rec8);
    load_records3(pool.data() + 1, rec3);
    for (int i = 0; i < K; ++i) {
        for (int f = 0; f < 8; ++f)
            EXPECT_TRUE(same_bits(rec8[f][i], pool[size_t(1 + 8 * i + f)])) << i << " " << f;
        for (int c = 0; c < 3; ++c)
            EXPECT_TRUE(same_bits(rec3[c][i], pool[size_t(1 + 3 * i + c)])) << i << " " << c;
    }

    // The same in rows of a packet's width, a row stride apart (a block of a wider tile), and
    // with the rows adjacent (a run).
    constexpr int width = K == 4 ? 2 : 4, rows = K / width;
    for (const int records_apart : {width + 3, width}) {
        const std::vector<float> grid = test_values(size_t(8 * records_apart * rows + 1), 12);
        load_record_rows8(grid.data() + 1, 8 * records_apart, rec8);
        load_record_rows3(grid.data() + 1, 3 * records_apart, rec3);
        for (int i = 0; i < K; ++i) {
            const int record = (i / width) * records_apart + i % width;
            for (int f = 0; f < 8; ++f)
                EXPECT_TRUE(same_bits(rec8[f][i], grid[size_t(1 + 8 * record + f)]))
                    << records_apart << " " << i << " " << f;
            for (int c = 0; c < 3; ++c)
                EXPECT_TRUE(same_bits(rec3[c][i], grid[size_t(1 + 3 * record + c)]))
                    << records_apart << " " << i << " " << c;
        }
    }
}

TYPED_TEST(Simd, MasksMatchTheirBits) {
    constexpr int K = TypeParam::value;
    using vb = vbool<K>;
    std::mt19937 rng(5);
    for (int trial = 0; trial < 200; ++trial) {
        const uint32_t a = rng() & all_lanes<K>, b = rng() & all_lanes<K>;
        const vb x = vb::from_bits(a), y = vb::from_bits(b);
        EXPECT_EQ(movemask(x), a);
        EXPECT_EQ(movemask(x & y), a & b);
        EXPECT_EQ(movemask(x | y), a | b);
        EXPECT_EQ(movemask(x ^ y), a ^ b);
        EXPECT_EQ(movemask(!x), ~a & all_lanes<K>);
        EXPECT_EQ(movemask(andnot(x, y)), a & ~b);
        EXPECT_EQ(any(x), a != 0);
        EXPECT_EQ(none(x), a == 0);
        EXPECT_EQ(all(x), a == all_lanes<K>);
        EXPECT_EQ(popcount(x), std::popcount(a));
        for (int i = 0; i < K; ++i) EXPECT_EQ(x[i], bool((a >> i) & 1));
    }
    EXPECT_TRUE(all(vb(true)));
    EXPECT_TRUE(none(vb(false)));
}

TYPED_TEST(Simd, IntegersMatchScalar) {
    constexpr int K = TypeParam::value;
    using vi = vint<K>;
    std::mt19937 rng(6);
    const int32_t specials[] = {0, 1, -1, INT32_MIN, INT32_MAX, 7};
    alignas(64) int32_t a[K], b[K], out[K];
    int mismatches = 0;
    for (int trial = 0; trial < 300; ++trial) {
        for (int i = 0; i < K; ++i) {
            a[i] = rng() % 3 ? int32_t(rng()) : specials[rng() % 6];
            b[i] = rng() % 3 ? int32_t(rng()) : (rng() % 2 ? a[i] : specials[rng() % 6]);
        }
        const vi x = vi::load(a), y = vi::loadu(b);
        const vi sum = x + y, diff = x - y, prod = x * y, band = x & y, bor = x | y, bxor = x ^ y;
        const vi mn = min(x, y), mx = max(x, y), sel = select(x < y, x, y);
        const uint32_t eq = movemask(x == y), ne = movemask(x != y), lt = movemask(x < y);
        const uint32_t gt = movemask(x > y), ul = movemask(ult(x, y));
        for (int i = 0; i < K; ++i) {
            const uint32_t ua = uint32_t(a[i]), ub = uint32_t(b[i]);
            mismatches += uint32_t(sum[i]) != ua + ub;
            mismatches += uint32_t(diff[i]) != ua - ub;
            mismatches += uint32_t(prod[i]) != ua * ub;
            mismatches += band[i] != (a[i] & b[i]);
            mismatches += bor[i] != (a[i] | b[i]);
            mismatches += bxor[i] != (a[i] ^ b[i]);
            mismatches += mn[i] != std::min(a[i], b[i]);
            mismatches += mx[i] != std::max(a[i], b[i]);
            mismatches += sel[i] != (a[i] < b[i] ? a[i] : b[i]);
            mismatches += ((eq >> i) & 1) != uint32_t(a[i] == b[i]);
            mismatches += ((ne >> i) & 1) != uint32_t(a[i] != b[i]);
            mismatches += ((lt >> i) & 1) != uint32_t(a[i] < b[i]);
            mismatches += ((gt >> i) & 1) != uint32_t(a[i] > b[i]);
            mismatches += ((ul >> i) & 1) != uint32_t(ua < ub);
        }
        store(out, sum);
        for (int i = 0; i < K; ++i) mismatches += out[i] != sum[i];
    }
    EXPECT_EQ(mismatches, 0);
    const vi s = vi::step();
    vi t(3);
    t.set(K - 1, 42);
    for (int i = 0; i < K; ++i) {
        EXPECT_EQ(s[i], i);
        EXPECT_EQ(t[i], i == K - 1 ? 42 : 3);
    }
    EXPECT_EQ(movemask(as_int(vfloat<K>(-0.f)) == vi(INT32_MIN)), all_lanes<K>);
    EXPECT_EQ(as_float(vi(0x3F800000))[0], 1.f);
}

TYPED_TEST(Simd, Vec3MatchesScalarVectorMaths) {
    constexpr int K = TypeParam::value;
    using vf = vfloat<K>;
    const std::vector<float> c = test_values(6 * K, 7);
    int mismatches = 0;
    Vec3v<K> a(Vec3f{0.f}), b(Vec3f{0.f});
    for (int i = 0; i < K; ++i) {
        a.x.set(i, c[6 * i]);
        a.y.set(i, c[6 * i + 1]);
        a.z.set(i, c[6 * i + 2]);
        b.x.set(i, c[6 * i + 3]);
        b.y.set(i, c[6 * i + 4]);
        b.z.set(i, c[6 * i + 5]);
    }
    const vf d = dot(a, b);
    const Vec3v<K> x = cross(a, b), s = a - b, p = a + b;
    for (int i = 0; i < K; ++i) {
        const Vec3f sa{a.x[i], a.y[i], a.z[i]}, sb{b.x[i], b.y[i], b.z[i]};
        const Vec3f sx = cross(sa, sb), ss = sa - sb, sp = sa + sb;
        mismatches += !same_bits(d[i], dot(sa, sb));
        for (int k = 0; k < 3; ++k) {
            mismatches += !same_bits(x[k][i], sx[k]);
            mismatches += !same_bits(s[k][i], ss[k]);
            mismatches += !same_bits(p[k][i], sp[k]);
        }
    }
    EXPECT_EQ(mismatches, 0);
    const Vec3v<K> broadcast(Vec3f{1.f, 2.f, 3.f});
    EXPECT_EQ(broadcast.z[K - 1], 3.f);
}

// ---- the K-wide watertight test, lane by lane ------------------------------------------------

template <typename T>
class PacketTriangle : public ::testing::Test {};
TYPED_TEST_SUITE(PacketTriangle, Widths);

/// K random rays, some axis-parallel, some with tied |components|; with `one_permutation`
/// all go along +z or all along -z, so they share the watertight test's axis permutation.
template <int K>
void random_rays(std::mt19937& rng, Ray (&rays)[K], bool one_permutation) {
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const float z_sign = rng() % 2 ? 1.f : -1.f;
    for (int i = 0; i < K; ++i) {
        Vec3f d{u(rng), u(rng), u(rng)};
        switch (rng() % 6) {
            case 0:
                d[int(rng() % 3)] = rng() % 2 ? 0.f : -0.f;
                break;  // axis-parallel planes
            case 1:
                d.y = d.x;
                break;  // |x| == |y|: tie rule
            case 2:
                d.z = -d.y;
                break;
            default:
                break;
        }
        if (one_permutation) d = Vec3f{0.1f * d.x, 0.1f * d.y, z_sign};
        rays[i] = Ray{{u(rng) * 0.3f, u(rng) * 0.3f, u(rng) * 0.3f + 2.f * (d.z < 0.f)},
                      d,
                      rng() % 4 ? 0.f : 0.5f,
                      rng() % 4 ? pos_inf : 2.5f};
    }
}

template <int K>
WatertightPacket<K> to_packet(const Ray (&rays)[K], uint32_t active) {
    Vec3v<K> org(Vec3f{0.f}), dir(Vec3f{0.f});
    vfloat<K> tmin(0.f), tmax(0.f);
    for (int i = 0; i < K; ++i) {
        for (int a = 0; a < 3; ++a) {
            org[a].set(i, rays[i].org[a]);
            dir[a].set(i, rays[i].dir[a]);
        }
        tmin.set(i, rays[i].tmin);
        tmax.set(i, rays[i].tmax);
    }
    return WatertightPacket<K>(org, dir, tmin, tmax, vbool<K>::from_bits(active));
}

TYPED_TEST(PacketTriangle, ConstantsMatchWatertightRay) {
    constexpr int K = TypeParam::value;
    std::mt19937 rng(11);
    int mismatches = 0;
    for (int trial = 0; trial < 500; ++trial) {
        Ray rays[K];
        random_rays<K>(rng, rays, trial % 2);
        const WatertightPacket<K> p = to_packet<K>(rays, all_lanes<K>);
        for (int i = 0; i < K; ++i) {
            const WatertightRay w(rays[i]);
            mismatches += p.kx[i] != w.kx || p.ky[i] != w.ky || p.kz[i] != w.kz;
            mismatches += std::bit_cast<uint32_t>(p.sx[i]) != std::bit_cast<uint32_t>(w.sx);
            mismatches += std::bit_cast<uint32_t>(p.sy[i]) != std::bit_cast<uint32_t>(w.sy);
            mismatches += std::bit_cast<uint32_t>(p.sz[i]) != std::bit_cast<uint32_t>(w.sz);
            if (p.uniform) {
                mismatches += p.ukx != w.kx || p.uky != w.ky || p.ukz != w.kz;
            }
        }
        if (trial % 2) {
            EXPECT_TRUE(p.uniform);  // all lanes along +-z share one permutation
        }
    }
    EXPECT_EQ(mismatches, 0);
}

TYPED_TEST(PacketTriangle, EveryLaneAnswersLikeTheScalarTest) {
    constexpr int K = TypeParam::value;
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    int mismatches = 0, hits = 0, tested = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        Ray rays[K];
        random_rays<K>(rng, rays, trial % 2);
        const uint32_t active = trial % 3 ? all_lanes<K> : (uint32_t(rng()) & all_lanes<K>);
        const WatertightPacket<K> p = to_packet<K>(rays, active);
        TriangleVerts tri{{u(rng), u(rng), 1.f + u(rng)},
                          {u(rng), u(rng), 1.f + u(rng)},
                          {u(rng), u(rng), 1.f + u(rng)}};
        if (trial % 5 == 0) tri.v2 = tri.v1;  // degenerate
        if (trial % 7 == 0) {
            // Aim lane 0 exactly at a vertex, lane 1 at an edge point.
            rays[0].dir = tri.v0 - rays[0].org;
            rays[1 % K].dir = (tri.v1 + tri.v2) * 0.5f - rays[1 % K].org;
        }
        const WatertightPacket<K> q = trial % 7 == 0 ? to_packet<K>(rays, active) : p;
        vfloat<K> t;
        const uint32_t hit =
            movemask(intersect_watertight<K>(q, vbool<K>::from_bits(active), tri, t));
        // The form without the early exit (packet leaves) gives the same lanes and t.
        vfloat<K> t_full;
        const uint32_t hit_full =
            movemask(intersect_watertight<K, false>(q, vbool<K>::from_bits(active), tri, t_full));
        mismatches += hit_full != hit;
        for (int i = 0; i < K; ++i) {
            if ((hit >> i) & 1) mismatches += !same_bits(t[i], t_full[i]);
            if (!((active >> i) & 1)) {
                mismatches += (hit >> i) & 1;
                continue;
            }
            ++tested;
            float ts = 0.f;
            const bool hs = intersect_watertight(WatertightRay(rays[i]), tri, ts);
            hits += hs;
            mismatches += hs != bool((hit >> i) & 1);
            if (hs) mismatches += std::bit_cast<uint32_t>(ts) != std::bit_cast<uint32_t>(t[i]);
        }
    }
    std::printf("PacketTriangle<%d>: %d mismatches over %d ray/triangle tests (%d hits)\n", K,
                mismatches, tested, hits);
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(hits, tested / 20);  // the test exercises hits, not only misses
}

TYPED_TEST(PacketTriangle, ClosestHitUpdateBreaksTiesByIndex) {
    constexpr int K = TypeParam::value;
    PacketHit<K> best;
    const vbool<K> lanes = vbool<K>::from_bits(0x5u);
    best.update(lanes, vfloat<K>(2.f), 7);
    best.update(vbool<K>(true), vfloat<K>(2.f), 9);  // equal t, larger index: lanes 0, 2 keep 7
    best.update(vbool<K>::from_bits(0x1u), vfloat<K>(2.f), 3);  // equal t, smaller index wins
    EXPECT_EQ(uint32_t(best.tri[0]), 3u);
    EXPECT_EQ(uint32_t(best.tri[1]), 9u);
    EXPECT_EQ(uint32_t(best.tri[2]), 7u);
    best.update(vbool<K>(true), vfloat<K>(1.f), 20);
    EXPECT_EQ(uint32_t(best.tri[K - 1]), 20u);
    EXPECT_EQ(best.t[0], 1.f);
}

}  // namespace
}  // namespace rtt
