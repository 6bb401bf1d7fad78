// Scenes with smooth-shaded meshes (per-vertex normals), built in code for the shading-normal
// tests: a low-poly UV sphere whose vertex normals are the true sphere's, in a closed room.
#pragma once
#include <cmath>

#include "common/test_scenes.h"
#include "scene/mesh_tangents.h"

namespace pcl::test_scenes {

// A UV sphere of `stacks` × `slices` quads (two triangles each, poles as fans) around c, its
// vertex normals the exact sphere's (outward) when `normals`, texture coordinates (u around
// from +x toward +z, v from the top pole down); returns the mesh index.
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
            m.uv[0].push_back(float(j) / float(slices));
            m.uv[0].push_back(float(i) / float(stacks));
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

// An 8 × 8 tangent-space normal map of 2 × 2-texel cells tilted ±0.4 along x and ±0.3 along y
// (linear rgb = (n + 1)/2).
inline Image slopeCellsNormalMap() {
    Image map(8, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const Vec3 m = normalize(Vec3((x / 2) % 2 ? -0.4f : 0.4f, (y / 2) % 2 ? -0.3f : 0.3f, 1.0f));
            map.set(x, y, (m + Vec3(1.0f)) * 0.5f);
        }
    return map;
}

// A 16 × 16 tangent-space normal map of gentle waves: n ∝ (0.3 sin 2πx/16, 0.3 cos 2πy/16, 1),
// x, y the texel centres (tileable; linear rgb = (n + 1)/2).
inline Image wavesNormalMap() {
    Image map(16, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const float a = 6.2831853f * (float(x) + 0.5f) / 16.0f, b = 6.2831853f * (float(y) + 0.5f) / 16.0f;
            const Vec3 m = normalize(Vec3(0.3f * std::sin(a), 0.3f * std::cos(b), 1.0f));
            map.set(x, y, (m + Vec3(1.0f)) * 0.5f);
        }
    return map;
}

// The smooth room with normal maps: the floor and the diffuse sphere carry wavesNormalMap (the
// floor's repeated 1.5 × by its transform), the glass sphere too (scale 0.5 on all three): every stage meets
// perturbed normals on diffuse and specular surfaces. Gentle waves, not slopeCellsNormalMap's
// cells: a normal that turns steeply across a texel turns the twin's last-bit differences in
// the hit's coordinates (its own traversal arithmetic) into differences the checks count. Tangents are
// generated (addMissingTangents, as validateScene does).
inline Scene normalMappedRoom(int width = 48, int height = 36) {
    Scene s = smoothRoom(width, height);
    s.path = "(normal-mapped room)";
    Texture floorMap;
    floorMap.path = "(in memory: waves, repeated)";
    floorMap.image = wavesNormalMap();
    floorMap.transform.scale[0] = floorMap.transform.scale[1] = 1.5f;
    s.textures.push_back(floorMap);
    Texture sphereMap = floorMap;
    sphereMap.path = "(in memory: waves)";
    sphereMap.transform = TextureTransform{};
    s.textures.push_back(sphereMap);
    const int floorMat = addMaterial(s, Vec3(0.6f));
    s.materials[size_t(floorMat)].normalTexture = 0;
    s.materials[size_t(floorMat)].normalScale = 0.5f;
    s.meshes[0].material = floorMat;
    s.meshes[0].uv[0] = {0, 0, 1, 0, 1, 1, 0, 1};
    for (size_t k = 6; k < 8; ++k) {  // the diffuse and the glass sphere
        Material& m = s.materials[size_t(s.meshes[k].material)];
        m.normalTexture = 1;
        m.normalScale = 0.5f;
    }
    addMissingTangents(s);
    return s;
}

}  // namespace pcl::test_scenes
