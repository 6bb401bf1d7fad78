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
// constant without an emission texture (exact). With one: 0 when every texel bilinear filtering
// can read on the triangle is 0 (it emits nothing anywhere; exact), else the mean of the
// texture at the centroids of g² congruent sub-triangles (g from 4 to 64, about two samples per
// texel the triangle spans along a side) times the constant, or, when every sample reads 0,
// the constant times the largest texel the triangle can read over the number of samples (one
// sample's worth: what the grid can have missed). So the estimate is positive wherever the
// emitter can emit.
Vec3 meanEmission(const Scene& scene, const TriangleMesh& mesh, uint32_t triangle);

}  // namespace pcl
