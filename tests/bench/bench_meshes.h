// Meshes generated in code for benchmarks: no file to ship or load.
#pragma once
#include <cmath>

#include "scene/scene.h"

namespace pcl {

// A sphere tessellated into 2·rings·segments triangles (minus the poles) with a bumpy radial
// displacement, so the triangles vary in size and orientation like a scanned model.
// rings = 500, segments = 1000 gives ~1M triangles.
inline TriangleMesh displacedSphere(int rings, int segments, float radius = 1.0f) {
    TriangleMesh m;
    m.name = "displaced-sphere";
    m.positions.reserve(size_t(rings + 1) * segments);
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < segments; ++j) {
            float th = 3.14159265f * i / rings, ph = 6.2831853f * j / segments;
            float bump = 1.0f + 0.08f * std::sin(7 * th) * std::cos(11 * ph) +
                         0.03f * std::sin(31 * th + 3 * ph) * std::sin(23 * ph);
            m.positions.push_back(Vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)) *
                                  (radius * bump));
        }
    m.indices.reserve(size_t(rings) * segments * 6);
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            uint32_t a = i * segments + j, b = i * segments + (j + 1) % segments;
            uint32_t c = a + segments, d = b + segments;
            if (i > 0) m.indices.insert(m.indices.end(), {a, b, c});
            if (i < rings - 1) m.indices.insert(m.indices.end(), {b, d, c});
        }
    return m;
}

}  // namespace pcl
