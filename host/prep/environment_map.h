// The environment light ("sky", scene.h Environment) as the renderers read it: radiance by
// direction, and directions sampled in proportion to it.
//
// Mapping (Mitsuba 3's envmap, so the same file means the same sky there): a direction w in the
// environment's own frame (the world turned back by rotationDegrees about +y) falls in texel
//   u = atan2(w.x, −w.z) / 2π  (wrapped to [0, 1)),   v = acos(w.y) / π  (row 0 looks up),
// and its radiance is scale × that texel: nearest texel, so the sky is constant over each texel.
// That makes exact importance sampling simple: choose a texel by its share of ∫ L dω (its
// luminance Y (Rec. 709) times its solid angle (2π/W)(cos θ0 − cos θ1)), then a direction uniformly
// in its solid angle (φ uniform, cos θ uniform): the density is exactly proportional to the
// texel's luminance. A constant sky is one texel covering the sphere: uniform directions.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace pcl {

class EnvironmentMap {
public:
    EnvironmentMap() = default;
    explicit EnvironmentMap(const Environment& environment);

    bool active() const { return !rowCdf_.empty(); }

    // Radiance arriving from direction w (unit, pointing toward the sky).
    Vec3 radiance(Vec3 w) const;
    // A direction toward the sky from two uniform numbers, and its solid-angle density; false
    // only for an inactive map.
    bool sample(float u1, float u2, Vec3& w, float& pdf) const;
    // The density sample() gives direction w.
    float pdf(Vec3 w) const;
    // ∫ L dω over the sphere, per channel (4π L for a constant sky).
    Vec3 integral() const { return integral_; }
    // (∫ Y dω)² / ∫ Y² dω in sr, Y the luminance: how much of the sphere the sky's light is spread
    // over (4π for a constant sky, about a sun's solid angle when a sun dominates); 0 inactive.
    double effectiveSolidAngle() const { return effectiveSolidAngle_; }

private:
    Vec3 toLocal(Vec3 w) const;
    Vec3 toWorld(Vec3 w) const;
    void texelOf(Vec3 local, int& x, int& y) const;
    Vec3 texel(int x, int y) const;
    float rowSolidAngle(int y) const;

    Vec3 scale_{0.0f};
    const Image* image_ = nullptr;  // null: constant
    int width_ = 1, height_ = 1;
    float cosRot_ = 1.0f, sinRot_ = 0.0f;
    std::vector<double> rowCdf_;     // height + 1 entries, 0 .. 1
    std::vector<double> columnCdf_;  // per row, width + 1 entries, 0 .. 1
    std::vector<float> texelProbability_;
    Vec3 integral_{0.0f};
    double effectiveSolidAngle_ = 0.0;
};

// A sky whose light is spread over at least this solid angle (EnvironmentMap::
// effectiveSolidAngle, sr) is found well by rays from the eye side, through specular surfaces
// too: with PlanSettings::skyCaustics false it sends no caustic photons (LightPaths::skySpread,
// RenderPlan::skyCausticPhotons). A sky whose sun holds its light (the courtyard's: its caustic
// through the glass ball is a firefly to a gather ray) keeps them.
constexpr double kSpreadSkySolidAngle = 1.0;
bool skyCausticsByEyeRays(const Scene& scene);

// The photon methods and the device stages read the sky (its photons, eye rays that escape,
// direct light by its map: kernels/shared/environment.h) but do not carry it through
// participating media: they refuse a scene with both instead of rendering it wrong.
// Throws InputError "SCENE: environment: expected a scene without an environment light or
// without participating media for WHAT (...), got ..." when scene.environment is active and
// the scene has a medium.
void refuseEnvironmentInMediaWithoutPathTracer(const Scene& scene, const std::string& what);

}  // namespace pcl
