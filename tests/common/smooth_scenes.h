// Scenes with smooth-shaded meshes (per-vertex normals), built in code for the shading-normal
// tests: a low-poly UV sphere whose vertex normals are the true sphere's, in a closed room.
#pragma once
#include <cmath>

#include "common/test_scenes.h"

namespace pcl::test_scenes {

// A UV sphere of `stacks` × `slices` quads (two triangles each, poles as fans) around c, its
// vertex normals the exact sphere's (outward) when `normals`; returns the mesh index.
inline int addUvSphereMesh(Scene& s, Vec3 c, float r, int stacks, int slices, int material, bool normals = true) {
    TriangleMesh m;
    m.name = "uv-sphere";
    for (int i = 0; i <= stacks; ++i) {
        const float theta = 3.14159265358979f * float(i) / float(stacks);
        for (int j = 0; j <= slices; ++j) {
            const float phi = 6.28318530717959f * float(j) / float(slices);
            const Vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            m.positions.push_back(c + n * r);
            if (normals) m.normals.push_back(n);
        }
    }
    const uint32_t row = uint32_t(slices + 1);
    for (int i = 0; i < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            const uint32_t a = uint32_t(i) * row + uint32_t(j), b = a + 1, d = a + row, e = d + 1;
            // Outward winding: (p1 − p0) × (p2 − p0) along the outside normal.
            if (i > 0) m.indices.insert(m.indices.end(), {a, b, d});
            if (i + 1 < stacks) m.indices.insert(m.indices.end(), {b, e, d});
        }
    m.material = material;
    s.meshes.push_back(m);
    return static_cast<int>(s.meshes.size()) - 1;
}

// A closed grey room (2 × 2 × 2) lit by a point light below the ceiling, with a diffuse smooth
// sphere, a glass smooth sphere and a glossy smooth sphere (12 × 16 facets each: their normals
// differ from the facets' by up to ~8°), seen from the front.
inline Scene smoothRoom(int width = 48, int height = 36) {
    Scene s;
    s.path = "(smooth room)";
    const int plain = addMaterial(s, Vec3(0.6f, 0.6f, 0.6f));
    const int red = addMaterial(s, Vec3(0.7f, 0.2f, 0.2f));
    const int diffuse = addMaterial(s, Vec3(0.8f, 0.8f, 0.5f));
    const int glass = addGlass(s, 1.5f);
    const int glossy = addMaterial(s, Vec3(0.3f, 0.4f, 0.6f), Vec3(0.4f), SpecularKind::Glossy, Vec3(0.0f), 20.0f);
    addQuad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), plain);  // floor, +y
    addQuad(s, Vec3(-1, 0, -1), Vec3(2, 0, 0), Vec3(0, 2, 0), plain);  // back, +z
    addQuad(s, Vec3(-1, 2, -1), Vec3(2, 0, 0), Vec3(0, 0, 2), plain);  // ceiling, −y
    addQuad(s, Vec3(-1, 0, 1), Vec3(0, 0, -2), Vec3(0, 2, 0), red);    // left, +x
    addQuad(s, Vec3(1, 0, -1), Vec3(0, 0, 2), Vec3(0, 2, 0), plain);   // right, −x
    addQuad(s, Vec3(1, 0, 1), Vec3(-2, 0, 0), Vec3(0, 2, 0), plain);   // front, −z
    addUvSphereMesh(s, Vec3(-0.45f, 0.4f, -0.3f), 0.4f, 12, 16, diffuse);
    addUvSphereMesh(s, Vec3(0.5f, 0.35f, 0.1f), 0.35f, 12, 16, glass);
    addUvSphereMesh(s, Vec3(0.1f, 0.3f, -0.6f), 0.3f, 12, 16, glossy);
    Light l = pointLight(Vec3(0.0f, 1.8f, 0.0f));
    l.intensity = Vec3(3.0f);
    s.lights.push_back(l);
    setCamera(s, Vec3(0.0f, 1.0f, 0.95f), Vec3(0.0f, 0.5f, -1.0f), Vec3(0, 1, 0), 70.0f, width, height);
    return s;
}

}  // namespace pcl::test_scenes
