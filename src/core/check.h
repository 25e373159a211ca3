// Programmer-invariant checks (not for user input: that is rtt::Error).
// RTT_CHECK is always on and prints both operands; RTT_DCHECK compiles away in Release.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace rtt::detail {
template <typename A, typename B>
[[noreturn]] void check_failed(const char* file, int line, const char* expr, const A& a,
                               const B& b) {
    std::ostringstream os;
    os << file << ":" << line << ": check failed: " << expr << " (" << a << " vs " << b << ")";
    std::fprintf(stderr, "%s\n", os.str().c_str());
    std::abort();
}
}  // namespace rtt::detail

#define RTT_CHECK_OP(a, op, b)                                                                  \
    do {                                                                                        \
        const auto& rtt_a_ = (a);                                                               \
        const auto& rtt_b_ = (b);                                                               \
        if (!(rtt_a_ op rtt_b_)) [[unlikely]]                                                   \
            ::rtt::detail::check_failed(__FILE__, __LINE__, #a " " #op " " #b, rtt_a_, rtt_b_); \
    } while (0)
#define RTT_CHECK(cond) RTT_CHECK_OP(static_cast<bool>(cond), ==, true)
#define RTT_CHECK_EQ(a, b) RTT_CHECK_OP(a, ==, b)
#define RTT_CHECK_LT(a, b) RTT_CHECK_OP(a, <, b)
#define RTT_CHECK_LE(a, b) RTT_CHECK_OP(a, <=, b)

#ifdef NDEBUG
#define RTT_DCHECK(cond) ((void)0)
#define RTT_DCHECK_LT(a, b) ((void)0)
#else
#define RTT_DCHECK(cond) RTT_CHECK(cond)
#define RTT_DCHECK_LT(a, b) RTT_CHECK_LT(a, b)
#endif
