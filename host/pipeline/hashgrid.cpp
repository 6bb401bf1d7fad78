#include "pipeline/hashgrid.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "pipeline/device_scene.h"
#include "pipeline/sort.h"

namespace pcl {

PclGridParams hashGridParams(const std::vector<PclPhoton>& photons, float maxRadius) {
    if (!(maxRadius > 0.0f) || !std::isfinite(maxRadius))
        throw InternalError("hash grid: the search radius must be positive and finite, got " +
                            std::to_string(maxRadius));
    PclGridParams g{};
    if (!photons.empty()) {
        float lo[3] = {photons[0].x, photons[0].y, photons[0].z};
        for (const PclPhoton& p : photons) {
            lo[0] = std::min(lo[0], p.x);
            lo[1] = std::min(lo[1], p.y);
            lo[2] = std::min(lo[2], p.z);
        }
        g.ox = lo[0], g.oy = lo[1], g.oz = lo[2];
    }
    g.cellSize = 2.0f * maxRadius;
    g.invCellSize = 1.0f / g.cellSize;
    if (photons.size() > (size_t(1) << 31))
        throw InputError("hash grid: " + std::to_string(photons.size()) + " photons exceed the 32-bit table");
    uint32_t table = 1;
    while (table < photons.size()) table <<= 1;
    g.tableSize = table;
    g.photonCount = uint32_t(photons.size());
    return g;
}

HashGridBuild hashGridBuildFor(cl_device_type type) {
    return (type & CL_DEVICE_TYPE_CPU) ? HashGridBuild::Bucketed : HashGridBuild::Sorted;
}

// Chunks of at least 16384 photons, at most 8 per core (balance on a shared machine); buckets of
// 2^12 hashes: a bucket's table entries (32 KiB) and, with a table about the size of the map, its
// few thousand pairs (~20 bytes in, 24 out each) stay in a core's L2 while it is sorted.
HashGridBucketShape hashGridBucketShape(size_t n, uint32_t tableSize, size_t computeUnits) {
    HashGridBucketShape s;
    const size_t minChunk = 16384, maxChunks = 8 * std::max<size_t>(computeUnits, 1);
    s.chunks = std::max<size_t>(1, std::min((n + minChunk - 1) / minChunk, maxChunks));
    s.chunkSize = std::max<size_t>(1, (n + s.chunks - 1) / s.chunks);
    int bits = 0;
    while ((uint64_t(1) << bits) < tableSize) ++bits;
    s.lowBits = std::min(bits, 12);
    s.buckets = size_t(1) << (bits - s.lowBits);
    return s;
}

namespace {

// hashgrid_hashes' unsorted hashes in g.keys, then the counting sort (kernels/hashgrid.cl, "The
// bucketed build") into g.keys, g.order, g.points and the tables.
void buildBucketed(Device& device, const cl::Buffer& photons, DeviceHashGrid& g) {
    const size_t n = g.count;
    const HashGridBucketShape s = hashGridBucketShape(n, g.params.tableSize, device.info().computeUnits);
    const cl_mem_flags rw = CL_MEM_READ_WRITE;
    cl::Buffer counts = device.allocate<uint32_t>(s.buckets * s.chunks, rw, "hash grid: bucket counts");
    cl::Buffer bucketKeys = device.allocate<uint32_t>(n, rw, "hash grid: bucket keys");
    cl::Buffer bucketPoints = device.allocate<cl_float4>(n, rw, "hash grid: bucket points");
    const cl::NDRange one(1);
    auto count =
        device.kernel<cl::Buffer, cl_uint, cl_uint, cl_uint, cl_uint, cl::Buffer>("hashgrid", "hashgrid_bucket_count");
    auto scan = device.kernel<cl::Buffer, cl_uint>("hashgrid", "hashgrid_bucket_scan");
    auto scatter = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl_uint, cl::Buffer, cl::Buffer, cl::Buffer>(
        "hashgrid", "hashgrid_bucket_scatter");
    auto cells = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                               cl::Buffer, cl::Buffer>("hashgrid", "hashgrid_bucket_cells");
    std::vector<cl::Event> sortEvents;
    sortEvents.push_back(device.launchLocal("hashgrid", count, cl::NDRange(s.chunks), one, g.keys, cl_uint(n),
                                            cl_uint(s.chunkSize), cl_uint(s.lowBits), cl_uint(s.buckets), counts));
    sortEvents.push_back(device.launchLocal("hashgrid", scan, one, one, counts, cl_uint(s.buckets * s.chunks)));
    sortEvents.push_back(device.launchLocal("hashgrid", scatter, cl::NDRange(s.chunks), one, g.keys, photons,
                                            cl_uint(n), cl_uint(s.chunkSize), cl_uint(s.lowBits), counts, bucketKeys,
                                            bucketPoints));
    cl::Event c = device.launchLocal("hashgrid", cells, cl::NDRange(s.buckets), one, bucketKeys, bucketPoints,
                                     cl_uint(s.chunks), cl_uint(s.lowBits), counts, g.cellStart, g.cellEnd, g.keys,
                                     g.order, g.points);
    c.wait();
    for (const cl::Event& e : sortEvents) g.sortSeconds += Device::elapsedSeconds(e);
    g.rangeSeconds = Device::elapsedSeconds(c);
}

}  // namespace

DeviceHashGrid buildHashGrid(Device& device, const cl::Buffer& photons, size_t count, const PclGridParams& params,
                             HashGridBuild build) {
    if (params.photonCount != count)
        throw InternalError("buildHashGrid: params.photonCount " + std::to_string(params.photonCount) + " for " +
                            std::to_string(count) + " photons");
    if (params.tableSize == 0 || (params.tableSize & (params.tableSize - 1)) != 0)
        throw InternalError("buildHashGrid: tableSize " + std::to_string(params.tableSize) + " is not a power of two");
    if (build == HashGridBuild::ForDevice) build = hashGridBuildFor(device.info().type);
    DeviceHashGrid g;
    g.params = params;
    g.count = count;
    const cl_mem_flags rw = CL_MEM_READ_WRITE;
    g.keys = device.allocate<uint32_t>(count, rw, "hash grid: keys");
    g.order = device.allocate<uint32_t>(count, rw, "hash grid: order");
    g.cellStart = device.allocate<uint32_t>(params.tableSize, rw, "hash grid: cell starts");
    g.cellEnd = device.allocate<uint32_t>(params.tableSize, rw, "hash grid: cell ends");
    g.points = device.allocate<cl_float4>(count, rw, "hash grid: points");
    if (count == 0 || build == HashGridBuild::Sorted) {  // the bucketed build writes every table entry
        device.fill(g.cellStart, uint32_t(0), params.tableSize);
        device.fill(g.cellEnd, uint32_t(0), params.tableSize);
    }
    if (count == 0) {
        device.finish();
        return g;
    }
    const cl::NDRange local(kPhotonGroup);
    if (build == HashGridBuild::Bucketed) {
        auto hashes = device.kernel<PclGridParams, cl::Buffer, cl::Buffer>("hashgrid", "hashgrid_hashes");
        cl::Event e = device.launchLocal("hashgrid", hashes, photonGlobalRange(count), local, params, photons, g.keys);
        e.wait();
        g.keySeconds = Device::elapsedSeconds(e);
        buildBucketed(device, photons, g);
        return g;
    }
    auto keys = device.kernel<PclGridParams, cl::Buffer, cl::Buffer, cl::Buffer>("hashgrid", "hashgrid_keys");
    cl::Event e =
        device.launchLocal("hashgrid", keys, photonGlobalRange(count), local, params, photons, g.keys, g.order);
    e.wait();
    g.keySeconds = Device::elapsedSeconds(e);
    // Stable radix sort of (hash, index): hashes are below tableSize, so only log2(tableSize)
    // bits need sorting (a 2^20 table: 5 passes of 4 bits, not 8).
    int bits = 1;
    while ((uint64_t(1) << bits) < params.tableSize) ++bits;
    sortPairsOnDevice(device, g.keys, g.order, count, 32, bits, &g.sortSeconds);

    auto cells = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "hashgrid", "hashgrid_cells");
    cl::Event c = device.launchLocal("hashgrid", cells, photonGlobalRange(count), local, g.keys, g.order,
                                     cl_uint(count), photons, g.cellStart, g.cellEnd, g.points);
    c.wait();
    g.rangeSeconds = Device::elapsedSeconds(c);
    return g;
}

}  // namespace pcl
