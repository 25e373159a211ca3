// The float steps and order keys the kd-tree build relies on (src/core/float_step.h).
#include "core/float_step.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace rtt {
namespace {

std::vector<float> sample_floats() {
    constexpr float inf = std::numeric_limits<float>::infinity();
    std::vector<float> xs = {0.f,
                             -0.f,
                             std::numeric_limits<float>::denorm_min(),
                             -std::numeric_limits<float>::denorm_min(),
                             std::numeric_limits<float>::min(),
                             -std::numeric_limits<float>::min(),
                             1.f,
                             -1.f,
                             std::nextafter(std::numeric_limits<float>::max(), 0.f),
                             -std::nextafter(std::numeric_limits<float>::max(), 0.f),
                             std::nextafter(0.f, inf),
                             1e-30f,
                             -3e-8f};
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> exponent(-40.f, 38.f), sign(-1.f, 1.f);
    for (int i = 0; i < 20000; ++i)
        xs.push_back(std::copysign(std::pow(10.f, exponent(rng)), sign(rng)));
    return xs;
}

TEST(FloatStep, NeighboursAreNextafters) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    for (float x : sample_floats()) {
        if (!std::isfinite(x)) continue;
        // -0 and +0 are one value: the float below either is -denorm_min.
        const float down = std::nextafter(x == 0.f ? 0.f : x, -inf);
        const float up = std::nextafter(x == 0.f ? -0.f : x, inf);
        EXPECT_EQ(next_float_down(x), down) << x;
        EXPECT_EQ(next_float_up(x), up) << x;
    }
}

TEST(FloatStep, OrderKeysFollowTheFloatsAndComeBack) {
    std::vector<float> xs = sample_floats();
    for (float x : xs) {
        const uint32_t key = float_order_key(x);
        EXPECT_EQ(float_from_order_key(key), x + 0.f) << x;
        // The next key is the next float (or -0 after -denorm_min: equal to 0 as a float).
        EXPECT_EQ(float_from_order_key(key + 1), next_float_up(x)) << x;
    }
    std::mt19937 rng(6);
    std::uniform_int_distribution<size_t> pick(0, xs.size() - 1);
    for (int i = 0; i < 20000; ++i) {
        const float a = xs[pick(rng)], b = xs[pick(rng)];
        EXPECT_EQ(a < b, float_order_key(a) < float_order_key(b)) << a << " " << b;
    }
}

}  // namespace
}  // namespace rtt
