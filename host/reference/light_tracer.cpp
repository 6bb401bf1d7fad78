#include "reference/light_tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include "core/clock.h"
#include "core/error.h"
#include "reference/bsdf.h"
#include "reference/sampler.h"
#include "reference/sampling.h"
#include "reference/surface.h"

namespace pcl {
namespace {

bool isDeltaLight(const Light& l) { return l.type != LightType::Area; }

bool hasDeltaLobe(const Material& m) {
    return (m.specular == SpecularKind::Mirror || m.specular == SpecularKind::Dielectric) &&
           maxComponent(m.rhoS) > 0.0f;
}

// Numbers of a light path: the light, the shutter time and the emitted ray; each vertex then
// uses PathVertexDims (kLightPoint: the lens point of its connection to the camera).
struct LightPathDims {
    static constexpr uint32_t kLightSelect = 0, kTime = 1, kDirection = 2, kPosition = 4, kTarget = 6;
};

// |ω_in·ns| |ω_out·ng| / (|ω_in·ng| |ω_out·ns|): the adjoint BSDF's shading-normal factor
// (Veach 1997 §5.3, pbrt-v4 §13.9); 1 where ns = ng. ω_in points back toward the light.
float shadingCorrection(const SurfacePoint& s, Vec3 wIn, Vec3 wOut) {
    float den = std::abs(dot(wIn, s.ng)) * std::abs(dot(wOut, s.ns));
    if (!(den > 0.0f)) return 0.0f;
    return std::abs(dot(wIn, s.ns)) * std::abs(dot(wOut, s.ng)) / den;
}

}  // namespace

std::string pathsThePathTracerMisses(const Scene& scene) {
    const Light* light = nullptr;
    for (const Light& l : scene.lights)
        if (isDeltaLight(l)) {
            light = &l;
            break;
        }
    // A mirror or dielectric some primitive wears.
    const Material* material = nullptr;
    auto consider = [&](int index) {
        if (!material && index >= 0 && size_t(index) < scene.materials.size() && hasDeltaLobe(scene.materials[index]))
            material = &scene.materials[index];
    };
    for (const Sphere& sp : scene.spheres) consider(sp.material);
    for (const TriangleMesh& mesh : scene.meshes)
        if (!mesh.positions.empty()) consider(mesh.material);
    if (!light || !material) return "";
    const char* kind = light->type == LightType::Point  ? "point"
                       : light->type == LightType::Spot ? "spot"
                                                        : "directional";
    return std::string("the ") + kind + " light '" + light->name + "' can shine through the " +
           (material->specular == SpecularKind::Mirror ? "mirror" : "dielectric") + " material '" + material->name +
           "', light the path tracer cannot find";
}

std::vector<uint8_t> pixelsSeeingNoDeltaSurfaceFirst(const Scene& scene, const SceneGeometry& geometry, int n) {
    Camera pinhole = scene.camera;
    pinhole.model = CameraModel::Pinhole;
    const RayCamera rc(pinhole);
    const int width = pinhole.width, height = pinhole.height;
    std::vector<uint8_t> keep(size_t(width) * height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int k = 0; k < n * n && keep[size_t(y) * width + x]; ++k) {
                CameraSample cs;
                cs.filmX = (float(k % n) + 0.5f) / float(n);
                cs.filmY = (float(k / n) + 0.5f) / float(n);
                const PclRay ray = rc.generateRay(x, y, cs);
                PclHit hit;
                if (geometry.intersect(ray, hit) && hasDeltaLobe(*surfaceAt(scene, geometry, ray, hit).material))
                    keep[size_t(y) * width + x] = 0;
            }
    return keep;
}

LightTracer::LightTracer(const Scene& scene, const SceneGeometry& geometry, LightTracerSettings settings)
    : scene_(scene), geometry_(geometry), settings_(std::move(settings)), camera_(scene.camera) {
    Bounds3 b = geometry.bounds();
    sceneCentre_ = (b.lo + b.hi) * 0.5f;
    sceneRadius_ = 0.5f * length(b.extent());
    if (!std::isfinite(sceneRadius_) || !(sceneRadius_ > 0.0f)) {
        sceneCentre_ = Vec3(0.0f);
        sceneRadius_ = 1.0f;
    }
    // The targets: bounding spheres of the mirror and dielectric primitives over the shutter.
    for (const Sphere& sp : scene.spheres)
        if (hasDeltaLobe(scene.materials[sp.material]))
            targets_.push_back({sp.centre + sp.motion * 0.5f, (sp.radius + 0.5f * length(sp.motion)) * 1.0001f});
    for (const TriangleMesh& mesh : scene.meshes) {
        if (mesh.positions.empty() || !hasDeltaLobe(scene.materials[mesh.material])) continue;
        Bounds3 mb;
        for (Vec3 p : mesh.positions) {
            mb.extend(p);
            mb.extend(p + mesh.motion);
        }
        targets_.push_back({(mb.lo + mb.hi) * 0.5f, 0.5f * length(mb.extent()) * 1.0001f + 1e-6f});
    }
    // Each delta light's power (any positive choice stays unbiased; power keeps variance low),
    // times the fraction of it aimed at the targets.
    std::vector<double> power;
    double total = 0.0, aimed = 0.0;
    for (uint32_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        double p = 0.0;
        switch (l.type) {
            case LightType::Point: p = 4.0 * kPi * luminance(l.intensity); break;
            case LightType::Spot: p = 2.0 * kPi * luminance(l.intensity) * (1.0 - l.cosOuter); break;
            case LightType::Directional: p = kPi * double(sceneRadius_) * sceneRadius_ * luminance(l.irradiance); break;
            case LightType::Area: continue;  // the path tracer's own
        }
        if (!(p > 0.0)) continue;
        double fraction = 1.0;
        Emission e = emissionOf(i, fraction);
        if (!(fraction > 0.0)) continue;  // aimed at nothing: no path of this light counts
        total += p;
        aimed += p * fraction;
        lights_.push_back(std::move(e));
        power.push_back(p * fraction);
    }
    if (lights_.empty()) return;
    double running = 0.0;
    for (double p : power) {
        running += p;
        cdf_.push_back(running / aimed);
        probability_.push_back(static_cast<float>(p / aimed));
    }
    cdf_.back() = 1.0;
    const double pixels = double(scene.camera.width) * double(scene.camera.height);
    pathsPerPass_ = static_cast<uint32_t>(std::max(1.0, std::ceil(pixels * aimed / total)));
}

LightTracer::Emission LightTracer::emissionOf(uint32_t index, double& aimedFraction) const {
    const Light& light = scene_.lights[index];
    Emission e;
    e.light = index;
    aimedFraction = 1.0;
    if (settings_.paths == LightTracerPaths::All) return e;  // every path counts: emit uniformly
    if (!settings_.aim) return e;
    if (targets_.empty()) {
        aimedFraction = 0.0;
        return e;
    }
    if (light.type == LightType::Directional) {
        // Discs on the plane the parallel rays start from (sceneRadius_ · 2 behind the centre).
        const Vec3 d = normalize(light.direction), start = sceneCentre_ - d * (2.0f * sceneRadius_);
        for (const Target& t : targets_) {
            e.disc.push_back(t.centre - d * dot(t.centre - start, d));
            e.radius.push_back(t.radius);
            e.measure += kPi * double(t.radius) * t.radius;
            e.cdf.push_back(e.measure);
        }
        aimedFraction = std::min(1.0, e.measure / (kPi * double(sceneRadius_) * sceneRadius_));
    } else {
        for (const Target& t : targets_) {
            const Vec3 v = t.centre - light.position;
            const float dist = length(v);
            if (!(dist > t.radius)) return e;  // the light is inside a bound: emit uniformly
            const float sin2 = (t.radius / dist) * (t.radius / dist);
            e.axis.push_back(v / dist);
            e.cosMax.push_back(std::sqrt(std::max(0.0f, 1.0f - sin2)));
            e.measure += 2.0 * kPi * (1.0 - double(e.cosMax.back()));
            e.cdf.push_back(e.measure);
        }
        const double emitted = light.type == LightType::Point ? 4.0 * kPi : 2.0 * kPi * (1.0 - double(light.cosOuter));
        aimedFraction = std::min(1.0, e.measure / emitted);
    }
    if (!(e.measure > 0.0)) {
        aimedFraction = 0.0;
        return e;
    }
    for (double& c : e.cdf) c /= e.measure;
    e.cdf.back() = 1.0;
    e.aimed = true;
    return e;
}

void LightTracer::tracePath(uint32_t pass, uint32_t path, std::vector<Splat>& splats, uint64_t& discarded) const {
    Sampler sampler(settings_.seed, path, pass, PCL_RNG_STREAM_LIGHT_PATH);
    // The light, by the power it aims at the targets.
    float u = sampler.get(LightPathDims::kLightSelect);
    size_t k =
        std::min<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), double(u)) - cdf_.begin(), lights_.size() - 1);
    while (probability_[k] == 0.0f && k > 0) --k;
    const Emission& emission = lights_[k];
    const Light& light = scene_.lights[emission.light];
    const float time = camera_.hasShutter() ? sampler.get(LightPathDims::kTime) : 0.0f;
    const float u1 = sampler.get(LightPathDims::kDirection), u2 = sampler.get(LightPathDims::kDirection + 1);
    // The target, if aimed: by solid angle or area.
    size_t target = 0;
    if (emission.aimed) {
        double ut = sampler.get(LightPathDims::kTarget);
        target = std::min<size_t>(std::upper_bound(emission.cdf.begin(), emission.cdf.end(), ut) - emission.cdf.begin(),
                                  emission.cdf.size() - 1);
    }

    // The emitted ray and its flux weight β = (emitted intensity or irradiance) / (pdf · choice).
    Vec3 origin, dir, beta;
    if (light.type == LightType::Directional) {
        dir = normalize(light.direction);
        float x, y;
        sampleConcentricDisk(sampler.get(LightPathDims::kPosition), sampler.get(LightPathDims::kPosition + 1), x, y);
        Vec3 t, b;
        makeBasis(dir, t, b);
        if (emission.aimed) {
            // A point on a target's disc; the density counts every disc that holds it.
            origin = emission.disc[target] + (t * x + b * y) * emission.radius[target];
            int holding = 0;
            for (size_t j = 0; j < emission.disc.size(); ++j) {
                Vec3 o = origin - emission.disc[j];
                holding += dot(o, o) <= emission.radius[j] * emission.radius[j];
            }
            beta = light.irradiance * float(emission.measure / std::max(1, holding));
        } else {
            // Parallel rays through a disc of the scene's bounding radius, from outside the scene.
            origin = sceneCentre_ + (t * x + b * y) * sceneRadius_ - dir * (2.0f * sceneRadius_);
            beta = light.irradiance * (kPi * sceneRadius_ * sceneRadius_);
        }
    } else {
        origin = light.position;
        if (emission.aimed) {
            // Uniform in a target's cone; the density counts every cone that holds the direction.
            const float cosMax = emission.cosMax[target];
            const float cosTheta = 1.0f - u1 * (1.0f - cosMax);
            const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
            Vec3 t, b;
            makeBasis(emission.axis[target], t, b);
            dir = fromLocal(t, b, emission.axis[target], sinTheta, cosTheta, 2.0f * kPi * u2);
            int holding = 0;
            for (size_t j = 0; j < emission.axis.size(); ++j)
                holding += dot(dir, emission.axis[j]) >= emission.cosMax[j];
            beta = light.intensity * float(emission.measure / std::max(1, holding));
        } else if (light.type == LightType::Point) {
            dir = sampleUniformSphere(u1, u2);
            beta = light.intensity * (4.0f * kPi);
        } else {
            // Uniform in the outer cone: pdf 1 / (2π (1 - cosOuter)).
            Vec3 axis = normalize(light.direction);
            float cosTheta = 1.0f - u1 * (1.0f - light.cosOuter);
            float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
            Vec3 t, b;
            makeBasis(axis, t, b);
            dir = fromLocal(t, b, axis, sinTheta, cosTheta, 2.0f * kPi * u2);
            beta = light.intensity * (2.0f * kPi * (1.0f - light.cosOuter));
        }
        if (light.type == LightType::Spot)
            beta *= smoothstep(light.cosOuter, light.cosInner, dot(dir, normalize(light.direction)));
    }
    beta = beta / probability_[k];
    if (!(maxComponent(beta) > 0.0f)) return;

    PclRay ray = makeRay(origin, dir, time);

    const bool all = settings_.paths == LightTracerPaths::All;
    const float invPaths = 1.0f / float(pathsPerPass_);
    Vec3 throughput(1.0f);  // relative to β, for Russian roulette
    for (int depth = 0;; ++depth) {
        PclHit hit;
        if (!geometry_.intersect(ray, hit)) break;
        SurfacePoint s = surfaceAt(scene_, geometry_, ray, hit);
        Vec3 wIn = -normalize(rayDirection(ray));
        MixedBsdf bsdf(*s.material, s.rhoD, s.rhoS, s.exponent, s.ns, s.ng);
        if (bsdf.isBlack()) break;
        uint32_t vertex = static_cast<uint32_t>(depth);

        // Connect to the camera: the path tracer's share is every path whose first bounce is
        // non-delta, so ThroughSpecular connects from the second vertex on only.
        if (bsdf.hasNonDelta() && (all || depth > 0)) {
            CameraConnection c;
            if (camera_.connect(s.p, sampler.vertex(vertex, PathVertexDims::kLightPoint),
                                sampler.vertex(vertex, PathVertexDims::kLightPoint + 1), c)) {
                Vec3 wCam = normalize(c.lensPoint - s.p);
                // f(ω_cam, ω_in) |ω_in·ns|, then the adjoint's |ω_cam·ng| / |ω_in·ng|.
                Vec3 fCos = bsdf.evalCos(wCam, wIn);
                float cosIn = std::abs(dot(wIn, s.ng));
                if (maxComponent(fCos) > 0.0f && cosIn > 0.0f &&
                    !geometry_.occluded(spawnShadowRay(s.p, s.ng, c.lensPoint, Vec3(0.0f), time))) {
                    Vec3 value = beta * throughput * fCos *
                                 (std::abs(dot(wCam, s.ng)) / cosIn * c.importance * invPaths);
                    if (isFinite(value))
                        splats.push_back({static_cast<uint32_t>(c.y * scene_.camera.width + c.x), value});
                    else ++discarded;
                }
            }
        }
        if (depth >= settings_.maxDepth) break;

        BsdfSample bs;
        if (!bsdf.sample(wIn, sampler.vertex(vertex, PathVertexDims::kLobe),
                         sampler.vertex(vertex, PathVertexDims::kDirection),
                         sampler.vertex(vertex, PathVertexDims::kDirection + 1), bs))
            break;
        if (!all && depth == 0 && !bs.delta) break;  // the path tracer's path
        // Flux crosses a refraction without the radiance's η² (importance transport).
        throughput *= bs.weight * (shadingCorrection(s, wIn, bs.wi) / bs.radianceScale);
        ray = spawnRay(s.p, s.ng, bs.wi, time, std::numeric_limits<float>::infinity());

        if (depth + 1 >= settings_.rouletteDepth) {
            float q = std::max(0.05f, 1.0f - maxComponent(throughput));
            if (sampler.vertex(vertex, PathVertexDims::kRoulette) < q) break;
            throughput *= 1.0f / (1.0f - q);
        }
        if (!(maxComponent(throughput) > 0.0f)) break;
    }
}

