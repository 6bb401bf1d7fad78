#include "reference/light_sampling.h"

#include <algorithm>
#include <cmath>

#include "prep/emission_texture.h"
#include "reference/sampling.h"

namespace pcl {
LightSampler::LightSampler(const Scene& scene, const SceneGeometry& geometry) : scene_(scene) {
    emitterOfPrim_.assign(geometry.primitiveCount(), -1);
    std::vector<double> power;
    // Surfaces: power of a one-sided Lambertian emitter is π A Le (per channel; luminance here).
    uint32_t prim = 0;
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        const Material& mat = scene.materials[mesh.material];
        for (uint32_t t = 0; t < mesh.triangleCount(); ++t, ++prim) {
            if (!mat.emits()) continue;
            TriangleVertices v = triangleAt(mesh, t, 0.0f);
            float area = 0.5f * length(cross(v.p1 - v.p0, v.p2 - v.p0));
            if (!(area > 0.0f)) continue;
            emitterOfPrim_[prim] = static_cast<int32_t>(emitters_.size());
            emitters_.push_back({Kind::Triangle, m, t, area});
            power.push_back(kPi * area * std::max(luminance(meanEmission(scene, mesh, t)), 1e-6f));
        }
    }
    for (uint32_t s = 0; s < scene.spheres.size(); ++s, ++prim) {
        const Sphere& sphere = scene.spheres[s];
        const Material& mat = scene.materials[sphere.material];
        if (!mat.emits()) continue;
        float area = 4.0f * kPi * sphere.radius * sphere.radius;
        emitterOfPrim_[prim] = static_cast<int32_t>(emitters_.size());
        emitters_.push_back({Kind::Sphere, s, 0, area});
        power.push_back(kPi * area * std::max(luminance(mat.emission), 1e-6f));
    }
    // Delta lights. Directional power is E times the scene's cross-section (bounding sphere).
    float radius = 0.5f * length(geometry.bounds().extent());
    if (!std::isfinite(radius)) radius = 1.0f;
    for (uint32_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        switch (light.type) {
            case LightType::Point:
                emitters_.push_back({Kind::Point, l, 0, 0.0f});
                power.push_back(4.0f * kPi * luminance(light.intensity));
                break;
            case LightType::Spot:
                emitters_.push_back({Kind::Spot, l, 0, 0.0f});
                power.push_back(2.0f * kPi * luminance(light.intensity) *
                                (1.0f - 0.5f * (light.cosInner + light.cosOuter)));
                break;
            case LightType::Directional:
                emitters_.push_back({Kind::Directional, l, 0, 0.0f});
                power.push_back(kPi * radius * radius * luminance(light.irradiance));
                break;
            case LightType::Area: break;  // its mesh's emissive triangles are already in the list
        }
    }
    // The sky: the power it sends through the scene's cross-section, π R² ∫ L dω.
    environment_ = EnvironmentMap(scene.environment);
    if (environment_.active()) {
        environmentEmitter_ = int32_t(emitters_.size());
        emitters_.push_back({Kind::Environment, 0, 0, 0.0f});
        power.push_back(kPi * radius * radius * luminance(environment_.integral()));
    }
    double total = 0.0;
    for (double& p : power) total += p = std::max(p, 0.0);
    if (!(total > 0.0)) {
        emitters_.clear();
        return;
    }
    double running = 0.0;
    for (double p : power) {
        running += p;
        cdf_.push_back(running / total);
        probability_.push_back(static_cast<float>(p / total));
    }
    cdf_.back() = 1.0;
}

size_t LightSampler::choose(float u, float& probability) const {
    size_t i = std::upper_bound(cdf_.begin(), cdf_.end(), static_cast<double>(u)) - cdf_.begin();
    i = std::min(i, emitters_.size() - 1);
    while (probability_[i] == 0.0f && i > 0) --i;  // never land on a zero-power entry
    probability = probability_[i];
    return i;
}

bool LightSampler::sampleLi(Vec3 p, float time, float uSelect, float u1, float u2, LightSample& out) const {
    if (emitters_.empty()) return false;
    float choice;
    const size_t index = choose(uSelect, choice);
    return sampleLiFrom(index, p, time, u1, u2, out);
}

bool LightSampler::sampleLiFrom(size_t index, Vec3 p, float time, float u1, float u2, LightSample& out) const {
    const float choice = probability_[index];
    if (choice <= 0.0f) return false;
    const Emitter& e = emitters_[index];
    out = LightSample{};
    out.emitter = index;
    if (e.kind == Kind::Triangle || e.kind == Kind::Sphere) {
        if (e.kind == Kind::Triangle) {
            const TriangleMesh& mesh = scene_.meshes[e.object];
            TriangleVertices v = triangleAt(mesh, e.index, time);
            float b0, b1;
            sampleUniformTriangle(u1, u2, b0, b1);
            out.point = v.p0 * b0 + v.p1 * b1 + v.p2 * (1.0f - b0 - b1);
            out.normal = normalize(cross(v.p1 - v.p0, v.p2 - v.p0));
            out.Li = emissionAt(scene_, mesh, e.index, b1, 1.0f - b0 - b1);  // its emission texture's, if any
        } else {
            const Sphere& sphere = scene_.spheres[e.object];
            out.normal = sampleUniformSphere(u1, u2);
            out.point = sphere.centre + sphere.motion * time + out.normal * sphere.radius;
            out.Li = scene_.materials[sphere.material].emission;
        }
        Vec3 d = out.point - p;
        float dist2 = dot(d, d);
        if (!(dist2 > 0.0f)) return false;
        out.wi = d / std::sqrt(dist2);
        float cosLight = -dot(out.normal, out.wi);
        if (cosLight <= 0.0f) return false;  // the back of a one-sided emitter
        // Area density converted to solid angle: p_ω = p_A r² / cos θ_light (pbrt-v4 eq. 4.9).
        out.pdf = choice / e.area * dist2 / cosLight;
        return true;
    }
    if (e.kind == Kind::Environment) {
        float pdf;
        if (!environment_.sample(u1, u2, out.wi, pdf)) return false;
        out.Li = environment_.radiance(out.wi);
        out.pdf = choice * pdf;
        out.infinite = true;
        return maxComponent(out.Li) > 0.0f;
    }
    const Light& light = scene_.lights[e.object];
    out.delta = true;
    out.pdf = choice;
    if (e.kind == Kind::Directional) {
        out.wi = -normalize(light.direction);
        out.Li = light.irradiance;  // E on a surface facing the light; the BSDF term adds cos θ
        out.infinite = true;
        return true;
    }
    out.point = light.position;
    Vec3 d = out.point - p;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return false;
    out.wi = d / std::sqrt(dist2);
    Vec3 I = light.intensity;
    if (e.kind == Kind::Spot) I *= smoothstep(light.cosOuter, light.cosInner, dot(-out.wi, normalize(light.direction)));
    out.Li = I / dist2;  // inverse square law: E = I cos θ / r² once the BSDF term adds cos θ
    return maxComponent(out.Li) > 0.0f;
}

float LightSampler::pdfLi(uint32_t prim, Vec3 p, Vec3 pl, Vec3 nl) const {
    if (prim >= emitterOfPrim_.size() || emitterOfPrim_[prim] < 0) return 0.0f;
    int32_t i = emitterOfPrim_[prim];
    Vec3 d = pl - p;
    float dist2 = dot(d, d);
    float cosLight = std::abs(dot(nl, d)) / std::sqrt(dist2);
    if (!(cosLight > 0.0f)) return 0.0f;
    return probability_[i] / emitters_[i].area * dist2 / cosLight;
}

}  // namespace pcl
