// The search structure of a photon map: Jensen's left-balanced kd-tree or a sorted hash grid.
// Both find the same photons in the same order (pipeline/knn.h); only the speed differs.
#pragma once
#include <string>

namespace pcl {

enum class KnnStructure { KdTree, HashGrid };

inline const char* knnStructureName(KnnStructure s) { return s == KnnStructure::KdTree ? "kd-tree" : "hash grid"; }

}  // namespace pcl
