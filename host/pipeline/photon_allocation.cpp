#include "pipeline/photon_allocation.h"

namespace pcl {

uint64_t photonPassSeed(uint64_t seed, uint32_t pass) {
    return seed + uint64_t(pass) * 0x9E3779B97F4A7C15ull;
}

float emitFraction(const PclLight& light) {
    return float(light.projCount) / float(PCL_PROJ_GRID * PCL_PROJ_GRID);
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

void emittedFlux(const SceneBuffers& buffers, const std::vector<uint32_t>& first, uint32_t passKind,
                 double flux[3]) {
    flux[0] = flux[1] = flux[2] = 0.0;
    for (size_t l = 0; l < buffers.lights.size(); ++l) {
        uint32_t n = first[l + 1] - first[l];
        if (n == 0) continue;
        const PclLight& L = buffers.lights[l];
        for (int c = 0; c < 3; ++c) {
            float per = passKind == PCL_PASS_CAUSTIC ? L.power[c] * emitFraction(L) / float(n)
                                                     : L.power[c] / float(n);
            flux[c] += double(per) * double(n);
        }
    }
}

PclPhotonParams makePhotonParams(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                 uint32_t passKind, uint64_t passSeed, uint32_t maxDepth,
                                 uint32_t firstPhoton, uint32_t batchSize, bool storeGlobal) {
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
    p.storeGlobal = storeGlobal ? 1u : 0u;
    p.rayEpsilon = buffers.rayEpsilon;
    return p;
}

}  // namespace pcl
