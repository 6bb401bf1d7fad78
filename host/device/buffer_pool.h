// Buffers kept for reuse: a render allocates the same large buffers every pass and chunk (the
// gather's 4 M queries and hits, kNN outputs, kd-tree scratch), and a fresh buffer costs the
// host its page faults and zeroing (17 % of a PoCL fg pass, perf). Device::allocateBytes asks
// the pool first: a pooled buffer with the same flags, at least the bytes asked and at most
// 1/8 more, that nobody else holds (reference count 1: the pool's own) is handed out again.
// One in-order queue per Device makes that safe: a command still reading the old contents runs
// before any command the new holder enqueues. Contents are not cleared (OpenCL promises no
// initial contents either). Idle buffers above the byte cap are released, oldest first.
#pragma once
#include <CL/opencl.hpp>

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

namespace pcl {

class BufferPool {
public:
    explicit BufferPool(size_t idleCap) : idleCap_(idleCap) {}

    // A pooled buffer for `bytes` with `flags`, or an empty cl::Buffer when none is free.
    cl::Buffer take(size_t bytes, cl_mem_flags flags);
    // Keeps a buffer made for `bytes` (it may be larger: the size class) for later takes.
    void keep(const cl::Buffer& buffer, size_t bytes, cl_mem_flags flags);

    // The size a pooled buffer for `bytes` is made with: rounded up to 1/8 of its leading power
    // of two (so the next pass's slightly larger map still fits), never above `limit`.
    static size_t sizeClass(size_t bytes, size_t limit);
    // Buffers below this are not pooled: their allocation is cheap.
    static constexpr size_t kMinBytes = size_t(1) << 20;

private:
    struct Entry {
        cl::Buffer buffer;
        size_t bytes = 0;
        cl_mem_flags flags = 0;
        uint64_t lastUse = 0;
    };
    static bool idle(const Entry& e);
    void trim();

    std::mutex mutex_;
    std::vector<Entry> entries_;
    size_t idleCap_;
    uint64_t clock_ = 0;
};

}  // namespace pcl
