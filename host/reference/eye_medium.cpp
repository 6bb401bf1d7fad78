#include "reference/eye_medium.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/eye_scatter.h"
#include "reference/medium.h"

namespace pcl {

Vec3 eyeMediumTransmittance(const PclMedium& m, float len) {
    return transmittance(eyeVec(m.sigmaA) + eyeVec(m.sigmaS), len);
}

Vec3 eyeShadowTransmittance(const SceneGeometry& geometry, const SceneBuffers& buffers, bool hasMedia, int32_t medium,
                            Vec3 o, Vec3 dir, float tmax, float tau) {
    if (!hasMedia) return geometry.occluded(eyeRay(o, dir, tmax, tau)) ? Vec3(0.0f) : Vec3(1.0f);
    Vec3 tr(1.0f);
    const float len = std::sqrt(dot(dir, dir));
    for (uint32_t crossing = 0; crossing < PCL_MAX_SEGMENTS; ++crossing) {
        PclHit hit;
        const bool found = geometry.intersect(eyeRay(o, dir, tmax, tau), hit);
        const float end = found ? hit.t : tmax;
        if (medium >= 0) tr = tr * eyeMediumTransmittance(buffers.media[size_t(medium)], end * len);
        if (!found) return tr;
        if (!(buffers.materials[buffers.primInfo[hit.prim].material].flags & PCL_MATERIAL_INTERFACE)) break;
        const Vec3 p = o + dir * hit.t;
        const Vec3 n = eyeNormalAt(buffers, hit.prim, geometry.triangleCount(), p, tau);
        const float dn = dot(dir, n);
        medium = dn < 0.0f ? buffers.primMedia[hit.prim].inside : buffers.primMedia[hit.prim].outside;
        const Vec3 nf = dn < 0.0f ? n : -n;
        o = p + nf * -buffers.rayEpsilon;
        tmax = tmax - hit.t;
        if (!(tmax > 0.0f)) return tr;
    }
    return Vec3(0.0f);
}

bool eyeEquiangular(Vec3 o, Vec3 d, Vec3 c, float tEnd, float u, float& t, float& pdf) {
    const float delta = dot(c - o, d);
    const Vec3 foot = o + d * delta - c;
    const float D = std::sqrt(dot(foot, foot));
    if (!(D > 0.0f)) return false;
    const float thetaA = std::atan2(-delta, D);
    const float thetaB = tEnd < std::numeric_limits<float>::infinity() ? std::atan2(tEnd - delta, D) : 0.5f * kPi;
    const float range = thetaB - thetaA;
    if (!(range > 0.0f)) return false;
    const float x = D * std::tan(thetaA + u * range);
    t = std::clamp(delta + x, 0.0f, tEnd);
    pdf = D / (range * (D * D + x * x));
    return pdf > 0.0f && std::isfinite(t);
}

float eyeSphereExit(Vec3 o, Vec3 d, Vec3 centre, float radius) {
    const Vec3 oc = o - centre;
    const float b = dot(oc, d);
    const float disc = b * b - (dot(oc, oc) - radius * radius);
    if (!(disc > 0.0f)) return 0.0f;
    const float t = -b + std::sqrt(disc);
    return t > 0.0f ? t : 0.0f;
}

}  // namespace pcl
