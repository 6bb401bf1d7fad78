// Light sampling for next-event estimation. Every emitting surface is a light — each triangle
// of an emissive mesh (area lights) and each emissive sphere — sampled uniformly by area; point,
// spot and directional lights are delta lights; the sky (scene.environment) is one more emitter,
// sampled by its map (prep/environment_map.h). One light is chosen per sample with probability
// proportional to an estimate of its power (any positive choice stays unbiased; power keeps
// the variance low): a triangle with an emission texture by π A times the estimate of its mean
// radiance (prep/emission_texture.h), its point then uniform with the texture's radiance there. Emission is one-sided: radiance leaves the geometric-normal side only.
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/environment_map.h"
#include "reference/surface.h"
#include "scene/scene.h"

namespace pcl {

struct LightSample {
    Vec3 Li;            // incident radiance (area) or I/r², E (delta lights), before the BSDF
    Vec3 wi;            // unit direction from the shading point toward the light
    Vec3 point;         // the point on the light (unused for directional lights)
    Vec3 normal{0.0f};  // the light's surface normal there (zero for delta lights)
    float pdf = 0.0f;   // solid-angle density incl. the light choice; delta lights: the choice probability
    bool delta = false;
    bool infinite = false;  // directional: the shadow ray runs to infinity
    size_t emitter = 0;     // which emitter (LightSampler's index) the sample came from
};

class LightSampler {
public:
    LightSampler(const Scene& scene, const SceneGeometry& geometry);

    bool empty() const { return emitters_.empty(); }
    size_t count() const { return emitters_.size(); }

    // Samples a light as seen from p at shutter time `time`; false if nothing reaches p
    // (the back of a one-sided emitter, outside a spot cone, no lights).
    bool sampleLi(Vec3 p, float time, float uSelect, float u1, float u2, LightSample& out) const;

    // The same from a given emitter (no choice: out.pdf is the emitter's choice probability times
    // the point's density, as sampleLi would report it).
    bool sampleLiFrom(size_t emitter, Vec3 p, float time, float u1, float u2, LightSample& out) const;

    // Point and spot lights: the ones with one position (equiangular sampling in media aims at it).
    bool isPositional(size_t emitter) const {
        return emitters_[emitter].kind == Kind::Point || emitters_[emitter].kind == Kind::Spot;
    }
    float probability(size_t emitter) const { return probability_[emitter]; }
    Vec3 positionOf(size_t emitter) const { return scene_.lights[emitters_[emitter].object].position; }

    // The density sampleLi gives to the emitter point pl (normal nl) of primitive `prim` as
    // seen from p, in solid angle (for MIS when a BSDF-sampled ray hits an emitter).
    float pdfLi(uint32_t prim, Vec3 p, Vec3 pl, Vec3 nl) const;

    // The sky (scene.environment): radiance arriving from direction w (0 without one), and the
    // density sampleLi gives w, light choice included (for MIS when a path escapes).
    Vec3 environmentRadiance(Vec3 w) const { return environment_.radiance(w); }
    float pdfEnvironment(Vec3 w) const {
        return environmentEmitter_ >= 0 ? probability_[size_t(environmentEmitter_)] * environment_.pdf(w) : 0.0f;
    }

    // Radiance a surface point emits toward w (one-sided; its emission texture's there, if any).
    static Vec3 emitted(const SurfacePoint& s, Vec3 w) {
        return (s.material->emits() && dot(s.ng, w) > 0.0f) ? s.emission : Vec3(0.0f);
    }

private:
    enum class Kind { Triangle, Sphere, Point, Spot, Directional, Environment };
    struct Emitter {
        Kind kind;
        uint32_t object;  // mesh, sphere or light index
        uint32_t index;   // triangle within the mesh
        float area;       // surfaces
    };
    size_t choose(float u, float& probability) const;

    const Scene& scene_;
    std::vector<Emitter> emitters_;
    std::vector<double> cdf_;             // cumulative power, normalised to end at 1
    std::vector<float> probability_;      // per emitter
    std::vector<int32_t> emitterOfPrim_;  // global primitive id → emitter, -1 if it does not emit
    EnvironmentMap environment_;          // inactive without a sky
    int32_t environmentEmitter_ = -1;     // its emitter index, -1 without a sky
};

}  // namespace pcl