void LightTracer::render(Film& film, LightTracerStats* stats) const {
    const int width = scene_.camera.width, height = scene_.camera.height;
    if (film.width() != width || film.height() != height)
        throw InputError("light tracer: film is " + std::to_string(film.width()) + "x" + std::to_string(film.height()) +
                         ", expected the camera's " + std::to_string(width) + "x" + std::to_string(height));
    const auto start = Clock::now();
    LightTracerStats st;
    const uint32_t pathsPerPass = pathsPerPass_;
    if (pathsPerPass > 0 && settings_.passes > 0) {
        // Fixed chunks of paths, traced in parallel a batch at a time and splatted in chunk
        // order: the same sums for any thread count.
        constexpr uint32_t kChunk = 1024;
        const uint32_t chunksPerPass = (pathsPerPass + kChunk - 1) / kChunk;
        const uint64_t chunkCount = uint64_t(chunksPerPass) * settings_.passes;
        int threads = settings_.threads > 0 ? settings_.threads : static_cast<int>(std::thread::hardware_concurrency());
        threads = std::max(1, threads);
        const uint64_t batch = uint64_t(threads) * 8;
        std::vector<std::vector<Splat>> splats(batch);
        std::vector<uint64_t> discarded(batch);
        for (uint64_t first = 0; first < chunkCount; first += batch) {
            const uint64_t n = std::min(batch, chunkCount - first);
            std::atomic<uint64_t> next{0};
            auto worker = [&]() {
                for (uint64_t c; (c = next.fetch_add(1)) < n;) {
                    splats[c].clear();
                    discarded[c] = 0;
                    const uint64_t chunk = first + c;
                    const uint32_t pass = settings_.firstPass + static_cast<uint32_t>(chunk / chunksPerPass);
                    const uint32_t begin = static_cast<uint32_t>(chunk % chunksPerPass) * kChunk;
                    const uint32_t end = std::min(pathsPerPass, begin + kChunk);
                    for (uint32_t p = begin; p < end; ++p) tracePath(pass, p, splats[c], discarded[c]);
                }
            };
            std::vector<std::thread> pool;
            for (int t = 1; t < std::min<int>(threads, static_cast<int>(n)); ++t) pool.emplace_back(worker);
            worker();
            for (auto& t : pool) t.join();
            for (uint64_t c = 0; c < n; ++c) {
                for (const Splat& sp : splats[c])
                    film.splat(static_cast<int>(sp.pixel % uint32_t(width)),
                               static_cast<int>(sp.pixel / uint32_t(width)), sp.value);
                st.splats += splats[c].size();
                st.discarded += discarded[c];
            }
        }
        st.paths = uint64_t(pathsPerPass) * settings_.passes;
    }
    st.seconds = since(start);
    if (stats) *stats = st;
}

}  // namespace pcl
