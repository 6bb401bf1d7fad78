#include "reference/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/sampling.h"
#include "reference/surface.h"

namespace pcl {

RayCamera::RayCamera(const Camera& camera) : camera_(camera) {
    forward_ = normalize(camera.lookAt - camera.position);
    right_ = normalize(cross(forward_, camera.up));
    up_ = cross(right_, forward_);
    tanHalfHeight_ = std::tan(0.5f * camera.vfovDegrees * kPi / 180.0f);
    tanHalfWidth_ = tanHalfHeight_ * static_cast<float>(camera.width) / static_cast<float>(camera.height);
    shutterOpen_ = camera.shutterClose > camera.shutterOpen;
    pixelArea_ = (2.0f * tanHalfWidth_ / static_cast<float>(camera.width)) *
                 (2.0f * tanHalfHeight_ / static_cast<float>(camera.height));
}

bool RayCamera::connect(Vec3 p, float lensU, float lensV, CameraConnection& out) const {
    Vec3 lens = camera_.position;
    const bool thinLens = camera_.model == CameraModel::ThinLens && camera_.apertureRadius > 0.0f;
    if (thinLens) {
        float lx, ly;
        sampleConcentricDisk(lensU, lensV, lx, ly);
        lens = lens + (right_ * lx + up_ * ly) * camera_.apertureRadius;
    }
    Vec3 d = p - lens;
    float dist2 = dot(d, d);
    float z = dot(d, forward_);
    if (!(dist2 > 0.0f) || !(z > 0.0f)) return false;
    // The film point whose ray through this lens point heads for p: the pinhole ray toward the
    // point where the line lens → p crosses the plane of focus (generateRay in reverse; for a
    // pinhole the line's own direction).
    Vec3 v = thinLens ? (lens - camera_.position) + d * (camera_.focusDistance / z) : d;
    float vz = dot(v, forward_);
    if (!(vz > 0.0f)) return false;
    float sx = dot(v, right_) / vz, sy = dot(v, up_) / vz;
    float fx = 0.5f * (sx / tanHalfWidth_ + 1.0f) * static_cast<float>(camera_.width);
    float fy = 0.5f * (1.0f - sy / tanHalfHeight_) * static_cast<float>(camera_.height);
    if (!(fx >= 0.0f && fx < static_cast<float>(camera_.width) && fy >= 0.0f &&
          fy < static_cast<float>(camera_.height)))
        return false;
    out.x = std::min(static_cast<int>(fx), camera_.width - 1);
    out.y = std::min(static_cast<int>(fy), camera_.height - 1);
    out.lensPoint = lens;
    float cosTheta = z / std::sqrt(dist2);
    out.importance = 1.0f / (pixelArea_ * cosTheta * cosTheta * cosTheta * dist2);
    return true;
}

PclRay RayCamera::generateRay(int x, int y, const CameraSample& s) const {
    // Film point on the plane at distance 1 in front of the pinhole.
    float sx = (2.0f * (static_cast<float>(x) + s.filmX) / static_cast<float>(camera_.width) - 1.0f) * tanHalfWidth_;
    float sy = (1.0f - 2.0f * (static_cast<float>(y) + s.filmY) / static_cast<float>(camera_.height)) * tanHalfHeight_;
    Vec3 dir = normalize(forward_ + right_ * sx + up_ * sy);
    Vec3 origin = camera_.position;
    if (camera_.model == CameraModel::ThinLens && camera_.apertureRadius > 0.0f) {
        // Thin lens: every ray through the lens point reaches the same point on the plane of
        // focus (perpendicular to the view axis at focusDistance) as the pinhole ray does.
        float lx, ly;
        sampleConcentricDisk(s.lensU, s.lensV, lx, ly);
        Vec3 focus = origin + dir * (camera_.focusDistance / dot(dir, forward_));
        origin = origin + (right_ * lx + up_ * ly) * camera_.apertureRadius;
        dir = normalize(focus - origin);
    }
    PclRay ray = makeRay(origin, dir, shutterOpen_ ? s.time : 0.0f);
    return ray;
}

}  // namespace pcl
