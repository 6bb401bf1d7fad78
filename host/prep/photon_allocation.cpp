#include "prep/photon_allocation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "shared/rng.h"

namespace pcl {

double scalarPower(const PclLight& light) {
    return (double(light.power[0]) + double(light.power[1]) + double(light.power[2])) / 3.0;
}

std::vector<uint32_t> allocatePhotons(const std::vector<double>& weights, uint32_t photons) {
    const size_t n = weights.size();
    std::vector<uint32_t> count(n, 0);
    double total = 0.0;
    for (double w : weights) total += std::max(0.0, w);
    if (total > 0.0 && photons > 0) {
        std::vector<double> remainder(n, 0.0);
        uint64_t given = 0;
        for (size_t i = 0; i < n; ++i) {
            double exact = photons * (std::max(0.0, weights[i]) / total);
            count[i] = static_cast<uint32_t>(std::floor(exact));
            remainder[i] = exact - count[i];
            given += count[i];
        }
        std::vector<size_t> order(n);
        std::iota(order.begin(), order.end(), size_t(0));
        // Largest remainder first, ties to the lower index (stable sort keeps index order).
        std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return remainder[a] > remainder[b]; });
        for (size_t k = 0; given < photons && k < n; ++k) {
            if (weights[order[k]] > 0.0) {
                ++count[order[k]];
                ++given;
            }
        }
        // Every light with power gets a photon (taken from the largest allocation), so none
        // of its power is lost.
        for (size_t i = 0; i < n; ++i) {
            if (weights[i] > 0.0 && count[i] == 0) {
                size_t largest = static_cast<size_t>(std::max_element(count.begin(), count.end()) - count.begin());
                if (count[largest] <= 1) break;  // fewer photons than lights: nothing to take
                --count[largest];
                ++count[i];
            }
        }
    }
    std::vector<uint32_t> first(n + 1, 0);
    for (size_t i = 0; i < n; ++i) first[i + 1] = first[i] + count[i];
    return first;
}

uint64_t photonPassSeed(uint64_t seed, uint32_t pass) { return seed + uint64_t(pass) * 0x9E3779B97F4A7C15ull; }

float emitFraction(const PclLight& light) {
    const float f = float(light.projCount) / float(PCL_PROJ_GRID * PCL_PROJ_GRID);
    if (light.type != PCL_LIGHT_ENVIRONMENT || !(light.e1[3] > 0.0f)) return f;
    const float share = light.e1[3] / light.radius;
    return f * share * share;
}

std::vector<uint32_t> lightFirstPhoton(const SceneBuffers& buffers, uint32_t photons, uint32_t passKind) {
    std::vector<double> weights;
    weights.reserve(buffers.lights.size());
    for (const PclLight& l : buffers.lights) {
        double s = scalarPower(l);
        if (passKind == PCL_PASS_CAUSTIC) s *= double(emitFraction(l));
        weights.push_back(s);
    }
    return allocatePhotons(weights, photons);
}

void emittedFlux(const SceneBuffers& buffers, const std::vector<uint32_t>& first, uint32_t passKind, double flux[3]) {
    flux[0] = flux[1] = flux[2] = 0.0;
    for (size_t l = 0; l < buffers.lights.size(); ++l) {
        uint32_t n = first[l + 1] - first[l];
        if (n == 0) continue;
        const PclLight& L = buffers.lights[l];
        for (int c = 0; c < 3; ++c) {
            float per = passKind == PCL_PASS_CAUSTIC ? L.power[c] * emitFraction(L) / float(n) : L.power[c] / float(n);
            flux[c] += double(per) * double(n);
        }
    }
}

float photonEmissionTime(const PclPhotonParams& params, uint32_t photon) {
    if (!params.hasMotion) return 0.0f;
    const uint64_t seed = uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32;
    const uint32_t stream = params.pass == PCL_PASS_CAUSTIC ? PCL_RNG_STREAM_CAUSTIC : PCL_RNG_STREAM_PHOTON;
    uint32_t w[4];
    rng_block(seed, photon, 0u, 0u, stream, w);
    return rng_u01(w[3]);
}

void appendRecordTimes(const PclPhotonParams& params, const std::vector<uint32_t>& counts, std::vector<float>& times) {
    for (size_t i = 0; i < counts.size(); ++i) {
        if (counts[i] == 0) continue;
        const float t = photonEmissionTime(params, params.firstPhoton + uint32_t(i));
        times.insert(times.end(), counts[i], t);
    }
}

PclPhotonParams makePhotonParams(const SceneGeometry& geometry, const SceneBuffers& buffers, uint32_t passKind,
                                 uint64_t passSeed, uint32_t maxDepth, uint32_t firstPhoton, uint32_t batchSize,
                                 bool storeGlobal) {
    PclPhotonParams p{};
    p.seedLo = uint32_t(passSeed);
    p.seedHi = uint32_t(passSeed >> 32);
    p.firstPhoton = firstPhoton;
    p.batchSize = batchSize;
    p.lightCount = uint32_t(buffers.lights.size());
    p.triangleCount = geometry.triangleCount();
    p.maxDepth = maxDepth;
    p.pass = passKind;
    p.hasMotion = buffers.hasMotion ? 1u : 0u;
    p.hasMedia = buffers.hasMedia ? 1u : 0u;
    p.storeGlobal = storeGlobal ? 1u : 0u;
    p.rayEpsilon = buffers.rayEpsilon;
    return p;
}

}  // namespace pcl
