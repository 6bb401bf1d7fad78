// The thin-wall leak scene (estimate tests, stability suite): two closed rooms of diffuse quads
// sharing a wall of thickness t, lit in one. Room B's floor and ceiling are coplanar with A's,
// so A's floor photons pass B's normal tests: only a visibility test stops them.
#pragma once

#include "scene/scene.h"
#include "stages/photon_test_scenes.h"

namespace pcl::test {

// The closed box [lo, hi] as one mesh of inward-facing quads.
inline void addRoom(Scene& s, Vec3 lo, Vec3 hi, int material) {
    TriangleMesh m;
    m.material = material;
    Vec3 c[8];
    for (int i = 0; i < 8; ++i) c[i] = Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    addQuad(m, c[0], c[1], c[3], c[2]);
    addQuad(m, c[4], c[6], c[7], c[5]);
    addQuad(m, c[0], c[4], c[5], c[1]);
    addQuad(m, c[2], c[3], c[7], c[6]);
    addQuad(m, c[0], c[2], c[6], c[4]);
    addQuad(m, c[1], c[5], c[7], c[3]);
    s.meshes.push_back(m);
}

}  // namespace pcl::test
