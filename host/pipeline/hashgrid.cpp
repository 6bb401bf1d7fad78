#include "pipeline/hashgrid.h"

#include <algorithm>
#include <cmath>
#include <string>

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

DeviceHashGrid buildHashGrid(Device& device, const cl::Buffer& photons, size_t count, const PclGridParams& params) {
    if (params.photonCount != count)
        throw InternalError("buildHashGrid: params.photonCount " + std::to_string(params.photonCount) + " for " +
                            std::to_string(count) + " photons");
    if (params.tableSize == 0 || (params.tableSize & (params.tableSize - 1)) != 0)
        throw InternalError("buildHashGrid: tableSize " + std::to_string(params.tableSize) + " is not a power of two");
    DeviceHashGrid g;
    g.params = params;
    g.count = count;
    const cl_mem_flags rw = CL_MEM_READ_WRITE;
    g.keys = device.allocate<uint32_t>(count, rw, "hash grid: keys");
    g.order = device.allocate<uint32_t>(count, rw, "hash grid: order");
    g.cellStart = device.allocate<uint32_t>(params.tableSize, rw, "hash grid: cell starts");
    g.cellEnd = device.allocate<uint32_t>(params.tableSize, rw, "hash grid: cell ends");
    g.points = device.allocate<cl_float4>(count, rw, "hash grid: points");
    device.fill(g.cellStart, uint32_t(0), params.tableSize);
    device.fill(g.cellEnd, uint32_t(0), params.tableSize);
    if (count == 0) {
        device.finish();
        return g;
    }
    const cl::NDRange local(kPhotonGroup);
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
