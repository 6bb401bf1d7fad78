// Whether a triangle mesh bounds a volume, so that it can hold a medium: closed (every edge
// shared by exactly two triangles), consistently wound (the two triangles run along a shared
// edge in opposite directions) and facing outward (positive enclosed volume), so that a ray
// crossing a triangle against its geometric normal enters the inside.
#pragma once
#include <string>

#include "scene/scene.h"

namespace pcl {

// Empty if `mesh` bounds a volume with outward-facing triangles; otherwise what is wrong, for a
// message ("edge (3,7) is used by 1 triangle", ...). Vertices at the same position count as one,
// so meshes split at creases (per-face normals) are still closed.
std::string closedMeshProblem(const TriangleMesh& mesh);

// The volume a closed, consistently wound mesh encloses (divergence theorem: Σ p0·(p1×p2)/6);
// positive when its triangles face outward.
double enclosedVolume(const TriangleMesh& mesh);

}  // namespace pcl
