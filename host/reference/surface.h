// The surface point a ray hit, rebuilt from a PclHit: position, normals and material, with
// moving primitives placed at the ray's shutter time.
#pragma once
#include <cstdint>
#include <limits>

#include "geometry/scene_geometry.h"
#include "scene/scene.h"

namespace pcl {

struct SurfacePoint {
    Vec3 p;   // world position
    Vec3 ng;  // geometric normal, unit: the emitting / outside side (not flipped toward the ray)
    Vec3 ns;  // shading normal, unit, on the same side as ng
    const Material* material = nullptr;
    // The material's quantities here: its constants with its textures at the hit (if any).
    Vec3 rhoD, rhoS;
    float exponent = 0.0f;  // glossy: the Phong exponent
    Vec3 emission{0.0f};    // emitted radiance (one-sided, the ng side): the constant × its emission texture
    uint32_t prim = PCL_NO_HIT;
    float time = 0.0f;
};

// Vertex positions and geometric normal of triangle `index` of `mesh` at shutter time τ.
struct TriangleVertices {
    Vec3 p0, p1, p2;
};
TriangleVertices triangleAt(const TriangleMesh& mesh, uint32_t index, float time);

SurfacePoint surfaceAt(const Scene& scene, const SceneGeometry& geometry, const PclRay& ray, const PclHit& hit);

inline Vec3 rayOrigin(const PclRay& r) { return {r.ox, r.oy, r.oz}; }
inline Vec3 rayDirection(const PclRay& r) { return {r.dx, r.dy, r.dz}; }
// The ray o + t d, t in [tmin, tmax), with no offset (cameras and lights: nothing to leave).
inline PclRay makeRay(Vec3 o, Vec3 d, float time, float tmax = std::numeric_limits<float>::infinity(),
                      float tmin = 0.0f) {
    PclRay r{};
    r.ox = o.x;
    r.oy = o.y;
    r.oz = o.z;
    r.dx = d.x;
    r.dy = d.y;
    r.dz = d.z;
    r.tmin = tmin;
    r.tmax = tmax;
    r.time = time;
    return r;
}

// A ray leaving p along d (unnormalised allowed) on the side of n that d points to, offset
// against self-intersection by a distance relative to the magnitude of p.
PclRay spawnRay(Vec3 p, Vec3 n, Vec3 d, float time, float tmax);
// A shadow ray from p (offset along n toward `target`) to `target` (offset along targetN toward
// p; targetN = 0 for a point light): the direction is unnormalised, t runs over (0, 1), so
// neither end's own surface shadows it.
PclRay spawnShadowRay(Vec3 p, Vec3 n, Vec3 target, Vec3 targetN, float time);

}  // namespace pcl
