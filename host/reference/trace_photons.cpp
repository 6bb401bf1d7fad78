#include "reference/trace_photons.h"

#include <algorithm>
#include <cmath>

#include "reference/bsdf.h"
#include "reference/eye_scatter.h"
#include "reference/medium.h"
#include "reference/parallel_for.h"
#include "reference/sampling.h"
#include "reference/shutter_open.h"
#include "reference/textured_material.h"
#include "shared/rng.h"
#include "shared/shading_frame.h"

namespace pcl {
namespace {

Vec3 vec(const float v[4]) { return {v[0], v[1], v[2]}; }

// Roulette and the new direction in the frame of shading normal ns (= n on flat surfaces).
ReferenceScatter scatterInShadingFrame(const PclMaterial& m, Vec3 d, Vec3 n, Vec3 ns, Vec3 power, const float u[4]) {
    ReferenceScatter s;
    const Vec3 rhoD = vec(m.rhoD), rhoS = vec(m.rhoS);
    const Vec3 nf = dot(d, n) < 0.0f ? ns : -ns;  // the shading normal on the photon's side

    // Jensen 2001 §5.3.2: per-channel probabilities, so a coloured surface keeps the photon's
    // power level and changes only its colour. (Grey surfaces: the notes' z < ρd, z < ρd + ρs.)
    const float maxPower = maxComponent(power);
    if (!(maxPower > 0.0f)) return s;  // absorbed
    float pd = maxComponent(rhoD * power) / maxPower;
    float ps = m.specular == PCL_SPECULAR_NONE ? 0.0f : maxComponent(rhoS * power) / maxPower;
    s.pDiffuse = pd;
    s.pSpecular = ps;
    if (pd + ps > 1.0f) {
        const float sum = pd + ps;
        pd /= sum;
        ps /= sum;
    }

    const float z = u[0];
    if (z < pd) {  // diffuse: cosine hemisphere around n_f (Malley), Φ ρd / P_d
        s.kind = ReferenceScatter::Diffuse;
        s.direction = sampleCosineHemisphere(nf, u[2], u[3]);
        s.power = power * rhoD / pd;
        return s;
    }
    if (!(z < pd + ps)) return s;  // absorbed

    s.power = power * rhoS / ps;
    const Vec3 mirror = d - nf * (2.0f * dot(d, nf));
    switch (m.specular) {
        case PCL_SPECULAR_MIRROR:
            s.kind = ReferenceScatter::Mirror;
            s.direction = mirror;
            break;
        case PCL_SPECULAR_GLOSSY: {
            // Normalised Phong lobe ρs (n+2)/(2π) cosⁿα sampled with density (n+1)/(2π) cosⁿα:
            // the weight is (n+2)/(n+1) cosθ'.
            s.direction = samplePhongLobe(mirror, m.exponent, u[2], u[3]);
            const float cosOut = dot(s.direction, nf);
            if (!(cosOut > 0.0f)) {
                s.kind = ReferenceScatter::GlossyBelow;
                s.power = Vec3(0.0f);
                return s;
            }
            s.kind = ReferenceScatter::Glossy;
            s.power = s.power * ((m.exponent + 2.0f) / (m.exponent + 1.0f) * cosOut);
            break;
        }
        default: {  // dielectric: exact Fresnel chooses reflection or refraction
            const bool entering = dot(d, n) < 0.0f;
            const float eta = entering ? 1.0f / m.ior : m.ior;
            const float cosI = std::fabs(dot(d, ns));
            const float F = entering ? fresnelDielectric(cosI, 1.0f, m.ior) : fresnelDielectric(cosI, m.ior, 1.0f);
            if (u[1] < F) {
                s.kind = ReferenceScatter::Reflected;
                s.direction = mirror;
            } else {
                // Snell in vector form; photons carry flux, so no η² scaling.
                s.kind = ReferenceScatter::Refracted;
                const float cosT = std::sqrt(std::max(0.0f, 1.0f - eta * eta * (1.0f - cosI * cosI)));
                s.direction = d * eta + nf * (eta * cosI - cosT);
            }
            break;
        }
    }
    return s;
}

}  // namespace

// ---- Step 2 of the spec: Russian roulette on a mixed surface, then the new direction --------
ReferenceScatter scatterPhotonReference(const PclMaterial& m, Vec3 d, Vec3 n, Vec3 power, const float u[4]) {
    return scatterPhotonReference(m, d, n, n, power, u);
}

ReferenceScatter scatterPhotonReference(const PclMaterial& m, Vec3 d, Vec3 n, Vec3 ns, Vec3 power, const float u[4]) {
    ReferenceScatter s = scatterInShadingFrame(m, d, n, ns, power, u);
    const bool moved = s.kind != ReferenceScatter::Absorbed && s.kind != ReferenceScatter::GlossyBelow;
    if (!moved || !eyeIsSmooth(ns, n)) return s;
    const float side = dot(s.direction, n) * dot(d, n);  // > 0: through the surface
    if (s.kind == ReferenceScatter::Refracted ? !(side > 0.0f) : !(side < 0.0f)) {
        s.kind = ReferenceScatter::WrongSide;
        s.power = Vec3(0.0f);
        return s;
    }
    auto v3 = [](Vec3 v) { return sampling_v3(v.x, v.y, v.z); };
    s.power = s.power * shading_adjoint(v3(ns), v3(n), v3(-d), v3(s.direction));
    return s;
}

// ---- The photon record ------------------------------------------------------------------
uint32_t referenceEncodeRgbe(Vec3 power) {
    const float v = maxComponent(power);
    if (v < 1e-32f) return 0u;
    int e;
    const float m = std::frexp(v, &e);
    const float scale = m * 256.0f / v;
    auto byte = [&](float c) { return std::min(255u, static_cast<uint32_t>(std::floor(c * scale + 0.5f))); };
    return byte(power.x) | byte(power.y) << 8 | byte(power.z) << 16 | uint32_t(e + 128) << 24;
}

Vec3 referenceDecodeRgbe(uint32_t rgbe) {
    const uint32_t E = rgbe >> 24;
    if (rgbe == 0u) return Vec3(0.0f);
    const float f = std::ldexp(1.0f, int(E) - 136);
    return Vec3(float(rgbe & 255u), float((rgbe >> 8) & 255u), float((rgbe >> 16) & 255u)) * f;
}

uint32_t referenceEncodeDirection(Vec3 w) {
    const float theta = std::acos(std::min(1.0f, std::max(-1.0f, w.z)));
    const uint32_t tb = std::min(255u, static_cast<uint32_t>(std::floor(theta * (256.0f / kPi))));
    const int32_t pb = static_cast<int32_t>(std::floor(std::atan2(w.y, w.x) * (128.0f / kPi)));
    return tb | (static_cast<uint32_t>(pb) & 255u) << 8;
}

uint32_t referenceEncodeNormal(Vec3 n) {
    const float s = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
    float u = s > 0.0f ? n.x / s : 0.0f, v = s > 0.0f ? n.y / s : 0.0f;
    if (n.z < 0.0f) {  // fold the lower hemisphere over the octahedron's edges
        const float fu = (1.0f - std::fabs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
        v = (1.0f - std::fabs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
        u = fu;
    }
    auto snorm16 = [](float c) {
        const float q = std::floor(std::min(1.0f, std::max(-1.0f, c)) * 32767.0f + 0.5f);
        return static_cast<uint32_t>(static_cast<int32_t>(q)) & 0xFFFFu;
    };
    return snorm16(u) | snorm16(v) << 16;
}

// ---- One path ---------------------------------------------------------------------------
uint32_t tracePhotonPathReference(const SceneBuffers& buffers, const SceneGeometry& geometry,
                                  const PclPhotonParams& params, const PclPhotonRay& ray, uint32_t i, PclPhoton* slots,
                                  uint32_t& count, std::vector<ReferencePhotonHit>* hits, PclPhoton* volumeSlots,
                                  uint32_t* volumeCount) {
    const bool caustic = params.pass == PCL_PASS_CAUSTIC;
    const uint64_t seed = uint64_t(params.seedLo) | (uint64_t(params.seedHi) << 32);
    const uint32_t j = params.firstPhoton + i;
    const uint32_t stream = caustic ? PCL_RNG_STREAM_CAUSTIC : PCL_RNG_STREAM_PHOTON;
    const float time = ray.time;

    Vec3 o{ray.ox, ray.oy, ray.oz}, d{ray.dx, ray.dy, ray.dz};
    Vec3 power{ray.power[0], ray.power[1], ray.power[2]};
    uint32_t flags = 0;  // AFTER_SPECULAR / AFTER_DIFFUSE: the path so far
    count = 0;
    uint32_t volumes = 0;
    if (volumeCount) *volumeCount = 0;
    int32_t mediumId = params.hasMedia ? buffers.lightMedia[ray.light] : PCL_NO_MEDIUM;
    uint32_t segment = 0;  // invisible boundaries crossed within this bounce: the random block 1 + segment
    if (mediumId == PCL_MEDIUM_UNREACHABLE) return 1 | PCL_END_ABSORBED << 8;  // a directional light in fog

    auto deposit = [&](Vec3 p, Vec3 nf, uint32_t b, uint32_t extra) {
        PclPhoton& ph = slots[count++];
        ph.x = p.x;
        ph.y = p.y;
        ph.z = p.z;
        ph.rgbe = referenceEncodeRgbe(power);
        ph.packed = referenceEncodeDirection(-d) | (b - 1) << PCL_PHOTON_BOUNCE_SHIFT | flags | extra;
        ph.normal = referenceEncodeNormal(nf);
    };

    for (uint32_t b = 1;;) {
        PclRay r{};
        r.ox = o.x;
        r.oy = o.y;
        r.oz = o.z;
        r.tmin = 0.0f;
        r.dx = d.x;
        r.dy = d.y;
        r.dz = d.z;
        r.tmax = INFINITY;
        r.time = time;
        PclHit hit;
        const bool found = geometry.intersect(r, hit);
        if (mediumId != PCL_NO_MEDIUM) {
            // A free flight through the medium: a scattering event before the surface, or the
            // transmittance weight up to it (reference/medium.h, spectral MIS by power).
            const PclMedium& pm = buffers.media[size_t(mediumId)];
            Medium medium;
            medium.sigmaA = vec(pm.sigmaA);
            medium.sigmaS = vec(pm.sigmaS);
            medium.g = pm.g;
            uint32_t v[4];
            rng_block(seed, j, b, 1 + segment, stream, v);
            const FreeFlight flight =
                sampleFreeFlight(medium, found ? hit.t : INFINITY, rng_u01(v[0]), rng_u01(v[1]), power);
            if (flight.scattered) {
                const Vec3 x = o + d * flight.t;
                const Vec3 scattered = power * flight.weight;  // ΔΦ: the power scattered at x
                const bool store = caustic ? (flags & PCL_PHOTON_AFTER_SPECULAR) && !(flags & PCL_PHOTON_AFTER_DIFFUSE)
                                           : params.storeGlobal != 0;
                if (store) {
                    if (volumeSlots) {
                        PclPhoton& ph = volumeSlots[volumes];
                        ph.x = x.x;
                        ph.y = x.y;
                        ph.z = x.z;
                        ph.rgbe = referenceEncodeRgbe(scattered);
                        ph.packed = referenceEncodeDirection(-d) | (b - 1) << PCL_PHOTON_BOUNCE_SHIFT | flags |
                                    PCL_PHOTON_VOLUME | (caustic ? PCL_PHOTON_CAUSTIC : 0u);
                        ph.normal = 0;
                    }
                    ++volumes;
                    if (volumeCount) *volumeCount = volumes;
                }
                // The caustic pass keeps L S+ V and nothing past a medium event.
                if (caustic) return b | (store ? PCL_END_STORED : PCL_END_ABSORBED) << 8;
                // Roulette on the scattered share: q = the single-scattering albedo when grey.
                const float q =
                    std::min(1.0f, maxComponent(power) > 0.0f ? maxComponent(scattered) / maxComponent(power) : 0.0f);
                rng_block(seed, j, b, 0, stream, v);  // block 0: no surface event at this bounce
                if (!(rng_u01(v[0]) < q)) return b | PCL_END_ABSORBED << 8;
                power = scattered / Vec3(q);
                flags |= PCL_PHOTON_AFTER_DIFFUSE;
                if (b >= params.maxDepth) return b | PCL_END_MAX_DEPTH << 8;
                d = sampleHenyeyGreenstein(-d, medium.g, rng_u01(v[2]), rng_u01(v[3]));
                o = x;
                segment = 0;
                ++b;
                continue;
            }
            power = power * flight.weight;
            if (!(maxComponent(power) > 0.0f)) return b | (found ? PCL_END_ABSORBED : PCL_END_ESCAPED) << 8;
        }
        if (!found) return b | PCL_END_ESCAPED << 8;

        const Vec3 p = o + d * hit.t;
        const PclPrimInfo& info = buffers.primInfo[hit.prim];
        const Vec3 n = hit.prim < params.triangleCount
                           ? Vec3(info.a, info.b, info.c)
                           : (p - (Vec3(info.a, info.b, info.c) + Vec3(info.mx, info.my, info.mz) * time)) /
                                 info.radius;
        const PclMaterial m = texturedMaterial(buffers, params.triangleCount, hit);  // ρd at the hit
        const Vec3 nf = dot(d, n) < 0.0f ? n : -n;                                   // the side the photon arrives on
        if (params.hasMedia) {
            if (m.flags & PCL_MATERIAL_INTERFACE) {
                // An invisible medium boundary: straight on in the medium beyond, same bounce.
                const PclPrimMedium& sides = buffers.primMedia[hit.prim];
                mediumId = dot(d, n) < 0.0f ? sides.inside : sides.outside;
                o = p - nf * params.rayEpsilon;
                if (++segment >= PCL_MAX_SEGMENTS) return b | PCL_END_MAX_DEPTH << 8;
                continue;
            }
            segment = 0;
        }

        // 1. Deposit at a diffuse surface: global map L(S|D)*D, caustic map LS+D. A caustic
        //    path is only ever specular so far (it stops at its first diffuse bounce), so LS+D
        //    means: not the first hit. It then meets roulette like any other path: the specular
        //    part of a mixed surface carries it on.
        bool depositedHere = false;
        if (maxComponent(vec(m.rhoD)) > 0.0f) {
            if (!caustic) {
                // The global map keeps a moving surface's photons where it sits at shutter open.
                if (params.storeGlobal) deposit(shutterOpenPosition(info, p, time), nf, b, 0u);
            } else if (b > 1 && !(flags & PCL_PHOTON_AFTER_DIFFUSE)) {
                deposit(p, nf, b, PCL_PHOTON_CAUSTIC);
                depositedHere = true;
            }
        }

        // 2. Russian roulette and the bounce, from the numbers of bounce b.
        uint32_t w[4];
        rng_block(seed, j, b, 0, stream, w);
        const float u[4] = {rng_u01(w[0]), rng_u01(w[1]), rng_u01(w[2]), rng_u01(w[3])};
        const Vec3 ns = eyeShadingNormal(buffers, params.triangleCount, hit, n);  // the scattering frame
        const ReferenceScatter s = scatterPhotonReference(m, d, n, ns, power, u);
        if (hits) hits->push_back({b, s.kind, s.pDiffuse, s.pSpecular, power, s.power, hit.prim, p, d, n, s.direction});
        // A caustic path ending here: STORED when this hit deposited, else ABSORBED.
        const uint32_t endHere = depositedHere ? PCL_END_STORED : PCL_END_ABSORBED;
        if (s.kind == ReferenceScatter::Absorbed || s.kind == ReferenceScatter::GlossyBelow ||
            s.kind == ReferenceScatter::WrongSide)
            return b | endHere << 8;
        if (caustic && s.kind == ReferenceScatter::Diffuse) return b | endHere << 8;  // no longer LS+D
        flags |= s.kind == ReferenceScatter::Diffuse ? PCL_PHOTON_AFTER_DIFFUSE : PCL_PHOTON_AFTER_SPECULAR;
        power = s.power;
        if (b >= params.maxDepth) return b | PCL_END_MAX_DEPTH << 8;

        // Through the surface (refraction): the medium on the other side.
        if (params.hasMedia && dot(s.direction, n) * dot(d, n) > 0.0f) {
            const PclPrimMedium& sides = buffers.primMedia[hit.prim];
            mediumId = dot(d, n) < 0.0f ? sides.inside : sides.outside;
        }

        // 3. Spawn on the side the new direction leaves from.
        const Vec3 side = dot(s.direction, nf) > 0.0f ? nf : -nf;
        o = p + side * params.rayEpsilon;
        d = s.direction;
        ++b;
    }
}

ReferencePhotonBatch tracePhotonsReference(const SceneBuffers& buffers, const SceneGeometry& geometry,
                                           const PclPhotonParams& params, const std::vector<PclPhotonRay>& rays,
                                           unsigned threads) {
    ReferencePhotonBatch out;
    const size_t n = std::min<size_t>(params.batchSize, rays.size());
    out.slotsPerPath = params.maxDepth;  // one record per hit at most, in either pass
    out.slots.assign(n * out.slotsPerPath, PclPhoton{});
    out.counts.assign(n, 0u);
    out.ends.assign(n, 0u);
    if (params.hasMedia) {
        out.volumeSlots.assign(n * out.slotsPerPath, PclPhoton{});
        out.volumeCounts.assign(n, 0u);
    }
    referenceParallelFor(n, threads, [&](size_t i) {
        out.ends[i] = tracePhotonPathReference(buffers, geometry, params, rays[i], static_cast<uint32_t>(i),
                                               &out.slots[i * out.slotsPerPath], out.counts[i], nullptr,
                                               params.hasMedia ? &out.volumeSlots[i * out.slotsPerPath] : nullptr,
                                               params.hasMedia ? &out.volumeCounts[i] : nullptr);
    });
    return out;
}

}  // namespace pcl
