// CPU twin of the device radix sort (kernels/README.md, "Photon maps", sort): (key, value)
// pairs ordered by key with std::stable_sort, so equal keys keep their input order; the
// order-preserving float → key flip.
#pragma once
#include <cstdint>
#include <vector>

namespace pcl {

// Sorts pairs (keys[i], values[i]) by key, stably; only the low sortBits bits of a key count
// (64: all of them). keys.size() == values.size().
void referenceSortPairs(std::vector<uint32_t>& keys, std::vector<uint32_t>& values, int sortBits = 32);
void referenceSortPairs(std::vector<uint64_t>& keys, std::vector<uint32_t>& values, int sortBits = 64);

// bits b of a float → b ^ 0x80000000 if the sign is clear, ~b if it is set: unsigned key order
// is float order (−0 below +0; NaNs at the ends).
uint32_t referenceFloatKey(float x);

}  // namespace pcl
