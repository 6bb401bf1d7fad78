#include "reference/eye_paths.h"

#include <cmath>
#include <limits>

#include "reference/eye_scatter.h"
#include "reference/light_sample.h"
#include "reference/parallel_for.h"
#include "reference/sampler.h"

namespace pcl {

PclEyeHit referenceEyePath(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                           const PclEyeParams& params, const PclRay& ray, uint32_t i) {
    const uint32_t s = params.firstSample + i;
    const uint32_t pixel = s / params.samplesPerPixel, k = s % params.samplesPerPixel;
    Sampler sampler(uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32, pixel, k);
    PclEyeHit h{};
    h.time = ray.time;
    h.prim = PCL_NO_HIT;
    h.pixel = pixel;
    h.sample = k;
    Vec3 o(ray.ox, ray.oy, ray.oz), d(ray.dx, ray.dy, ray.dz);
    Vec3 T(1.0f), Le(0.0f);
    float pdfLobe = 0.0f;  // the density with which the last hit's glossy lobe chose d; 0 if not glossy
    for (uint32_t v = 0; v < params.maxDepth; ++v) {
        PclHit hit;
        if (!geometry.intersect(eyeRay(o, d, std::numeric_limits<float>::infinity(), ray.time), hit)) break;
        const Vec3 p = o + d * hit.t;
        const Vec3 n = eyeNormalAt(buffers, hit.prim, params.triangleCount, p, ray.time);
        const float dn = dot(d, n);
        const Vec3 nf = dn < 0.0f ? n : -n;
        const uint32_t mat = buffers.primInfo[hit.prim].material;
        const PclMaterial& m = buffers.materials[mat];
        if (dn < 0.0f) {  // a triangle light found by a glossy lobe: MIS with that hit's light sample
            float wE = 1.0f;
            const uint32_t l = table.lightOfPrim[hit.prim];
            if (pdfLobe > 0.0f && l != PCL_NO_HIT && params.areaPowerTotal > 0.0f)
                wE = eyeMisWeight(1, pdfLobe, 1,
                                  eyeAreaLightPdf(buffers.lights[l], params.areaPowerTotal, d, hit.t * hit.t));
            Le = Le + T * eyeVec(m.emission) * wE;
        }
        const float pd = eyeDiffuseProbability(m);
        if (pd < 0.0f) break;
        if (m.specular == PCL_SPECULAR_GLOSSY && params.lightCount > 0) {  // direct light through the lobe
            const Vec3 lifted = p + nf * buffers.rayEpsilon;
            const float e = m.exponent;
            Vec3 sum(0.0f);
            for (uint32_t l = 0; l < params.lightCount; ++l) {
                const PclLight& L = buffers.lights[l];
                if (L.type == PCL_LIGHT_TRIANGLE) continue;
                Vec3 wi;
                const float g = lightDelta(geometry, L, p, nf, lifted, ray.time, wi);
                if (g > 0.0f) sum = sum + eyeVec(L.power) * (g * eyePhongCosPower(d, nf, wi, e));
            }
            Vec3 wi, le;
            float pdfL, cosS;
            if (params.areaPowerTotal > 0.0f &&
                lightAreaSample(geometry, buffers, table, params.lightCount, params.areaPowerTotal, p, nf, lifted,
                                buffers.rayEpsilon, ray.time, sampler.vertex(v, PathVertexDims::kLightSelect),
                                sampler.vertex(v, PathVertexDims::kLightPoint),
                                sampler.vertex(v, PathVertexDims::kLightPoint + 1), wi, pdfL, cosS, le)) {
                const float cp = eyePhongCosPower(d, nf, wi, e);
                const float pdfB = (1.0f - pd) * ((e + 1.0f) / (2.0f * kPi)) * cp;
                sum = sum + le * (cp * cosS * eyeMisWeight(1, pdfL, 1, pdfB) / pdfL);
            }
            const float norm = (e + 2.0f) / (2.0f * kPi);
            Le = Le + T * eyeVec(m.rhoS) * Vec3(norm) * sum;
        }
        if (sampler.vertex(v, PathVertexDims::kLobe) < pd) {
            h.x = p.x;
            h.y = p.y;
            h.z = p.z;
            h.nx = nf.x;
            h.ny = nf.y;
            h.nz = nf.z;
            h.prim = hit.prim;
            h.wox = -d.x;
            h.woy = -d.y;
            h.woz = -d.z;
            const Vec3 t = T / Vec3(pd);
            h.throughput[0] = t.x;
            h.throughput[1] = t.y;
            h.throughput[2] = t.z;
            for (int c = 0; c < 3; ++c) h.albedo[c] = m.rhoD[c];
            h.material = mat;
            h.depth = v;
            h.flags = PCL_EYE_DIFFUSE;
            break;
        }
        Vec3 dNew, w;
        if (!eyeSpecularScatter(m, d, n, sampler.vertex(v, 7), sampler.vertex(v, PathVertexDims::kDirection),
                                sampler.vertex(v, PathVertexDims::kDirection + 1), dNew, w))
            break;
        T = T * w / Vec3(1.0f - pd);
        pdfLobe = m.specular == PCL_SPECULAR_GLOSSY
                      ? (1.0f - pd) * ((m.exponent + 1.0f) / (2.0f * kPi)) * eyePhongCosPower(d, nf, dNew, m.exponent)
                      : 0.0f;
        o = p + nf * (dot(dNew, nf) > 0.0f ? buffers.rayEpsilon : -buffers.rayEpsilon);
        d = dNew;
    }
    h.emitted[0] = Le.x;
    h.emitted[1] = Le.y;
    h.emitted[2] = Le.z;
    bool finite = true;
    for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(h.throughput[c]) && std::isfinite(h.emitted[c]);
    if (!finite) {
        for (int c = 0; c < 4; ++c) h.throughput[c] = h.emitted[c] = 0.0f;
        h.prim = PCL_NO_HIT;
        h.flags = 0;
    }
    return h;
}

std::vector<PclEyeHit> referenceEyePaths(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                         const std::vector<PclRay>& rays, const PclEyeParams& params) {
    const AreaLightTable table = buildAreaLightTable(buffers, geometry.primitiveCount());
    std::vector<PclEyeHit> out(rays.size());
    parallelForEveryThread(rays.size(), [&](size_t i) {
        out[i] = referenceEyePath(geometry, buffers, table, params, rays[i], uint32_t(i));
    });
    return out;
}

}  // namespace pcl
