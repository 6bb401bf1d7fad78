// Jensen's mixed surface as a BSDF for the reference path tracer: a Lambertian part ρd/π plus
// one specular part ρs of kind mirror (delta), glossy (normalised Phong lobe around the mirror
// direction) or dielectric (exact Fresnel between reflection and refraction, both delta).
//
// sample() picks the diffuse or the specular lobe with probability proportional to the
// luminance of ρd and ρs, and returns the sample's weight f |cosθ| / pdf with that choice
// folded in, so the estimator stays unbiased whatever the split.
//
// Refraction scales radiance by η² as pbrt-v4's "radiance" mode does: crossing from wo's side
// (index η_o) to the other (η_t), the weight picks up (η_o/η_t)², so a camera inside glass sees
// the world outside η² brighter and a diffuse floor under water looks 1/η² dimmer. (Paths that
// enter and leave a dielectric get factors that cancel.)
#pragma once
#include "core/vec3.h"
#include "scene/scene.h"

namespace pcl {

struct BsdfSample {
    Vec3 wi;        // incident direction (unit, pointing away from the surface)
    Vec3 weight;    // f |cos θi| / pdf
    float pdf = 0;  // solid-angle density of wi (non-delta), or the discrete probability (delta)
    bool delta = false;
    float radianceScale = 1.0f;  // the (η_i/η_t)² of a refraction folded into weight; 1 otherwise
};

class MixedBsdf {
public:
    // ns: shading normal, ng: geometric normal (outside of a dielectric), both unit, same side.
    MixedBsdf(const Material& material, Vec3 ns, Vec3 ng);
    // The same with ρd, ρs and the glossy exponent at the shading point in place of the
    // material's constants (its textures; SurfacePoint has them).
    MixedBsdf(const Material& material, Vec3 rhoD, Vec3 rhoS, float exponent, Vec3 ns, Vec3 ng);

    bool isBlack() const { return pDiffuse_ == 0.0f && pSpecular_ == 0.0f; }
    // True if some lobe is not a delta, so light sampling can reach it.
    bool hasNonDelta() const { return pDiffuse_ > 0.0f || (pSpecular_ > 0.0f && m_.specular == SpecularKind::Glossy); }

    // f(wo, wi) |cos θi| over the non-delta lobes (diffuse, glossy); delta lobes give 0.
    Vec3 evalCos(Vec3 wo, Vec3 wi) const;
    // Density with which sample() returns wi through its non-delta lobes.
    float pdf(Vec3 wo, Vec3 wi) const;
    // uLobe picks the lobe (and reflection vs refraction); u1, u2 the direction. False: no
    // valid direction (below the surface, or absorbed).
    bool sample(Vec3 wo, float uLobe, float u1, float u2, BsdfSample& out) const;

private:
    Vec3 shadingNormalFacing(Vec3 w) const { return dot(ng_, w) >= 0.0f ? ns_ : -ns_; }
    bool sameSide(Vec3 wo, Vec3 wi) const { return dot(ng_, wo) * dot(ng_, wi) > 0.0f; }

    Material m_;
    Vec3 ns_, ng_;
    float pDiffuse_ = 0.0f, pSpecular_ = 0.0f;  // lobe choice probabilities (sum 1, or both 0)
};

// Fresnel reflectance of a smooth dielectric for unpolarised light (the exact formula, e.g.
// pbrt-v3 eq. 8.2): cosI ≥ 0 on the incident side, etaI / etaT the indices on either side.
// Returns 1 under total internal reflection.
float fresnelDielectric(float cosI, float etaI, float etaT);

// Direction refracted through the surface with normal n (on wo's side), eta = etaI / etaT
// (Snell's law in vector form). False under total internal reflection.
bool refract(Vec3 wo, Vec3 n, float eta, Vec3& wt);

}  // namespace pcl
