// A progress line on stderr for long phases: a bar with the time left for a render, the
// elapsed time for phases of unknown length (loading a scene, building the kd-tree).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

namespace rtt::render_detail {

/// Draws "rendering [#####.....]  47%  3.1 s, 3.5 s left" (or "building the kd-tree ...  2.0 s"
/// when `total` is 0: work of unknown length) on stderr, from its own thread. Shown only when
/// enabled, stderr is a terminal and the work has run for about a second; the line is cleared
/// when the bar is destroyed. When stderr is not a terminal (a log file), a phase that took a
/// second or more gets one line "rtt: <label> took 2.3 s" instead.
class ProgressBar {
public:
    ProgressBar(uint64_t total, bool enabled, const char* label = "rendering");
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    /// Thread-safe.
    void advance(uint64_t n = 1) { done_.fetch_add(n, std::memory_order_relaxed); }

private:
    void run();
    void draw(double seconds);

    uint64_t total_;
    const char* label_;
    std::atomic<uint64_t> done_{0};
    std::chrono::steady_clock::time_point start_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    bool drawn_ = false;
    bool summary_ = false;  ///< Enabled but stderr is no terminal: one line at the end.
    std::thread thread_;
};

}  // namespace rtt::render_detail
