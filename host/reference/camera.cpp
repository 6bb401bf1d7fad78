#include "reference/camera.h"

#include <cmath>
#include <limits>

#include "reference/sampling.h"

namespace pcl {

RayCamera::RayCamera(const Camera& camera) : camera_(camera) {
    forward_ = normalize(camera.lookAt - camera.position);
    right_ = normalize(cross(forward_, camera.up));
    up_ = cross(right_, forward_);
    tanHalfHeight_ = std::tan(0.5f * camera.vfovDegrees * kPi / 180.0f);
    tanHalfWidth_ = tanHalfHeight_ * static_cast<float>(camera.width) / static_cast<float>(camera.height);
    shutterOpen_ = camera.shutterClose > camera.shutterOpen;
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
    PclRay ray{};
    ray.ox = origin.x;
    ray.oy = origin.y;
    ray.oz = origin.z;
    ray.dx = dir.x;
    ray.dy = dir.y;
    ray.dz = dir.z;
    ray.tmin = 0.0f;
    ray.tmax = std::numeric_limits<float>::infinity();
    ray.time = shutterOpen_ ? s.time : 0.0f;
    return ray;
}

}  // namespace pcl
