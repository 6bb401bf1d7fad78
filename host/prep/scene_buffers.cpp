#include "prep/scene_buffers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/math.h"
#include "prep/emission_texture.h"
#include "prep/medium_boundaries.h"

namespace pcl {
namespace {

void put(float dst[4], Vec3 v) {
    dst[0] = v.x;
    dst[1] = v.y;
    dst[2] = v.z;
    dst[3] = 0.0f;
}

PclMaterial toDevice(const Material& m) {
    PclMaterial d{};
    put(d.rhoD, m.rhoD);
    put(d.rhoS, m.rhoS);
    put(d.emission, m.emission);
    switch (m.specular) {
        case SpecularKind::None: d.specular = PCL_SPECULAR_NONE; break;
        case SpecularKind::Mirror: d.specular = PCL_SPECULAR_MIRROR; break;
        case SpecularKind::Glossy: d.specular = PCL_SPECULAR_GLOSSY; break;
        case SpecularKind::Dielectric: d.specular = PCL_SPECULAR_DIELECTRIC; break;
    }
    d.exponent = m.phongExponent;
    d.ior = m.ior;
    d.flags = m.interface ? PCL_MATERIAL_INTERFACE : 0u;
    return d;
}

PclLight emptyLight(uint32_t type) {
    PclLight l{};
    l.type = type;
    l.prim = PCL_NO_HIT;
    return l;
}

}  // namespace

SceneBuffers buildSceneBuffers(const Scene& scene, const SceneGeometry& geometry) {
    SceneBuffers b;
    for (const Material& m : scene.materials) b.materials.push_back(toDevice(m));
    b.textures = buildTextureBuffers(scene, geometry);
    b.triangleNormals = buildTriangleNormals(scene, geometry);
    b.normalMaps = buildNormalMapBuffers(scene, geometry, b.textures);

    std::vector<uint32_t> meshFirst(scene.meshes.size() + 1, 0);
    for (size_t i = 0; i < scene.meshes.size(); ++i)
        meshFirst[i + 1] = meshFirst[i] + static_cast<uint32_t>(scene.meshes[i].triangleCount());

    b.primInfo.resize(geometry.primitiveCount());
    for (uint32_t prim = 0; prim < geometry.primitiveCount(); ++prim) {
        PrimitiveRef ref = geometry.primitive(prim);
        PclPrimInfo& info = b.primInfo[prim];
        if (ref.kind == PrimitiveRef::Triangle) {
            const TriangleMesh& mesh = scene.meshes[ref.object];
            Vec3 p0 = mesh.positions[mesh.indices[3 * ref.index]];
            Vec3 p1 = mesh.positions[mesh.indices[3 * ref.index + 1]];
            Vec3 p2 = mesh.positions[mesh.indices[3 * ref.index + 2]];
            Vec3 n = normalize(cross(p1 - p0, p2 - p0));
            info = {n.x,           n.y,           n.z,           static_cast<uint32_t>(mesh.material),
                    mesh.motion.x, mesh.motion.y, mesh.motion.z, 0.0f};
        } else {
            const Sphere& s = scene.spheres[ref.object];
            info = {s.centre.x, s.centre.y, s.centre.z, static_cast<uint32_t>(s.material),
                    s.motion.x, s.motion.y, s.motion.z, s.radius};
        }
    }

    Bounds3 bounds = geometry.bounds();
    if (bounds.empty()) bounds.extend(Vec3(0.0f));
    b.sceneCentre = bounds.centre();
    float diagonal = length(bounds.extent());
    b.sceneRadius = 0.5f * diagonal * 1.01f;
    // Also 32 float ulps of the largest coordinate: a hit point carries round-off of a few ulps of
    // its coordinates, so a small scene far from the origin (bounds 1 at 1e4) needs more than
    // 1e-4 of its diagonal (the stability suite's self-intersection test: 1 % of rays spawned
    // from triangles 1e4 times their size from the origin re-hit them).
    const Vec3 lo = bounds.lo, hi = bounds.hi;
    const float maxAbs =
        std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
    b.rayEpsilon = std::max({1e-6f, 1e-4f * diagonal, 32.0f * std::numeric_limits<float>::epsilon() * maxAbs});
    b.hasMotion = scene.hasMotion();

    for (const Light& light : scene.lights) {
        switch (light.type) {
            case LightType::Point: {
                PclLight l = emptyLight(PCL_LIGHT_POINT);
                put(l.p, light.position);
                put(l.power, light.intensity * (4.0f * kPi));
                b.lights.push_back(l);
                break;
            }
            case LightType::Spot: {
                PclLight l = emptyLight(PCL_LIGHT_SPOT);
                put(l.p, light.position);
                put(l.axis, normalize(light.direction));
                l.cosInner = light.cosInner;
                l.cosOuter = light.cosOuter;
                // Exact for the smoothstep falloff: smoothstep(x) + smoothstep(1 - x) = 1.
                float solidAngle = 2.0f * kPi * ((1.0f - light.cosInner) + 0.5f * (light.cosInner - light.cosOuter));
                put(l.power, light.intensity * solidAngle);
                b.lights.push_back(l);
                break;
            }
            case LightType::Directional: {
                PclLight l = emptyLight(PCL_LIGHT_DIRECTIONAL);
                put(l.p, b.sceneCentre);
                put(l.axis, normalize(light.direction));
                l.radius = b.sceneRadius;
                put(l.power, light.irradiance * (kPi * b.sceneRadius * b.sceneRadius));
                b.lights.push_back(l);
                break;
            }
            case LightType::Area: {
                if (light.mesh < 0 || light.mesh >= static_cast<int>(scene.meshes.size()))
                    throw InputError(scene.path + ": light '" + light.name + "': area light names no mesh");
                const TriangleMesh& mesh = scene.meshes[light.mesh];
                for (size_t t = 0; t < mesh.triangleCount(); ++t) {
                    Vec3 p0 = mesh.positions[mesh.indices[3 * t]];
                    Vec3 e1 = mesh.positions[mesh.indices[3 * t + 1]] - p0;
                    Vec3 e2 = mesh.positions[mesh.indices[3 * t + 2]] - p0;
                    Vec3 c = cross(e1, e2);
                    float area = 0.5f * length(c);
                    if (!(area > 0.0f)) continue;
                    PclLight l = emptyLight(PCL_LIGHT_TRIANGLE);
                    l.prim = meshFirst[light.mesh] + static_cast<uint32_t>(t);
                    put(l.p, p0);
                    put(l.e1, e1);
                    put(l.e2, e2);
                    put(l.axis, c / (2.0f * area));
                    put(l.motion, mesh.motion);
                    l.area = area;
                    // One-sided Lambertian emitter: Φ = π L A; a textured one's L is the estimate
                    // of its mean over the triangle (prep/emission_texture.h), which only
                    // chooses lights: each photon carries π A L(x) / n of its own point.
                    put(l.power, meanEmission(scene, mesh, uint32_t(t)) * (kPi * area));
                    b.lights.push_back(l);
                }
                break;
            }
        }
    }

    b.sky = buildEnvironmentBuffers(scene.environment);
    if (env_active(b.sky.environment)) b.lights.push_back(environmentLight(b.sky, b.sceneCentre, b.sceneRadius));

    if (scene.hasMedia()) {
        b.hasMedia = true;
        for (const Medium& m : scene.media) {
            PclMedium d{};
            put(d.sigmaA, m.sigmaA);
            put(d.sigmaS, m.sigmaS);
            d.g = m.g;
            b.media.push_back(d);
        }
        const MediumBoundaries sides = findMediumBoundaries(scene, geometry);
        b.cameraMedium = sides.cameraMedium;
        b.primMedia.resize(geometry.primitiveCount());
        for (uint32_t prim = 0; prim < geometry.primitiveCount(); ++prim)
            b.primMedia[prim] = {sides.inside[prim], sides.outside[prim]};
        // The medium each light entry emits into: a triangle's emitting side is the one its
        // normal (the geometric one, same winding) points to; a directional light comes from
        // infinitely far, through all of a global medium: none of it arrives.
        for (const PclLight& l : b.lights) {
            int32_t medium = PCL_NO_MEDIUM;
            if (l.type == PCL_LIGHT_DIRECTIONAL)
                medium = scene.globalMedium >= 0 ? PCL_MEDIUM_UNREACHABLE : PCL_NO_MEDIUM;
            else if (l.type == PCL_LIGHT_TRIANGLE) medium = sides.outside[l.prim];
            else medium = mediumAt(scene, Vec3(l.p[0], l.p[1], l.p[2]));
            b.lightMedia.push_back(medium);
        }
    }
    return b;
}

}  // namespace pcl
