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
    // GPUs: many small subtrees, one work-item each; CPUs: one subtree per work-item once there are
    // enough of them to keep the cores busy (the sequential partition runs in cache).
    return (type & CL_DEVICE_TYPE_GPU) ? 32 : 8192;
}

namespace {

// The chunk of a level's subtrees one kdtree_count / kdtree_scatter work-item takes: at least
// minChunk photons, at most 1024 chunks per subtree (each scatter work-item sums the counts of
// its subtree's earlier chunks).
struct LevelShape {
    uint64_t chunk = 0, chunks = 0;
};

LevelShape levelShape(uint64_t maxSize, cl_device_type type) {
    const uint64_t minChunk = (type & CL_DEVICE_TYPE_GPU) ? 256 : 2048;
    LevelShape l;
    l.chunk = std::max<uint64_t>(minChunk, (maxSize + 1023) / 1024);
    l.chunks = (maxSize + l.chunk - 1) / l.chunk;
    return l;
}

}  // namespace

size_t kdTreeCountEntries(size_t n, int finishSize, cl_device_type type) {
    size_t entries = 0;
    for (uint64_t first = 0; first < n; first = 2 * first + 1) {
        const uint64_t count = std::min<uint64_t>(first + 1, n - first);
        const uint64_t maxSize = subtreeSize(first, n);
        if (maxSize <= uint64_t(std::max(finishSize, 0))) break;
        entries = std::max<size_t>(entries, size_t(2 * count * levelShape(maxSize, type).chunks));
    }
    return entries;
}

