// Device radix sort (kernels/sort.cl; kernels/README.md, "Photon maps"): a stable LSD radix sort
// of (key, value) pairs, 8 (CPU) or 4 (GPU) bits per pass, keys of 32 or 64 bits, values 32-bit
// (the photon index). Stable and deterministic by construction: equal keys keep their input order, the
// result depends on the input alone. The twin is host/reference/sort.h (std::stable_sort).
//
//   cl::Buffer keys = dev.upload(k), values = dev.upload(v);   // CL_MEM_READ_WRITE buffers
//   sortPairsOnDevice(dev, keys, values, n, 32);               // sorted in place
//   sortPairsOnDevice(dev, keys64, values, n, 64, 40);         // 64-bit keys, only bits 0..39 used
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "device/device.h"

namespace pcl {

// Scratch buffers (a second key and value array, the tile histogram) kept between sorts so a
// caller that sorts repeatedly (the kd-tree build: one rank sort per axis) allocates them once.
struct SortWorkspace {
    cl::Buffer keys, values, hist;
    size_t capacity = 0;  // elements the key/value scratch holds
    size_t histCapacity = 0;
    int keyBits = 0;  // width of the scratch keys (32 or 64)
};

// Sorts the first n (key, value) pairs of `keys` (uint32 elements when keyBits == 32, uint64
// when keyBits == 64) and `values` (uint32) in place by key, stably. sortBits (1..keyBits, or 0
// for keyBits) limits the sort to the low sortBits bits: pairs are ordered by key & (2^sortBits
// − 1), higher key bits are ignored (they still move with their key); ⌈sortBits/8⌉ passes on a
// CPU (the top digit, then each bucket in cache, from 2^18 pairs), ⌈sortBits/4⌉ on a GPU.
// n < 2^31. Adds the device time to *seconds when given. Throws
// InternalError on a bad width, DeviceError on a device failure.
void sortPairsOnDevice(Device& device, cl::Buffer& keys, cl::Buffer& values, size_t n, int keyBits, int sortBits = 0,
                       double* seconds = nullptr, SortWorkspace* workspace = nullptr);

// Entries of the tile histogram a sort of n pairs allocates on a device of this type (the
// memory plan's prediction; the pass shape follows the type and PHOTONCL_SORT_SHAPE).
size_t sortHistogramEntries(cl_device_type type, size_t n);

// Vector conveniences: upload, sort, download.
void sortPairsOnDevice(Device& device, std::vector<uint32_t>& keys, std::vector<uint32_t>& values);
void sortPairsOnDevice(Device& device, std::vector<uint64_t>& keys, std::vector<uint32_t>& values, int sortBits = 64);

}  // namespace pcl
