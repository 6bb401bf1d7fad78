#include "pipeline/deposit.h"

#include <algorithm>
#include <string>

#include "core/error.h"
#include "pipeline/device_scene.h"

namespace pcl {
namespace {

constexpr size_t kScanGroup = 256;  // PCL_SCAN_GROUP in kernels/deposit.cl

}  // namespace

DevicePhotonMap makeDevicePhotonMap(Device& device, size_t capacity, const std::string& name) {
    DevicePhotonMap map;
    map.name = name;
    map.capacity = std::max<size_t>(capacity, 1);
    map.photons = device.allocate<PclPhoton>(map.capacity, CL_MEM_READ_WRITE, name);
    return map;
}

uint64_t exclusiveScan(Device& device, const cl::Buffer& values, cl::Buffer& exclusive, size_t n, double* seconds) {
    auto scan = device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl_uint>("deposit", "deposit_scan");
    auto add = device.kernel<cl::Buffer, cl::Buffer, cl_uint>("deposit", "deposit_scan_add");
    const size_t groups = (n + kScanGroup - 1) / kScanGroup;
    cl::Buffer sums = device.allocate<uint32_t>(groups, CL_MEM_READ_WRITE, "deposit: group sums");
    std::vector<cl::Event> events;
    events.push_back(device.launchLocal("deposit", scan, cl::NDRange(groups * kScanGroup), cl::NDRange(kScanGroup),
                                        values, exclusive, sums, cl_uint(n)));
    uint64_t total = 0;
    if (groups > 1) {
        cl::Buffer groupOffsets = device.allocate<uint32_t>(groups, CL_MEM_READ_WRITE, "deposit: group offsets");
        total = exclusiveScan(device, sums, groupOffsets, groups, seconds);
        events.push_back(device.launchLocal("deposit", add, photonGlobalRange(n), cl::NDRange(kPhotonGroup), exclusive,
                                            groupOffsets, cl_uint(n)));
        device.finish();
    } else {
        total = device.download<uint32_t>(sums, 1)[0];
    }
    if (seconds)
        for (const cl::Event& e : events) *seconds += Device::elapsedSeconds(e);
    return total;
}

namespace {

std::vector<PclPhoton> transposeSlots(const std::vector<PclPhoton>& in, size_t rows, size_t cols) {
    if (in.size() != rows * cols)
        throw InternalError("photon slots: " + std::to_string(in.size()) + " records, expected " +
                            std::to_string(rows) + " x " + std::to_string(cols));
    std::vector<PclPhoton> out(in.size());
    for (size_t r = 0; r < rows; ++r)
        for (size_t c = 0; c < cols; ++c) out[c * rows + r] = in[r * cols + c];
    return out;
}

}  // namespace

std::vector<PclPhoton> slotMajor(const std::vector<PclPhoton>& pathMajor, size_t paths, uint32_t slotsPerPath) {
    return transposeSlots(pathMajor, paths, slotsPerPath);
}

std::vector<PclPhoton> pathMajor(const std::vector<PclPhoton>& slotMajor, size_t paths, uint32_t slotsPerPath) {
    return transposeSlots(slotMajor, slotsPerPath, paths);
}

size_t depositPhotons(Device& device, const cl::Buffer& counts, const cl::Buffer& slots, uint32_t paths,
                      DevicePhotonMap& map, DepositTiming* timing) {
    if (paths == 0) return 0;
    DepositTiming local;
    DepositTiming& t = timing ? *timing : local;
    cl::Buffer offsets = device.allocate<uint32_t>(paths, CL_MEM_READ_WRITE, "deposit: offsets");
    const uint64_t total = exclusiveScan(device, counts, offsets, paths, &t.scanSeconds);
    if (total == 0) return 0;
    const uint64_t needed = map.count + total;
    if (needed > 0xFFFFFFFFull)
        throw DeviceError("stage deposit: a photon map of " + std::to_string(needed) +
                          " records exceeds the 32-bit offsets of deposit_scatter");
    if (needed > map.capacity) {
        // Grow, never truncate: a larger buffer, the old records copied over, the event counted.
        // Never past one max allocation (the memory plan checked the paths emitted fit; more
        // records than that can only be found here).
        const size_t limit = maxMapRecords(device.info().maxAlloc);
        if (needed > limit)
            throw InputError(map.name + " needs " + std::to_string(needed) + " records (" +
                             formatMiB(needed * sizeof(PclPhoton)) +
                             ") after this batch, above the device's max "
                             "allocation " +
                             describeMaxAlloc(device.info()) + ", which holds " + std::to_string(limit) +
                             " records; emit fewer photons or raise --max-buffer-mib");
        size_t capacity = std::min(std::max<size_t>(needed, map.capacity * 2), limit);
        cl::Buffer grown = device.allocate<PclPhoton>(capacity, CL_MEM_READ_WRITE, map.name);
        if (map.count) {
            cl::Event e;
            Device::guard("deposit", [&] {
                device.queue().enqueueCopyBuffer(map.photons, grown, 0, 0, map.count * sizeof(PclPhoton), nullptr, &e);
            });
            e.wait();
            t.growSeconds += Device::elapsedSeconds(e);
        }
        map.photons = grown;
        map.capacity = capacity;
        ++map.growths;
    }
    auto scatter =
        device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl::Buffer, cl_uint>("deposit", "deposit_scatter");
    cl::Event e = device.launchLocal("deposit", scatter, photonGlobalRange(paths), cl::NDRange(kPhotonGroup), counts,
                                     offsets, slots, cl_uint(paths), map.photons, cl_uint(map.count));
    e.wait();
    t.scatterSeconds += Device::elapsedSeconds(e);
    map.count += total;
    return size_t(total);
}

}  // namespace pcl
