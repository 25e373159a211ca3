#include "render/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace rtt::render_detail {

namespace {
constexpr auto show_after = std::chrono::seconds(1);
constexpr auto redraw_every = std::chrono::milliseconds(200);
constexpr int bar_width = 40;
}  // namespace

ProgressBar::ProgressBar(uint64_t total, bool enabled, const char* label)
    : total_(total), label_(label), start_(std::chrono::steady_clock::now()) {
    if (!enabled) return;
    if (isatty(STDERR_FILENO))
        thread_ = std::thread([this] { run(); });
    else
        summary_ = true;
}

ProgressBar::~ProgressBar() {
    if (summary_) {
        // Logs get one line per long phase instead of a bar.
        const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start_;
        if (took >= show_after) std::fprintf(stderr, "rtt: %s took %.1f s\n", label_, took.count());
        return;
    }
    if (!thread_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
    if (drawn_) {
        std::fprintf(stderr, "\r%*s\r", bar_width + 64, "");
        std::fflush(stderr);
    }
}

void ProgressBar::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (wake_.wait_for(lock, show_after, [this] { return stop_; })) return;
    while (!stop_) {
        draw(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
        wake_.wait_for(lock, redraw_every, [this] { return stop_; });
    }
}

void ProgressBar::draw(double seconds) {
    if (total_ == 0) {
        std::fprintf(stderr, "\r%s ...  %.1f s", label_, seconds);
        std::fflush(stderr);
        drawn_ = true;
        return;
    }
    const uint64_t done = std::min(done_.load(std::memory_order_relaxed), total_);
    const int filled = int(double(done) / double(total_) * bar_width);
    char bar[bar_width + 1];
    for (int i = 0; i < bar_width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[bar_width] = '\0';
    // Time left at the rate so far; tiles cost about the same on average over a frame.
    const double fraction = double(done) / double(total_);
    char left[32] = "";
    if (fraction > 0.02)
        std::snprintf(left, sizeof left, ", %.1f s left", seconds * (1.0 - fraction) / fraction);
    std::fprintf(stderr, "\r%s [%s] %3d%%  %.1f s%s   ", label_, bar, int(100.0 * fraction),
                 seconds, left);
    std::fflush(stderr);
    drawn_ = true;
}

}  // namespace rtt::render_detail
