#include "pipeline/kdtree.h"

#include <algorithm>
#include <string>

#include "core/error.h"
#include "device/work_group.h"
#include "pipeline/sort.h"

namespace pcl {
namespace {

// Photons in the subtree of heap node h of a complete tree of n nodes.
uint64_t subtreeSize(uint64_t h, uint64_t n) {
    uint64_t count = 0;
    for (uint64_t first = h, width = 1; first < n; first = 2 * first + 1, width *= 2)
        count += std::min(width, n - first);
    return count;
}

int bitLength(uint64_t v) {
    int b = 0;
    while (v) {
        ++b;
        v >>= 1;
    }
    return b;
}

}  // namespace

int kdTreeFinishSize(cl_device_type type) {
    // GPUs: small private arrays (they spill to memory); CPUs: longer finished subtrees.
    return (type & CL_DEVICE_TYPE_GPU) ? 32 : 128;
}

bool kdTreeUses64BitKeys(size_t n, int finishSize) {
    const int rankBits = bitLength(n ? n - 1 : 0);
    for (uint64_t first = 0; first < n; first = 2 * first + 1) {
        const uint64_t count = std::min<uint64_t>(first + 1, n - first);
        if (rankBits + bitLength(count) > 32) return true;
        if (subtreeSize(first, n) <= uint64_t(finishSize)) break;
    }
    return false;
}

DeviceKdTree buildKdTree(Device& device, const cl::Buffer& photons, size_t n, KdTreeTiming* timing, int finishSize) {
    if (n >= (size_t(1) << 31)) throw InputError("buildKdTree: " + std::to_string(n) + " photons (at most 2^31 - 1)");
    DeviceKdTree tree;
    tree.count = n;
    tree.photons = device.allocate<PclPhoton>(n, CL_MEM_READ_WRITE, "kd-tree: nodes");
    tree.index = device.allocate<uint32_t>(n, CL_MEM_READ_WRITE, "kd-tree: node index");
    if (n == 0) return tree;

    const std::string stage = "kdtree";
    if (finishSize < 0) finishSize = kdTreeFinishSize(device.info().type);
    const std::string opts = "-DPCL_KD_FINISH=" + std::to_string(std::max(finishSize, 1)) + "u";
    auto init = device.kernel<cl_uint, cl::Buffer>(stage, "kdtree_init", opts);
    auto boundsInit = device.kernel<cl::Buffer, cl_uint, cl_uint>(stage, "kdtree_bounds_init", opts);
    auto bounds = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl::Buffer>(stage, "kdtree_bounds", opts);
    auto rankKeys =
        device.kernel<cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer>(stage, "kdtree_rank_keys", opts);
    auto rankScatter = device.kernel<cl::Buffer, cl_uint, cl_uint, cl::Buffer>(stage, "kdtree_rank_scatter", opts);
    // Per key width (0: 32-bit keys, 1: 64-bit): keys, segments, assign.
    using KeysKernel = cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_uint, cl::Buffer, cl_uint, cl_uint, cl_uint,
                                         cl::Buffer, cl::Buffer>;
    using SegmentsKernel = cl::KernelFunctor<cl::Buffer, cl_uint, cl_uint, cl_uint, cl::Buffer, cl::Buffer>;
    using AssignKernel = cl::KernelFunctor<cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl_uint, cl_uint,
                                           cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>;
    std::vector<KeysKernel> keysK;
    std::vector<SegmentsKernel> segments;
    std::vector<AssignKernel> assign;
    for (const char* width : {" -DPCL_KD_KEY64=0", " -DPCL_KD_KEY64=1"}) {
        const std::string o = opts + width;
        keysK.push_back(device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl::Buffer, cl_uint, cl_uint, cl_uint,
                                      cl::Buffer, cl::Buffer>(stage, "kdtree_keys", o));
        segments.push_back(
            device.kernel<cl::Buffer, cl_uint, cl_uint, cl_uint, cl::Buffer, cl::Buffer>(stage, "kdtree_segments", o));
        assign.push_back(
            device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl_uint, cl_uint, cl::Buffer,
                          cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(stage, "kdtree_assign", o));
    }
    auto finish =
        device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer>(
            stage, "kdtree_finish", opts);

    const cl_mem_flags rw = CL_MEM_READ_WRITE;
    cl::Buffer sub = device.allocate<uint32_t>(n, rw, "kd-tree: subtrees");
    cl::Buffer keys = device.allocate<uint64_t>(n, rw, "kd-tree: keys");  // 32- or 64-bit keys, per level
    cl::Buffer values = device.allocate<uint32_t>(n, rw, "kd-tree: values");
    cl::Buffer ranks = device.allocate<uint32_t>(3 * n, rw, "kd-tree: ranks");
    cl::Buffer boxes = device.allocate<uint32_t>(6 * n, rw, "kd-tree: boxes");
    cl::Buffer segStart = device.allocate<uint32_t>(n, rw, "kd-tree: segment starts");
    cl::Buffer segEnd = device.allocate<uint32_t>(n, rw, "kd-tree: segment ends");
    SortWorkspace workspace[2];

    std::vector<cl::Event> events;
    const cl::NDRange group = workGroup();
    const cl_uint N = cl_uint(n);
    events.push_back(device.launchLocal(stage, init, wholeWorkGroups(n), group, N, sub));
    events.push_back(device.launchLocal(stage, boundsInit, wholeWorkGroups(1), group, boxes, cl_uint(0), cl_uint(1)));
    events.push_back(device.launchLocal(stage, bounds, wholeWorkGroups(n), group, photons, sub, N, boxes));

    double sortSeconds = 0.0;
    const int rankBits = bitLength(n - 1);
    for (cl_uint axis = 0; axis < 3; ++axis) {  // (n = 1 too: its one rank, 0, must be written)
        events.push_back(
            device.launchLocal(stage, rankKeys, wholeWorkGroups(n), group, photons, N, axis, keys, values));
        sortPairsOnDevice(device, keys, values, n, 32, 0, &sortSeconds, &workspace[0]);
        events.push_back(device.launchLocal(stage, rankScatter, wholeWorkGroups(n), group, values, N, axis, ranks));
    }
    for (uint64_t first = 0; first < n; first = 2 * first + 1) {
        const uint64_t count = std::min<uint64_t>(first + 1, n - first);  // nodes on this level
        const int keyBits = rankBits + bitLength(count);
        const int w = keyBits > 32 ? 1 : 0;
        events.push_back(device.launchLocal(stage, keysK[w], wholeWorkGroups(n), group, ranks, sub, N, boxes,
                                            cl_uint(first), cl_uint(count), cl_uint(rankBits), keys, values));
        sortPairsOnDevice(device, keys, values, n, w ? 64 : 32, keyBits, &sortSeconds, &workspace[w]);
        events.push_back(device.launchLocal(stage, segments[w], wholeWorkGroups(n), group, keys, N, cl_uint(count),
                                            cl_uint(rankBits), segStart, segEnd));
        ++tree.sortedLevels;
        if (subtreeSize(first, n) <= uint64_t(finishSize)) {  // the leftmost subtree is the level's largest
            events.push_back(device.launchLocal(stage, finish, wholeWorkGroups(count), group, photons, values, segStart,
                                                segEnd, cl_uint(first), cl_uint(count), tree.photons, tree.index));
            break;
        }
        events.push_back(device.launchLocal(stage, assign[w], wholeWorkGroups(n), group, photons, keys, values, N,
                                            cl_uint(first), cl_uint(count), cl_uint(rankBits), segStart, segEnd, boxes,
                                            sub, tree.photons, tree.index));
        const uint64_t childFirst = 2 * first + 1;
        if (childFirst >= n) continue;
        const uint64_t childCount = std::min<uint64_t>(2 * count, n - childFirst);
        events.push_back(device.launchLocal(stage, boundsInit, wholeWorkGroups(childCount), group, boxes,
                                            cl_uint(childFirst), cl_uint(childCount)));
        events.push_back(device.launchLocal(stage, bounds, wholeWorkGroups(n), group, photons, sub, N, boxes));
    }
    device.finish();
    tree.levels = uint32_t(bitLength(n));  // ⌊log2 n⌋ + 1
    if (timing) {
        timing->sortSeconds += sortSeconds;
        for (const cl::Event& e : events) timing->otherSeconds += Device::elapsedSeconds(e);
    }
    return tree;
}

}  // namespace pcl
