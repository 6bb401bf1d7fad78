#include "core/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace pcl {

std::string formatSeconds(double s) {
    char buf[32];
    if (!std::isfinite(s) || s < 0) return "?";
    if (s < 60) std::snprintf(buf, sizeof buf, "%.1fs", s);
    else if (s < 3600) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
    else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, (int(s) / 60) % 60);
    return buf;
}

Progress::Progress(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()), lastPrint_(start_) {}

Progress::~Progress() { finish(); }

double Progress::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::update(double fraction) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) return;
    auto now = std::chrono::steady_clock::now();
    double sinceLast = std::chrono::duration<double>(now - lastPrint_).count();
    if (sinceLast < (tty_ ? 0.2 : 5.0)) return;
    lastPrint_ = now;
    print(fraction, false);
}

void Progress::finish() {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) return;
    finished_ = true;
    print(1.0, true);
}

void Progress::print(double fraction, bool final) {
    double elapsed = elapsedSeconds();
    double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : NAN;
    if (final)
        std::fprintf(stderr, "%s%s: 100%% in %s\n", tty_ ? "\r" : "", label_.c_str(), formatSeconds(elapsed).c_str());
    else
        std::fprintf(stderr, "%s%s: %5.1f%%  elapsed %s  ETA %s%s", tty_ ? "\r" : "", label_.c_str(), 100.0 * fraction,
                     formatSeconds(elapsed).c_str(), formatSeconds(eta).c_str(), tty_ ? "   " : "\n");
    std::fflush(stderr);
}

}  // namespace pcl
