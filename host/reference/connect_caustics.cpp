#include "reference/connect_caustics.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/math.h"
#include "reference/camera.h"
#include "reference/parallel_for.h"
#include "reference/precomputed_irradiance.h"
#include "reference/sampler.h"
#include "reference/surface.h"
#include "reference/trace_photons.h"

namespace pcl {
namespace {

// The centre of the record's (θ, φ) byte cell (kernels/README.md, photon record).
Vec3 decodeDirection(uint32_t packed) {
    const float theta = (float(packed & 255u) + 0.5f) * (kPi / 256.0f);
    const uint32_t pb = (packed >> 8) & 255u;
    const float phi = (float(pb >= 128u ? int(pb) - 256 : int(pb)) + 0.5f) * (kPi / 128.0f);
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

PclSplat connect(const Scene& scene, const SceneGeometry& geometry, const RayCamera& rc, int width,
                 const PclConnectParams& params, uint64_t seed, uint32_t i, const PclPhoton& ph, float time) {
    PclSplat none{PCL_NO_SPLAT, 0.0f, 0.0f, 0.0f};
    const Vec3 p(ph.x, ph.y, ph.z);
    float nv[3];
    referenceDecodeNormal(ph.normal, nv);
    const Vec3 nf(nv[0], nv[1], nv[2]);
    const float h = params.findDistance;
    const PclRay find = makeRay(p + nf * h, -nf, time, 2.0f * h);
    PclHit hit;
    if (!geometry.intersect(find, hit)) return none;
    const SurfacePoint s = surfaceAt(scene, geometry, find, hit);
    const bool flip = dot(s.ng, nf) < 0.0f;
    const Vec3 ng = flip ? -s.ng : s.ng, ns = flip ? -s.ns : s.ns;

    Sampler sampler(seed, i, 0, PCL_RNG_STREAM_CONNECT);
    CameraConnection c;
    if (!rc.connect(p, sampler.get(0), sampler.get(1), c)) return none;
    const Vec3 wc = normalize(c.lensPoint - p), wi = decodeDirection(ph.packed);
    const float cosCamG = dot(wc, ng), cosCamS = dot(wc, ns);
    if (!(cosCamG > 0.0f) || !(cosCamS > 0.0f)) return none;
    // Light tracing's adjoint shading-normal factor times the cosine at the camera side.
    float g = cosCamG;
    if (dot(ns, ng) < 1.0f - 1e-6f) {
        const float cosInS = dot(wi, ns), cosInG = dot(wi, ng);
        if (!(cosInS > 0.0f) || !(cosInG > 0.0f)) return none;
        g = cosInS * cosCamG / cosInG;
    }
    if (geometry.occluded(spawnShadowRay(p, nf, c.lensPoint, Vec3(0.0f), time))) return none;
    const Vec3 v = referenceDecodeRgbe(ph.rgbe) * s.rhoD * (g * c.importance / kPi);
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || !(maxComponent(v) > 0.0f)) return none;
    return {uint32_t(c.y) * uint32_t(width) + uint32_t(c.x), v.x, v.y, v.z};
}

}  // namespace

std::vector<PclSplat> referenceConnectCaustics(const Scene& scene, const SceneGeometry& geometry,
                                               const PclConnectParams& params, const PclCameraParams& camera,
                                               const std::vector<PclPhoton>& photons, const std::vector<float>& times) {
    if (params.hasTimes && times.size() != photons.size())
        throw InternalError("connect caustics (twin): " + std::to_string(times.size()) + " times for " +
                            std::to_string(photons.size()) + " records");
    Camera cam = scene.camera;
    cam.width = int(camera.width);
    cam.height = int(camera.height);
    if (!camera.lensSampling) cam.model = CameraModel::Pinhole;
    const RayCamera rc(cam);
    const uint64_t passSeed = uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32;
    std::vector<PclSplat> splats(photons.size());
    parallelForEveryThread(photons.size(), [&](size_t i) {
        splats[i] = connect(scene, geometry, rc, cam.width, params, passSeed, uint32_t(i), photons[i],
                            params.hasTimes ? times[i] : 0.0f);
    });
    return splats;
}

}  // namespace pcl
