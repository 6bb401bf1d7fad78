// Static splits of [0, n) over std::threads, for the CPU twin (referenceParallelFor) and the host
// side of checks and benchmarks. Each index writes only its own outputs, so results never depend
// on the thread count or on scheduling.
#pragma once
#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace pcl {

// [0, n) in `threads` contiguous slices, one std::thread each.
template <class F>
void parallelForSlices(size_t n, unsigned threads, F f) {
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (size_t i = t * n / threads; i < (t + 1) * n / threads; ++i) f(i);
        });
    for (auto& th : pool) th.join();
}

// One slice per hardware thread however small n is (the host side of the traversal check and
// benchmark).
template <class F>
void parallelForEveryThread(size_t n, F f) {
    parallelForSlices(n, std::max(1u, std::thread::hardware_concurrency()), f);
}

template <class F>
void referenceParallelFor(size_t n, unsigned threads, F f) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = static_cast<unsigned>(std::min<size_t>(threads, std::max<size_t>(n / 256, 1)));
    if (threads <= 1) {
        for (size_t i = 0; i < n; ++i) f(i);
        return;
    }
    parallelForSlices(n, threads, f);
}

}  // namespace pcl
