#include "device/probe.h"

#include "shared/struct_list.h"

namespace pcl {

const std::vector<SharedStruct>& sharedStructs() {
#define PCL_HOST_SIZE(T) SharedStruct{#T, sizeof(T)},
    static const std::vector<SharedStruct> structs = {PCL_SHARED_STRUCTS(PCL_HOST_SIZE)};
#undef PCL_HOST_SIZE
    return structs;
}

std::vector<uint32_t> probeDeviceSizes(Device& device) {
    const size_t n = sharedStructs().size();
    auto probe = device.kernel<cl::Buffer>("probe", "probe_sizes");
    cl::Buffer sizes = device.allocate<uint32_t>(n);
    device.fill<uint32_t>(sizes, 0u, n);
    device.launch("probe", probe, cl::NDRange(1), sizes);
    return device.download<uint32_t>(sizes, n);
}

std::vector<std::array<uint32_t, 4>> probeDevicePhilox(Device& device, const std::vector<PhiloxInput>& in) {
    std::vector<uint32_t> ctr, key;
    for (const PhiloxInput& p : in) {
        ctr.insert(ctr.end(), p.ctr.begin(), p.ctr.end());
        key.insert(key.end(), p.key.begin(), p.key.end());
    }
    auto philox = device.kernel<cl::Buffer, cl::Buffer, cl::Buffer>("probe", "probe_philox");
    cl::Buffer ctrBuf = device.upload(ctr), keyBuf = device.upload(key);
    cl::Buffer outBuf = device.allocate<uint32_t>(4 * in.size());
    device.launch("probe", philox, cl::NDRange(in.size()), ctrBuf, keyBuf, outBuf);
    std::vector<uint32_t> flat = device.download<uint32_t>(outBuf, 4 * in.size());
    std::vector<std::array<uint32_t, 4>> out(in.size());
    for (size_t i = 0; i < in.size(); ++i)
        for (int j = 0; j < 4; ++j) out[i][j] = flat[4 * i + j];
    return out;
}

std::vector<uint32_t> probeDeviceRngStream(Device& device, uint64_t seed, uint32_t path, uint32_t bounce,
                                           uint32_t stream, size_t count) {
    auto k = device.kernel<cl_ulong, cl_uint, cl_uint, cl_uint, cl::Buffer>("probe", "probe_rng_stream");
    cl::Buffer out = device.allocate<uint32_t>(count);
    device.launch("probe", k, cl::NDRange(count), cl_ulong(seed), cl_uint(path), cl_uint(bounce), cl_uint(stream), out);
    return device.download<uint32_t>(out, count);
}

}  // namespace pcl
