// Progress on stderr for long work: percent, elapsed, ETA, one line rewritten in place when
// stderr is a terminal, a line every few seconds otherwise (logs stay readable).
#pragma once
#include <chrono>
#include <mutex>
#include <string>

namespace pcl {

class Progress {
public:
    explicit Progress(std::string label, bool enabled = true);
    ~Progress();
    // fraction in [0,1]; thread-safe, cheap to call often (printing is throttled).
    void update(double fraction);
    void finish();
    double elapsedSeconds() const;

private:
    void print(double fraction, bool final);
    std::string label_;
    bool enabled_, tty_, finished_ = false;
    std::chrono::steady_clock::time_point start_, lastPrint_;
    std::mutex mutex_;
};

std::string formatSeconds(double seconds);

}  // namespace pcl
