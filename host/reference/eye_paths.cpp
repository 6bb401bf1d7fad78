#include "reference/eye_paths.h"

#include <cmath>
#include <limits>

#include "reference/eye_scatter.h"
#include "reference/parallel_for.h"
#include "reference/sampler.h"

namespace pcl {

PclEyeHit referenceEyePath(const SceneGeometry& geometry, const SceneBuffers& buffers, const PclEyeParams& params,
                           const PclRay& ray, uint32_t i) {
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
    for (uint32_t v = 0; v < params.maxDepth; ++v) {
        PclHit hit;
        if (!geometry.intersect(eyeRay(o, d, std::numeric_limits<float>::infinity(), ray.time), hit)) break;
        const Vec3 p = o + d * hit.t;
        const Vec3 n = eyeNormalAt(buffers, hit.prim, params.triangleCount, p, ray.time);
        const float dn = dot(d, n);
        const Vec3 nf = dn < 0.0f ? n : -n;
        const uint32_t mat = buffers.primInfo[hit.prim].material;
        const PclMaterial& m = buffers.materials[mat];
        if (dn < 0.0f) Le = Le + T * eyeVec(m.emission);
        const float pd = eyeDiffuseProbability(m);
        if (pd < 0.0f) break;
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
    std::vector<PclEyeHit> out(rays.size());
    parallelForEveryThread(rays.size(), [&](size_t i) {
        out[i] = referenceEyePath(geometry, buffers, params, rays[i], uint32_t(i));
    });
    return out;
}

}  // namespace pcl
