#include "prep/medium_boundaries.h"

#include <cmath>
#include <limits>

#include "core/math.h"
#include "scene/mesh_topology.h"

namespace pcl {
namespace {

bool transmissive(const Material& m) { return m.interface || m.specular == SpecularKind::Dielectric; }

// A shape that encloses space a path can be in.
struct VolumeShape {
    bool sphere;
    uint32_t object;  // sphere or mesh index
    double volume;
    int32_t medium;  // inside
};

std::vector<VolumeShape> volumeShapes(const Scene& scene) {
    std::vector<VolumeShape> shapes;
    for (uint32_t i = 0; i < scene.spheres.size(); ++i) {
        const Sphere& s = scene.spheres[i];
        if (s.medium < 0 && !transmissive(scene.materials[size_t(s.material)])) continue;
        const double r = s.radius;
        shapes.push_back({true, i, 4.0 / 3.0 * kPiD * r * r * r, s.medium});
    }
    for (uint32_t i = 0; i < scene.meshes.size(); ++i) {
        const TriangleMesh& m = scene.meshes[i];
        if (m.medium < 0 && (!transmissive(scene.materials[size_t(m.material)]) || !closedMeshProblem(m).empty()))
            continue;
        shapes.push_back({false, i, enclosedVolume(m), m.medium});
    }
    return shapes;
}

// Ray parity: the number of triangles a fixed ray from p crosses is odd inside a closed mesh.
// The direction is skewed off every axis so that it does not run along the edges of boxes.
bool insideMesh(const TriangleMesh& mesh, Vec3 p) {
    const double d[3] = {0.5773502691896258, 0.5773502691896258 + 1.3e-3, 0.5773502691896258 - 2.1e-3};
    int crossings = 0;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        // Möller–Trumbore in double precision.
        const Vec3 a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                   c = mesh.positions[mesh.indices[t + 2]];
        const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
        const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
        const double pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
        const double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
        if (det == 0.0) continue;
        const double tv[3] = {double(p.x) - a.x, double(p.y) - a.y, double(p.z) - a.z};
        const double u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
        if (u < 0.0 || u > 1.0) continue;
        const double qv[3] = {tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2],
                              tv[0] * e1[1] - tv[1] * e1[0]};
        const double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        const double dist = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
        if (dist > 0.0) ++crossings;
    }
    return crossings % 2 == 1;
}

bool contains(const Scene& scene, const VolumeShape& v, Vec3 p) {
    if (v.sphere) {
        const Sphere& s = scene.spheres[v.object];
        return length(p - s.centre) < s.radius;
    }
    return insideMesh(scene.meshes[v.object], p);
}

// The inside medium of the smallest volume shape holding p (other than `skip`), else global.
int32_t surroundingMedium(const Scene& scene, const std::vector<VolumeShape>& shapes, Vec3 p, const VolumeShape* skip) {
    const VolumeShape* best = nullptr;
    for (const VolumeShape& v : shapes)
        if (&v != skip && (!best || v.volume < best->volume) && contains(scene, v, p)) best = &v;
    return best ? best->medium : scene.globalMedium;
}

}  // namespace

int32_t mediumAt(const Scene& scene, Vec3 p) {
    const std::vector<VolumeShape> shapes = volumeShapes(scene);
    return surroundingMedium(scene, shapes, p, nullptr);
}

MediumBoundaries findMediumBoundaries(const Scene& scene, const SceneGeometry& geometry) {
    MediumBoundaries b;
    b.inside.assign(geometry.primitiveCount(), -1);
    b.outside.assign(geometry.primitiveCount(), -1);
    if (!scene.hasMedia()) return b;
    const std::vector<VolumeShape> shapes = volumeShapes(scene);
    // Per shape: inside and outside medium.
    std::vector<int32_t> sphereIn(scene.spheres.size()), sphereOut(scene.spheres.size());
    std::vector<int32_t> meshIn(scene.meshes.size()), meshOut(scene.meshes.size());
    for (uint32_t i = 0; i < scene.spheres.size(); ++i) {
        const VolumeShape* self = nullptr;
        for (const VolumeShape& v : shapes)
            if (v.sphere && v.object == i) self = &v;
        sphereOut[i] = surroundingMedium(scene, shapes, scene.spheres[i].centre, self);
        sphereIn[i] = self ? self->medium : sphereOut[i];
    }
    for (uint32_t i = 0; i < scene.meshes.size(); ++i) {
        const VolumeShape* self = nullptr;
        for (const VolumeShape& v : shapes)
            if (!v.sphere && v.object == i) self = &v;
        const TriangleMesh& m = scene.meshes[i];
        meshOut[i] = surroundingMedium(scene, shapes, m.positions[m.indices[0]], self);
        meshIn[i] = self ? self->medium : meshOut[i];
    }
    for (uint32_t prim = 0; prim < geometry.primitiveCount(); ++prim) {
        const PrimitiveRef ref = geometry.primitive(prim);
        const bool sphere = ref.kind == PrimitiveRef::Sphere;
        b.inside[prim] = sphere ? sphereIn[ref.object] : meshIn[ref.object];
        b.outside[prim] = sphere ? sphereOut[ref.object] : meshOut[ref.object];
    }
    b.cameraMedium = surroundingMedium(scene, shapes, scene.camera.position, nullptr);
    return b;
}

}  // namespace pcl
