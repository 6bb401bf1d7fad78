// device/buffer_pool: a large buffer released by its holder is handed out again for a request
// of the same flags and a size within 1/8 below it; one still held, one of other flags, one far
// larger and small buffers are never shared; size classes round up by at most 1/8.
#include <gtest/gtest.h>

#include <cstdlib>

#include "device/buffer_pool.h"
#include "device_fixture.h"

namespace pcl {
namespace {

TEST(BufferPool, ReusesOnlyFreeBuffersOfTheSameFlagsAndSize) {
    Device device = Device::open(std::getenv("PHOTONCL_TEST_DEVICE") ? std::getenv("PHOTONCL_TEST_DEVICE") : "auto");
    // (its own pool: no other test's buffers in it)
    const size_t mib = size_t(1) << 20;
    cl_mem first = nullptr, second = nullptr;
    {
        cl::Buffer a = device.allocateBytes(3 * mib + 5, CL_MEM_READ_WRITE, "test: a");
        first = a();
        cl::Buffer held = device.allocateBytes(3 * mib + 5, CL_MEM_READ_WRITE, "test: held while a lives");
        EXPECT_NE(held(), first);  // a is still held: never shared
        second = held();
    }
    cl::Buffer again = device.allocateBytes(3 * mib, CL_MEM_READ_WRITE, "test: again");
    EXPECT_EQ(again(), first);  // both are free now: the first kept of the smallest fitting size
    cl::Buffer smaller = device.allocateBytes(2 * mib, CL_MEM_READ_WRITE, "test: much smaller");
    EXPECT_NE(smaller(), second);  // 3.25 MiB for 2 MiB is more than 1/8 over: not shared
    const size_t given = again.getInfo<CL_MEM_SIZE>();
    EXPECT_GE(given, 3 * mib);
    EXPECT_LE(given, 3 * mib + 3 * mib / 8);
    cl::Buffer other = device.allocateBytes(3 * mib, CL_MEM_READ_ONLY, "test: other flags");
    EXPECT_NE(other(), again());
    cl::Buffer small1 = device.allocateBytes(1000, CL_MEM_READ_WRITE, "test: small");
    cl_mem smallHandle = small1();
    small1 = cl::Buffer();
    cl::Buffer small2 = device.allocateBytes(1000, CL_MEM_READ_WRITE, "test: small again");
    EXPECT_EQ(small2.getInfo<CL_MEM_SIZE>(), 1000u);  // not pooled: exactly its size
    (void)smallHandle;

    EXPECT_EQ(BufferPool::sizeClass(1000, 1 << 30), 1000u);
    EXPECT_EQ(BufferPool::sizeClass(mib, 1 << 30), mib);
    EXPECT_EQ(BufferPool::sizeClass(mib + 1, 1 << 30), mib + mib / 8);
    EXPECT_EQ(BufferPool::sizeClass(3 * mib, 1 << 30), 3 * mib);
    EXPECT_EQ(BufferPool::sizeClass(mib + 1, mib + 10), mib + 10);  // never above the limit
    for (size_t b = mib; b < 64 * mib; b = b * 5 / 4 + 12345) {
        const size_t c = BufferPool::sizeClass(b, size_t(1) << 40);
        EXPECT_GE(c, b);
        EXPECT_LE(c - b, b / 8);
    }
}

}  // namespace
}  // namespace pcl
