// Small scenes for the photon-pass stage tests (emit, trace_photons, deposit), built in code so
// each test states its geometry, materials and lights.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "device_fixture.h"
#include "geometry/scene_geometry.h"
#include "pipeline/photon_pass.h"
#include "prep/photon_allocation.h"
#include "prep/projection_map.h"
#include "prep/scene_buffers.h"
#include "scene/load_scene.h"
#include "scene/scene.h"

namespace pcl::test {

inline void addQuad(TriangleMesh& m, Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3) {
    uint32_t base = static_cast<uint32_t>(m.positions.size());
    for (Vec3 p : {p0, p1, p2, p3}) m.positions.push_back(p);
    for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + k);
}

inline int addMaterial(Scene& s, Vec3 rhoD, Vec3 rhoS = Vec3(0.0f), SpecularKind kind = SpecularKind::None,
                       float exponent = 0.0f, float ior = 1.5f) {
    Material m;
    m.rhoD = rhoD;
    m.rhoS = rhoS;
    m.specular = kind;
    m.phongExponent = exponent;
    m.ior = ior;
    s.materials.push_back(m);
    return static_cast<int>(s.materials.size()) - 1;
}

// The closed cube [-h, h]³, faces wound to face inwards, one material.
inline TriangleMesh closedBox(float h, int material) {
    TriangleMesh m;
    m.material = material;
    Vec3 c[8];
    for (int i = 0; i < 8; ++i) c[i] = Vec3(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);
    addQuad(m, c[0], c[1], c[3], c[2]);  // z = -h, normal +z
    addQuad(m, c[4], c[6], c[7], c[5]);  // z = +h, normal -z
    addQuad(m, c[0], c[4], c[5], c[1]);  // y = -h, normal +y
    addQuad(m, c[2], c[3], c[7], c[6]);  // y = +h, normal -y
    addQuad(m, c[0], c[2], c[6], c[4]);  // x = -h, normal +x
    addQuad(m, c[1], c[5], c[7], c[3]);  // x = +h, normal -x
    return m;
}

inline Light pointLight(Vec3 p, Vec3 intensity) {
    Light l;
    l.type = LightType::Point;
    l.position = p;
    l.intensity = intensity;
    return l;
}

inline Light spotLight(Vec3 p, Vec3 axis, Vec3 intensity, float cosInner, float cosOuter) {
    Light l;
    l.type = LightType::Spot;
    l.position = p;
    l.direction = normalize(axis);
    l.intensity = intensity;
    l.cosInner = cosInner;
    l.cosOuter = cosOuter;
    return l;
}

// A downward-facing emitting quad of half-size a at height y (two triangle lights).
inline void addAreaLight(Scene& s, float y, float a, Vec3 radiance) {
    Material m;
    m.emission = radiance;
    s.materials.push_back(m);
    TriangleMesh q;
    q.material = static_cast<int>(s.materials.size()) - 1;
    addQuad(q, Vec3(-a, y, -a), Vec3(a, y, -a), Vec3(a, y, a), Vec3(-a, y, a));  // normal -y
    s.meshes.push_back(q);
    Light l;
    l.type = LightType::Area;
    l.mesh = static_cast<int>(s.meshes.size()) - 1;
    s.lights.push_back(l);
}

// Marks every projection-map cell of every light (f = 1): the caustic pass then emits as the
// global one does, for tests that do not depend on prep/projection_map.
inline void markAllProjectionCells(SceneBuffers& b) {
    b.projCells.clear();
    for (uint32_t k = 0; k < PCL_PROJ_GRID * PCL_PROJ_GRID; ++k) b.projCells.push_back(k);
    for (PclLight& l : b.lights) {
        l.projFirst = 0;
        l.projCount = PCL_PROJ_GRID * PCL_PROJ_GRID;
    }
}

struct BuiltScene {
    Scene scene;
    SceneGeometry geometry;
    SceneBuffers buffers;
};

inline BuiltScene build(Scene s) {
    BuiltScene b{s, SceneGeometry::build(s), {}};
    b.buffers = buildSceneBuffers(b.scene, b.geometry);
    return b;
}

// A scene file loaded and built with its projection maps, then one device photon pass of
// `photons` global and `photons` caustic paths.
struct ScenePhotonPass {
    BuiltScene built;
    PhotonPassOptions options;
    PhotonMaps maps;
};

inline ScenePhotonPass runScenePhotonPass(const std::string& path, uint32_t photons, uint64_t seed) {
    ScenePhotonPass r{build(loadScene(path)), {}, {}};
    buildProjectionMaps(r.built.scene, r.built.geometry, r.built.buffers);
    r.options.globalPhotons = photons;
    r.options.causticPhotons = photons;
    r.options.seed = seed;
    r.maps = runPhotonPass(testDevice(), r.built.geometry, r.built.buffers, r.options);
    return r;
}

inline double decodedPower(const PclPhoton& p) {
    uint32_t e = p.rgbe >> 24;
    if (e == 0) return 0.0;
    double scale = std::ldexp(1.0, int(e) - 136);
    return ((p.rgbe & 255u) + ((p.rgbe >> 8) & 255u) + ((p.rgbe >> 16) & 255u)) * scale / 3.0;
}

}  // namespace pcl::test
