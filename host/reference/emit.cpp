#include "reference/emit.h"

#include "prep/photon_allocation.h"
#include "prep/projection_map.h"

#include <algorithm>
#include <cmath>

#include "reference/parallel_for.h"
#include "reference/sampling.h"
#include "shared/environment.h"
#include "shared/rng.h"
#include "shared/texture.h"

namespace pcl {
namespace {

Vec3 vec(const float v[4]) { return {v[0], v[1], v[2]}; }

// Direction with cosθ and φ in the frame of `axis` (makeBasis, Duff et al. 2017).
Vec3 inFrame(Vec3 axis, float cosTheta, float phi) {
    Vec3 t, b;
    makeBasis(axis, t, b);
    float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    return fromLocal(t, b, axis, sinTheta, cosTheta, phi);
}

}  // namespace

uint64_t referencePhotonPassSeed(uint64_t seed, uint32_t pass) { return seed + uint64_t(pass) * 0x9E3779B97F4A7C15ull; }

uint32_t referenceLightOfPhoton(const std::vector<uint32_t>& first, uint32_t j) {
    // The last i with first[i] <= j (lights with no photons have first[i] == first[i+1]).
    auto it = std::upper_bound(first.begin(), first.end() - 1, j);
    return static_cast<uint32_t>(it - first.begin()) - 1;
}

std::vector<double> referenceAllocationWeights(const SceneBuffers& buffers, uint32_t pass) {
    std::vector<double> w;
    for (const PclLight& l : buffers.lights) {
        double s = scalarPower(l);
        if (pass == PCL_PASS_CAUSTIC) s *= projectionFraction(l);
        w.push_back(s);
    }
    return w;
}

float referenceSpotCosTheta(float s1, float cosInner, float cosOuter) {
    const double wIn = 1.0 - double(cosInner);
    const double wFall = 0.5 * (double(cosInner) - double(cosOuter));
    const double pIn = wIn / (wIn + wFall);
    if (s1 < pIn) return static_cast<float>(1.0 - (s1 / pIn) * wIn);
    // Falloff band: the normalised integral of smoothstep t²(3 − 2t) is 2t³ − t⁴ = v, monotone
    // on [0, 1]; bisection in double to full precision.
    const double v = (s1 - pIn) / (1.0 - pIn);
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 60; ++k) {
        double t = 0.5 * (lo + hi);
        (2.0 * t * t * t - t * t * t * t < v ? lo : hi) = t;
    }
    const double t = 0.5 * (lo + hi);
    return static_cast<float>(double(cosOuter) + t * (double(cosInner) - double(cosOuter)));
}

