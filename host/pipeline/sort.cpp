#include "pipeline/sort.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

#include "core/error.h"

namespace pcl {
namespace {

// The pass shape (kernels/sort.cl): radix bits per pass, work-items per tile, keys per work-item,
// and from how many pairs the sort is bucketed (top digit first, then each bucket in cache).
// CPUs (PoCL: one work-item is one scalar lane, a work-group one core's loop): 8-bit digits and
// one work-item per tile of 16384 keys, so the scatter needs no recount and no scan of
// per-work-item counters (kernels/sort.cl, sort_scatter), bucketed from 2^18 pairs. Measured
// with sort_bench on PoCL (2 cores), 1M-10M keys: one work-item per tile ~2x the earlier
// (8, 16, 512) shape; bucketing another ~1.3-2x on 64-bit keys (the low passes stay in cache),
// about even to ~1.4x on 32-bit; 9-11-bit digits, in the plain passes or within buckets, and
// write-combining buffers in the scatter were slower. GPUs: 4-bit digits over 256 work-items
// (16 KiB of counters, fits any GPU's local memory), never bucketed (one work-item per bucket).
struct SortShape {
    int radixBits = 8;
    size_t group = 1, items = 16384;
    size_t bucketedFrom = size_t(1) << 18;  // n from which the top digit goes first (0: never)
};

SortShape sortShape(cl_device_type type) {
    SortShape s;
    if (type & CL_DEVICE_TYPE_GPU) s = SortShape{4, 256, 16, 0};
    if (const char* e = std::getenv("PHOTONCL_SORT_SHAPE")) {  // tests and tuning: "bits,group,items[,bucketedFrom]"
        int b = 0;
        unsigned long g = 0, i = 0, f = 0;
        const int got = std::sscanf(e, "%d,%lu,%lu,%lu", &b, &g, &i, &f);
        if (got >= 3 && b >= 1 && b <= 12 && g >= 1 && i >= 1) {
            s.radixBits = b;
            s.group = g;
            s.items = i;
            s.bucketedFrom = got == 4 ? f : 0;
        }
    }
    return s;
}

std::string options(int keyBits, const SortShape& s) {
    return std::string(keyBits == 64 ? "-DPCL_SORT_KEY64=1 " : "") +
           "-DPCL_SORT_RADIX_BITS=" + std::to_string(s.radixBits) + " -DPCL_SORT_GROUP=" + std::to_string(s.group) +
           " -DPCL_SORT_ITEMS=" + std::to_string(s.items) + (s.bucketedFrom ? " -DPCL_SORT_BUCKETED=1" : "");
}

}  // namespace

size_t sortHistogramEntries(cl_device_type type, size_t n) {
    const SortShape shape = sortShape(type);
    const size_t tile = shape.group * shape.items;
    return ((n + tile - 1) / tile) << shape.radixBits;
}

void sortPairsOnDevice(Device& device, cl::Buffer& keys, cl::Buffer& values, size_t n, int keyBits, int sortBits,
                       double* seconds, SortWorkspace* workspace) {
    if (keyBits != 32 && keyBits != 64)
        throw InternalError("sortPairsOnDevice: keys of " + std::to_string(keyBits) + " bits (32 or 64 expected)");
    if (sortBits == 0) sortBits = keyBits;
    if (sortBits < 1 || sortBits > keyBits)
        throw InternalError("sortPairsOnDevice: " + std::to_string(sortBits) + " bits to sort of " +
                            std::to_string(keyBits) + "-bit keys");
    if (n >= (size_t(1) << 31))
        throw InputError("sortPairsOnDevice: " + std::to_string(n) + " pairs (at most 2^31 - 1)");
    if (n < 2) return;
    const SortShape shape = sortShape(device.info().type);
    const size_t kSortGroup = shape.group, kSortTile = shape.group * shape.items;
    const int kRadixBits = shape.radixBits;
    const size_t keySize = keyBits == 64 ? 8 : 4;
    const size_t tiles = (n + kSortTile - 1) / kSortTile;
    const size_t histSize = tiles << kRadixBits;

    SortWorkspace local;
    SortWorkspace& ws = workspace ? *workspace : local;
    if (ws.capacity < n || ws.keyBits != keyBits) {
        ws.keys = keyBits == 64 ? device.allocate<uint64_t>(n, CL_MEM_READ_WRITE, "sort: scratch keys (64-bit)")
                                : device.allocate<uint32_t>(n, CL_MEM_READ_WRITE, "sort: scratch keys (32-bit)");
        ws.values = device.allocate<uint32_t>(n, CL_MEM_READ_WRITE, "sort: scratch values");
        ws.capacity = n;
        ws.keyBits = keyBits;
    }
    if (ws.histCapacity < histSize) {
        ws.hist = device.allocate<uint32_t>(histSize, CL_MEM_READ_WRITE, "sort: tile histogram");
        ws.histCapacity = histSize;
    }
    const std::string opts = options(keyBits, shape);
    auto histogram = device.kernel<cl::Buffer, cl_uint, cl_uint, cl_uint, cl::Buffer>("sort", "sort_histogram", opts);
    auto scan = device.kernel<cl::Buffer, cl_uint>("sort", "sort_scan", opts);
    auto scatter = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl_uint, cl::Buffer, cl::Buffer, cl::Buffer>(
        "sort", "sort_scatter", opts);

    const cl::NDRange global(tiles * kSortGroup), group(kSortGroup);
    cl::Buffer* kin = &keys;
    cl::Buffer* vin = &values;
    cl::Buffer* kout = &ws.keys;
    cl::Buffer* vout = &ws.values;
    std::vector<cl::Event> events;
    // The fewest passes of at most kRadixBits bits, the bits spread evenly over them, the first
    // passes one bit wider (30 bits in 8-bit digits: 8, 8, 7, 7).
    const int passes = (sortBits + kRadixBits - 1) / kRadixBits;
    auto digitBits = [&](int p) { return sortBits / passes + (p < sortBits % passes ? 1 : 0); };
    auto countAndScan = [&](cl_uint shift, cl_uint mask) {
        events.push_back(device.launchLocal("sort", histogram, global, group, *kin, cl_uint(n), shift, mask, ws.hist));
        events.push_back(device.launchLocal("sort", scan, cl::NDRange(kSortGroup), group, ws.hist, cl_uint(histSize)));
    };
    auto scatterPass = [&](cl_uint shift, cl_uint mask) {
        events.push_back(device.launchLocal("sort", scatter, global, group, *kin, *vin, cl_uint(n), shift, mask,
                                            ws.hist, *kout, *vout));
        std::swap(kin, kout);
        std::swap(vin, vout);
    };
    int lsdFrom = 0;  // the first LSD pass to run (passes when the bucketed sort did it all)
    if (shape.bucketedFrom && n >= shape.bucketedFrom && passes >= 2) {
        // Top digit first, then each bucket sorted alone by the low bits (kernels/sort.cl,
        // sort_buckets): the first pass spreads the pairs over the whole array, the rest stay
        // within a bucket small enough for a core's cache. Only when no bucket holds more than
        // a core's fair share (n / (2 x compute units)) — else (keys whose top digit is nearly
        // constant) one core would sort most of it alone, and the plain LSD passes run instead.
        // Both give the same order. Ends in keys/values.
        const int topBits = digitBits(passes - 1), lowBits = sortBits - topBits;
        const cl_uint topMask = (1u << topBits) - 1u;
        countAndScan(cl_uint(lowBits), topMask);
        std::vector<cl_uint> starts(size_t(topMask) + 1);
        Device::guard("sort", [&] {
            device.queue().enqueueReadBufferRect(ws.hist, CL_TRUE, {0, 0, 0}, {0, 0, 0},
                                                 {sizeof(cl_uint), starts.size(), 1}, tiles * sizeof(cl_uint), 0,
                                                 sizeof(cl_uint), 0, starts.data());
        });
        size_t largest = 0;
        for (size_t d = 0; d < starts.size(); ++d)
            largest = std::max(largest, (d + 1 < starts.size() ? size_t(starts[d + 1]) : n) - starts[d]);
        if (largest * 2 * std::max<size_t>(device.info().computeUnits, 1) <= n) {
            scatterPass(cl_uint(lowBits), topMask);
            auto buckets = device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint,
                                         cl_uint, cl_uint>("sort", "sort_buckets", opts);
            events.push_back(device.launchLocal("sort", buckets, cl::NDRange(starts.size()), cl::NDRange(1), keys,
                                                values, ws.keys, ws.values, ws.hist, cl_uint(tiles), cl_uint(n),
                                                cl_uint(lowBits), cl_uint(passes - 1)));
            std::swap(kin, kout);  // sort_buckets leaves every bucket in keys/values
            std::swap(vin, vout);
            lsdFrom = passes;
        }
    }
    for (int p = lsdFrom, shiftBits = 0; p < passes; shiftBits += digitBits(p), ++p) {
        const cl_uint mask = (1u << digitBits(p)) - 1u;
        countAndScan(cl_uint(shiftBits), mask);
        scatterPass(cl_uint(shiftBits), mask);
    }
    if (kin != &keys) {  // an odd number of passes: the result is in the scratch buffers
        cl::Event ek, ev;
        Device::guard("sort", [&] {
            device.queue().enqueueCopyBuffer(*kin, keys, 0, 0, n * keySize, nullptr, &ek);
            device.queue().enqueueCopyBuffer(*vin, values, 0, 0, n * sizeof(uint32_t), nullptr, &ev);
        });
        events.push_back(ek);
        events.push_back(ev);
    }
    device.finish();
    if (seconds)
        for (const cl::Event& e : events) *seconds += Device::elapsedSeconds(e);
}

void sortPairsOnDevice(Device& device, std::vector<uint32_t>& keys, std::vector<uint32_t>& values) {
    if (keys.size() != values.size())
        throw InternalError("sortPairsOnDevice: " + std::to_string(keys.size()) + " keys, " +
                            std::to_string(values.size()) + " values");
    cl::Buffer k = device.upload(keys, CL_MEM_READ_WRITE), v = device.upload(values, CL_MEM_READ_WRITE);
    sortPairsOnDevice(device, k, v, keys.size(), 32);
    keys = device.download<uint32_t>(k, keys.size());
    values = device.download<uint32_t>(v, values.size());
}

void sortPairsOnDevice(Device& device, std::vector<uint64_t>& keys, std::vector<uint32_t>& values, int sortBits) {
    if (keys.size() != values.size())
        throw InternalError("sortPairsOnDevice: " + std::to_string(keys.size()) + " keys, " +
                            std::to_string(values.size()) + " values");
    cl::Buffer k = device.upload(keys, CL_MEM_READ_WRITE), v = device.upload(values, CL_MEM_READ_WRITE);
    sortPairsOnDevice(device, k, v, keys.size(), 64, sortBits);
    keys = device.download<uint64_t>(k, keys.size());
    values = device.download<uint32_t>(v, values.size());
}

}  // namespace pcl
