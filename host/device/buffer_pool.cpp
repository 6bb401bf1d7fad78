#include "device/buffer_pool.h"

#include <algorithm>

namespace pcl {

bool BufferPool::idle(const Entry& e) { return e.buffer.getInfo<CL_MEM_REFERENCE_COUNT>() == 1; }

size_t BufferPool::sizeClass(size_t bytes, size_t limit) {
    if (bytes < kMinBytes) return bytes;
    size_t top = 1;
    while (top <= bytes / 2) top <<= 1;  // the leading power of two
    const size_t step = std::max<size_t>(top / 8, 1);
    const size_t rounded = (bytes + step - 1) / step * step;
    return std::max(bytes, std::min(rounded, limit));
}

cl::Buffer BufferPool::take(size_t bytes, cl_mem_flags flags) {
    if (bytes < kMinBytes) return cl::Buffer();
    std::lock_guard<std::mutex> lock(mutex_);
    Entry* best = nullptr;
    for (Entry& e : entries_)
        if (e.flags == flags && e.bytes >= bytes && e.bytes - bytes <= bytes / 8 && (!best || e.bytes < best->bytes) &&
            idle(e))
            best = &e;
    if (!best) return cl::Buffer();
    best->lastUse = ++clock_;
    return best->buffer;
}

void BufferPool::keep(const cl::Buffer& buffer, size_t bytes, cl_mem_flags flags) {
    if (bytes < kMinBytes) return;
    std::lock_guard<std::mutex> lock(mutex_);
    entries_.push_back({buffer, bytes, flags, ++clock_});
    trim();
}

void BufferPool::trim() {
    for (;;) {
        size_t idleTotal = 0;
        Entry* oldest = nullptr;
        for (Entry& e : entries_)
            if (idle(e)) {
                idleTotal += e.bytes;
                if (!oldest || e.lastUse < oldest->lastUse) oldest = &e;
            }
        if (idleTotal <= idleCap_ || !oldest) return;
        entries_.erase(entries_.begin() + (oldest - entries_.data()));
    }
}

}  // namespace pcl