DeviceKdTree buildKdTree(Device& device, const cl::Buffer& photons, size_t n, KdTreeTiming* timing, int finishSize) {
    if (n >= (size_t(1) << 31)) throw InputError("buildKdTree: " + std::to_string(n) + " photons (at most 2^31 - 1)");
    DeviceKdTree tree;
    tree.count = n;
    tree.photons = device.allocate<PclPhoton>(n, CL_MEM_READ_WRITE, "kd-tree: nodes");
    tree.index = device.allocate<uint32_t>(n, CL_MEM_READ_WRITE, "kd-tree: node index");
    if (n == 0) return tree;

    const std::string stage = "kdtree";
    const cl_device_type type = device.info().type;
    if (finishSize < 0) finishSize = kdTreeFinishSize(type);
    auto points = device.kernel<cl::Buffer, cl_uint, cl::Buffer, cl::Buffer, cl::Buffer>(stage, "kdtree_points");
    auto lists = device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer, cl::Buffer,
                               cl::Buffer>(stage, "kdtree_lists");
    // The six lists come first in kdtree_count, kdtree_scatter and kdtree_finish.
    using L = cl::Buffer;
    auto countK = device.kernel<L, L, L, L, L, L, cl::Buffer, cl_uint, cl_uint, cl_uint, cl_uint, cl::Buffer,
                                cl::Buffer, cl::Buffer>(stage, "kdtree_count");
    auto scatter = device.kernel<L, L, L, L, L, L, cl::Buffer, cl_uint, cl_uint, cl_uint, cl_uint, cl::Buffer>(
        stage, "kdtree_scatter");
    auto finish =
        device.kernel<L, L, L, L, L, L, cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer>(stage, "kdtree_finish");
    auto places = device.kernel<cl::Buffer, cl_uint, cl::Buffer>(stage, "kdtree_places");
    auto nodesK = device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl::Buffer>(stage, "kdtree_nodes");

    const cl_mem_flags rw = CL_MEM_READ_WRITE;
    // One buffer per list (16 bytes a photon: none larger than the map's own 24).
    cl::Buffer x0 = device.allocate<cl_uint4>(n, rw, "kd-tree: list x");
    cl::Buffer y0 = device.allocate<cl_uint4>(n, rw, "kd-tree: list y");
    cl::Buffer z0 = device.allocate<cl_uint4>(n, rw, "kd-tree: list z");
    cl::Buffer x1 = device.allocate<cl_uint4>(n, rw, "kd-tree: list x (second)");
    cl::Buffer y1 = device.allocate<cl_uint4>(n, rw, "kd-tree: list y (second)");
    cl::Buffer z1 = device.allocate<cl_uint4>(n, rw, "kd-tree: list z (second)");
    cl::Buffer nodes = device.allocate<cl_uint4>(n, rw, "kd-tree: subtree ranges");
    cl::Buffer axes = device.allocate<uint8_t>(n, rw, "kd-tree: node axes");
    const size_t countEntries = kdTreeCountEntries(n, finishSize, type);
    cl::Buffer counts;
    if (countEntries) counts = device.allocate<uint32_t>(countEntries, rw, "kd-tree: chunk counts");

    std::vector<cl::Event> events;
    const cl::NDRange group = workGroup();
    const cl_uint N = cl_uint(n);
    double sortSeconds = 0.0;
    cl::Buffer keys = device.allocate<uint32_t>(n, rw, "kd-tree: keys");  // the sorts', then each photon's place
    {
        cl::Buffer values = device.allocate<uint32_t>(n, rw, "kd-tree: values");
        SortWorkspace workspace;
        events.push_back(device.launchLocal(stage, points, wholeWorkGroups(n), group, photons, N, x1, keys, values));
        for (cl_uint axis = 0; axis < 3; ++axis) {
            sortPairsOnDevice(device, keys, values, n, 32, 0, &sortSeconds, &workspace);
            events.push_back(device.launchLocal(stage, lists, wholeWorkGroups(n), group, x1, keys, values, N, axis, x0,
                                                y0, z0, nodes));
        }
    }
    for (uint64_t first = 0; first < n; first = 2 * first + 1) {
        const cl_uint count = cl_uint(std::min<uint64_t>(first + 1, n - first));  // nodes on this level
        const uint64_t maxSize = subtreeSize(first, n);  // the leftmost subtree is the level's largest
        if (maxSize <= uint64_t(finishSize)) {
            // CPUs run a work-group on one core, its work-items one after another: one subtree per
            // work-group spreads the subtrees over the cores (and evens out their sizes).
            const size_t local = (type & CL_DEVICE_TYPE_GPU) ? kWorkGroupSize : 1;
            events.push_back(device.launchLocal(stage, finish, cl::NDRange(count + (local - count % local) % local),
                                                cl::NDRange(local), x0, y0, z0, x1, y1, z1, nodes, cl_uint(first),
                                                count, tree.index, axes));
            break;
        }
        const LevelShape l = levelShape(maxSize, type);
        const size_t items = size_t(count) * l.chunks;
        events.push_back(device.launchLocal(stage, countK, wholeWorkGroups(items), group, x0, y0, z0, x1, y1, z1, nodes,
                                            cl_uint(first), count, cl_uint(l.chunks), cl_uint(l.chunk), counts,
                                            tree.index, axes));
        events.push_back(device.launchLocal(stage, scatter, wholeWorkGroups(items), group, x0, y0, z0, x1, y1, z1,
                                            nodes, cl_uint(first), count, cl_uint(l.chunks), cl_uint(l.chunk), counts));
        ++tree.sortedLevels;
    }
    events.push_back(device.launchLocal(stage, places, wholeWorkGroups(n), group, tree.index, N, keys));
    events.push_back(
        device.launchLocal(stage, nodesK, wholeWorkGroups(n), group, photons, keys, axes, N, tree.photons));
    device.finish();
    tree.levels = uint32_t(bitLength(n));  // ⌊log2 n⌋ + 1
    if (timing) {
        timing->sortSeconds += sortSeconds;
        for (const cl::Event& e : events) timing->otherSeconds += Device::elapsedSeconds(e);
    }
    return tree;
}

}  // namespace pcl
