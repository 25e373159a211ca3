// What the tests know about the build they run in.
#pragma once

namespace rtt::test_env {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool under_asan = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool under_asan = true;
#else
inline constexpr bool under_asan = false;
#endif
#else
inline constexpr bool under_asan = false;
#endif

/// Factor on wall-clock limits: AddressSanitizer builds (-O1, instrumented) run about 5 times
/// slower than Release.
inline constexpr double time_slack = under_asan ? 5.0 : 1.0;

}  // namespace rtt::test_env
