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

ProgressBar::ProgressBar(uint64_t total, bool enabled)
    : total_(total), start_(std::chrono::steady_clock::now()) {
    if (enabled && total > 0 && isatty(STDERR_FILENO)) thread_ = std::thread([this] { run(); });
}

ProgressBar::~ProgressBar() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
    if (drawn_) {
        std::fprintf(stderr, "\r%*s\r", bar_width + 32, "");
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
    const uint64_t done = std::min(done_.load(std::memory_order_relaxed), total_);
    const int filled = int(double(done) / double(total_) * bar_width);
    char bar[bar_width + 1];
    for (int i = 0; i < bar_width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[bar_width] = '\0';
    std::fprintf(stderr, "\rrendering [%s] %3d%%  %.1f s", bar,
                 int(100.0 * double(done) / double(total_)), seconds);
    std::fflush(stderr);
    drawn_ = true;
}

}  // namespace rtt::render_detail
