// Wall-clock timing of stages (stage tables, check reports, per-pass logs).
#pragma once
#include <chrono>

namespace pcl {

using Clock = std::chrono::steady_clock;

// Seconds from `start` to now.
inline double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace pcl
