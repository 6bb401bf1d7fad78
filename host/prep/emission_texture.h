// Textured emitters (Material::emissionTexture): the radiance a triangle emits at a point, and
// the estimate of its mean over the triangle that chooses lights by power.
//
// Light choice only has to be positive wherever the emitter can emit; the estimators divide by
// the same choice probability they sample with and weight each point by its own radiance, so
// any such estimate keeps them exact (photon power π A L(x) / n at the point sampled, uniform on
// the triangle; next-event estimation L(x) / pdf with pdf = P(triangle) / A · d² / cos). A good
// estimate only keeps the variance low.
#pragma once
#include <cstdint>

#include "core/vec3.h"
#include "scene/scene.h"

namespace pcl {

// Radiance triangle `triangle` of `mesh` emits at barycentrics (bu, bv) (p = p0 + bu (p1 − p0) +
// bv (p2 − p0)): its material's emission times the emission texture there, bilinearly filtered
// as kernels/shared/texture.h does (the constant alone without an emission texture).
Vec3 emissionAt(const Scene& scene, const TriangleMesh& mesh, uint32_t triangle, float bu, float bv);

// The mean emitted radiance over the triangle, estimated once at scene preparation: the
// constant without an emission texture (exact); with one, the mean of the texture at the
// centroids of g² congruent sub-triangles (g from 4 to 64, about two samples per texel the
// triangle covers along each side) times the constant. When every sample reads 0 it falls back
// to the constant times the texture's largest texel per channel (an upper bound), so the
// estimate is 0 only where the emitter emits nothing at all.
Vec3 meanEmission(const Scene& scene, const TriangleMesh& mesh, uint32_t triangle);

}  // namespace pcl
