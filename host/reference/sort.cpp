#include "reference/sort.h"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <stdexcept>

namespace pcl {
namespace {

template <class K>
void sortPairs(std::vector<K>& keys, std::vector<uint32_t>& values, int sortBits) {
    if (keys.size() != values.size()) throw std::invalid_argument("referenceSortPairs: key and value counts differ");
    const K mask = sortBits >= int(8 * sizeof(K)) ? ~K(0) : (K(1) << sortBits) - 1;
    std::vector<size_t> order(keys.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return (keys[a] & mask) < (keys[b] & mask); });
    std::vector<K> k(keys.size());
    std::vector<uint32_t> v(values.size());
    for (size_t i = 0; i < order.size(); ++i) {
        k[i] = keys[order[i]];
        v[i] = values[order[i]];
    }
    keys.swap(k);
    values.swap(v);
}

}  // namespace

void referenceSortPairs(std::vector<uint32_t>& keys, std::vector<uint32_t>& values, int sortBits) {
    sortPairs(keys, values, sortBits);
}

void referenceSortPairs(std::vector<uint64_t>& keys, std::vector<uint32_t>& values, int sortBits) {
    sortPairs(keys, values, sortBits);
}

uint32_t referenceFloatKey(float x) {
    uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return (b & 0x80000000u) ? ~b : (b ^ 0x80000000u);
}

}  // namespace pcl
