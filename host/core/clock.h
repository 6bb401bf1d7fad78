// Wall-clock timing of stages (stage tables, check reports, per-pass logs).
#pragma once
#include <chrono>

namespace pcl {

using Clock = std::chrono::steady_clock;

// Seconds from `start` to now.
inline double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace pcl

// `--time T`: whether to start another pass after `done` passes that took `passSeconds` in all,
// `elapsed` seconds into a budget of `budget`. Another pass starts only when its expected end
// (the mean pass so far) lies nearer the budget than stopping now does, so a render ends within
// half a pass of T, before or after it, not up to a whole pass past it: at equal time a method
// with long passes is not given more time than one with short ones.
inline bool anotherPassFits(double elapsed, double budget, unsigned done, double passSeconds) {
    if (done == 0) return true;  // at least one pass, whatever the budget
    return elapsed + 0.5 * (passSeconds / done) <= budget;
}