PclPhotonRay emitPhotonReference(const SceneBuffers& buffers, const std::vector<uint32_t>& first,
                                 const PclPhotonParams& params, uint32_t j) {
    const uint32_t li = referenceLightOfPhoton(first, j);
    const PclLight& light = buffers.lights[li];
    const bool caustic = params.pass == PCL_PASS_CAUSTIC;

    // Numbers of bounce 0: u0 projection cell, (u1, u2) position, u3 time, (u4, u5) direction.
    PclRng rng = rng_start(referenceParamsSeed(params), j, 0, caustic ? PCL_RNG_STREAM_CAUSTIC : PCL_RNG_STREAM_PHOTON);
    float u[6];
    for (float& x : u) x = rng_next(&rng);
    const float time = params.hasMotion ? u[3] : 0.0f;

    // The light's sample square: (u4, u5), or (u1, u2) for a directional light's position.
    const bool directional = light.type == PCL_LIGHT_DIRECTIONAL;
    float s1 = directional ? u[1] : u[4];
    float s2 = directional ? u[2] : u[5];
    if (caustic) {
        // Projection map (Jensen 1996): only the marked cells of the square.
        const uint32_t G = PCL_PROJ_GRID;
        uint32_t pick = std::min(static_cast<uint32_t>(u[0] * float(light.projCount)), light.projCount - 1);
        uint32_t k = buffers.projCells[light.projFirst + pick];
        s1 = (float(k % G) + s1) / float(G);
        s2 = (float(k / G) + s2) / float(G);
    }

    Vec3 origin, direction;
    const Vec3 axis = vec(light.axis);
    Vec3 skyScale(0.0f);    // the sky: π R² L_c(w) / p(w), the map's texel and density (shared/environment.h)
    bool textured = false;  // a triangle light with an emission texture: each photon carries π A L(x) / n
    Vec3 emitted(0.0f);     // then π A L(x)
    switch (light.type) {
        case PCL_LIGHT_ENVIRONMENT: {  // parallel from a disc of radius R facing −w, 2R back
            PclV3 w;
            float Ls[3];
            const float pdf = env_sample(buffers.sky.environment, buffers.sky.data.data(), s1, s2, &w, Ls);
            direction = Vec3(-w.x, -w.y, -w.z);
            float x, y;
            sampleConcentricDisk(u[1], u[2], x, y);
            Vec3 t, b;
            makeBasis(direction, t, b);
            const float R = light.radius;
            // Caustic photons: the disc of the ball around the specular objects (radius r).
            const bool aimed = caustic && light.e1[3] > 0.0f;
            const float r = aimed ? light.e1[3] : R;
            const Vec3 centre = aimed ? Vec3(light.e1[0], light.e1[1], light.e1[2]) : vec(light.p);
            origin = centre + (t * x + b * y) * r - direction * (2.0f * R);
            if (pdf > 0.0f)
                skyScale = Vec3(kPi * r * r * Ls[0] / pdf, kPi * r * r * Ls[1] / pdf, kPi * r * r * Ls[2] / pdf);
            break;
        }
        case PCL_LIGHT_POINT:
            origin = vec(light.p);
            direction = sampleUniformSphere(s1, s2);
            break;
        case PCL_LIGHT_SPOT:
            origin = vec(light.p);
            direction = inFrame(axis, referenceSpotCosTheta(s1, light.cosInner, light.cosOuter), 2.0f * kPi * s2);
            break;
        case PCL_LIGHT_TRIANGLE: {
            float b0, b1;
            sampleUniformTriangle(u[1], u[2], b0, b1);
            origin = vec(light.p) + vec(light.e1) * b1 + vec(light.e2) * (1.0f - b0 - b1) + vec(light.motion) * time +
                     axis * params.rayEpsilon;
            direction = sampleCosineHemisphere(axis, s1, s2);  // Malley: one-sided Lambertian
            const uint32_t mat = buffers.primInfo[light.prim].material;
            const TextureBuffers& tex = buffers.textures;
            if (mat < tex.materialTextures.size() && tex.materialTextures[mat].slot[PCL_TEXTURE_EMISSION].width != 0) {
                // L(x) at the barycentrics (b1, b2) of the point: shared/texture.h's lookup.
                textured = true;
                float le[3];
                texture_emission_at(tex.materialTextures.data(), tex.texels.data(), tex.triangleUvs.data(), mat,
                                    light.prim, params.triangleCount, b1, 1.0f - b0 - b1,
                                    buffers.materials[mat].emission, le);
                const float scale = kPi * light.area;
                emitted = Vec3(scale * le[0], scale * le[1], scale * le[2]);
            }
            break;
        }
        default: {  // directional: parallel rays from a disc covering the scene
            float x, y;
            sampleConcentricDisk(s1, s2, x, y);
            Vec3 t, b;
            makeBasis(axis, t, b);
            const float R = light.radius;
            origin = vec(light.p) + (t * x + b * y) * R - axis * (2.0f * R);
            direction = axis;
            break;
        }
    }

    // Every photon of light i carries Φ_i / n_i (caustic: Φ_i f_i / n_i), so the total is ΣΦ.
    const float n = float(first[li + 1] - first[li]);
    // (The sky's aim is in skyScale already: r², not R².)
    const float f = caustic ? float(light.projCount) / float(PCL_PROJ_GRID * PCL_PROJ_GRID) : 1.0f;
    PclPhotonRay r{};
    r.ox = origin.x;
    r.oy = origin.y;
    r.oz = origin.z;
    r.time = time;
    r.dx = direction.x;
    r.dy = direction.y;
    r.dz = direction.z;
    r.light = li;
    const Vec3 power = light.type == PCL_LIGHT_ENVIRONMENT ? skyScale : (textured ? emitted : vec(light.power));
    r.power[0] = power.x * f / n;
    r.power[1] = power.y * f / n;
    r.power[2] = power.z * f / n;
    r.power[3] = 0.0f;
    return r;
}

std::vector<PclPhotonRay> emitPhotonsReference(const SceneBuffers& buffers, const std::vector<uint32_t>& first,
                                               const PclPhotonParams& params, unsigned threads) {
    std::vector<PclPhotonRay> rays(params.batchSize);
    referenceParallelFor(params.batchSize, threads, [&](size_t i) {
        rays[i] = emitPhotonReference(buffers, first, params, params.firstPhoton + static_cast<uint32_t>(i));
    });
    return rays;
}

}  // namespace pcl
