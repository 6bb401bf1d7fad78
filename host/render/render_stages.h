// The stages one photon-mapped render calls, pass by pass and chunk by chunk, behind one
// interface with two implementations: the OpenCL pipeline (render/device_stages.h) and the CPU
// twin (render/twin_stages.h, host/reference). The loop around them (render/photon_renderer.cpp)
// decides everything a pixel depends on — seeds, parameters, which maps are read how, which parts
// a method adds — so the device render and the twin render of the same settings differ only
// where the stages themselves differ (what `check --stage render` and the stage checks measure).
//
//   stages.tracePhotons(pass options)   the pass's photon maps, as host vectors
//   stages.buildMaps(spec)              the search structures and irradiance readers of the pass
//   per chunk of eye samples (records 0 .. count−1):
//   [connectCaustics(the pass's caustic photons)]    fg: splats into the pass's film
//     cameraRays → eyePaths → [gatherHistograms] → directLight / causticEstimate /
//     globalEstimate / finalGather / volumeEstimate (each fills one part) → readSampleRadiance
//     (their sum per record to host; readChunk instead: records and parts, for AOVs)
#pragma once
#include <cstdint>
#include <vector>

#include "pipeline/photon_pass.h"
#include "prep/irradiance_settings.h"
#include "prep/volume_estimate_settings.h"
#include "shared/types.h"

namespace pcl {

// How a pass reads one photon map at its queries.
enum class MapReader {
    None,         // not read (the method does not use it, or it holds no photons)
    Estimate,     // the k-nearest-neighbour estimate (pipeline/estimate.h), k ≤ maxK
    FixedRadius,  // progressive: the box estimate over the disc of radius² `radius2`
                  // (render/fixed_radius.h), k ≤ maxK
    Precomputed,  // Christensen's precomputed irradiance (pipeline/precomputed_irradiance.h)
};

struct MapSpec {
    MapReader reader = MapReader::None;
    const std::vector<PclPhoton>* photons = nullptr;  // the records read (kept by the loop for the pass)
    uint32_t maxK = 0;                                // Estimate, FixedRadius
    EstimateSettings estimate;                        // Estimate, FixedRadius (rayEpsilon set)
    PrecomputedIrradianceOptions precomputed;         // Precomputed
};

// How a pass reads one volume photon map along the eye's medium segments: the beam radiance
// estimate (prep/volume_estimate_settings.h); not read when photons is null.
struct VolumeMapSpec {
    const std::vector<PclPhoton>* photons = nullptr;
    VolumeEstimateSettings settings;
};

// The maps of one pass.
struct PassMapSpec {
    MapSpec global, caustic;
    // Scenes with media: the global pass's volume map and the volume caustic map (L S+ V).
    VolumeMapSpec volume, volumeCaustic;
    // fg with importance-sampled gather rays: the histograms read the k nearest of these photons
    // (the whole global map) directly; null when not used.
    const std::vector<PclPhoton>* histogramPhotons = nullptr;
    float radius2 = 0.0f;  // the pass's search radius² (progressive: the schedule's; the hash grid's
                           // cells follow it)
};

// Which parts a chunk's records got (the others are 0).
struct ChunkParts {
    bool direct = false, caustic = false, indirect = false, volume = false;
};

// What readSampleRadiance sums: the chunk's records are samples first .. first + count − 1 of
// the pass, sample s in pixel s / samplesPerPixel of an image `width` wide.
struct SampleRadianceSpec {
    size_t first = 0;
    uint32_t count = 0, samplesPerPixel = 1, width = 1;
    ChunkParts parts;
    // 2 ints per image row: its pixels [begin, end) whose emitted light the render's emitter
    // samples give instead (the sum leaves it out there); empty: none.
    const std::vector<int32_t>* emitterSpans = nullptr;
};

// A chunk on the host: the eye records and the four parts, `count` each.
struct ChunkResult {
    std::vector<PclEyeHit> hits;
    std::vector<PclRadiance> direct, caustic, indirect, volume;
};

// The photons of one pass and how many paths each map emitted.
struct PassPhotons {
    std::vector<PclPhoton> global, caustic;
    std::vector<PclPhoton> volume, volumeCaustic;  // scenes with media
    std::vector<float> causticTimes;               // PhotonPassOptions::causticTimes: caustic[i]'s shutter time
    uint64_t globalEmitted = 0, causticEmitted = 0;
};

class RenderStages {
public:
    virtual ~RenderStages() = default;

    // Eye samples per chunk for a pass of passSamples (the device: what its buffers hold).
    virtual size_t chunkSamples(size_t passSamples) const = 0;
    // Waits for the work enqueued so far (the loop's stage timings); the twin has none.
    virtual void wait() {}

    virtual PassPhotons tracePhotons(const PhotonPassOptions& options) = 0;
    // Replaces the previous pass's maps; spec's photon vectors must live until the next call.
    virtual void buildMaps(const PassMapSpec& spec) = 0;

    virtual void cameraRays(const PclCameraParams& params) = 0;
    virtual void eyePaths(const PclEyeParams& params) = 0;
    // The importance histograms at the chunk's records (spec.histogramPhotons);
    // directLight and finalGather use them when their params' histogramCells > 0.
    virtual void gatherHistograms(const PclGatherParams& params) = 0;
    virtual void directLight(const PclDirectParams& params) = 0;           // → direct
    virtual void causticEstimate(const PclEyeEstimateParams& params) = 0;  // caustic map → caustic
    // fg's caustic connections: one splat per caustic photon (pipeline/connect_caustics.h).
    virtual std::vector<PclSplat> connectCaustics(const PclConnectParams& params, const PclCameraParams& camera,
                                                  const std::vector<PclPhoton>& photons,
                                                  const std::vector<float>& times) = 0;
    virtual void globalEstimate(const PclEyeEstimateParams& params) = 0;  // global map → indirect
    virtual void finalGather(const PclGatherParams& params) = 0;          // global map → indirect
    // The beam radiance estimate along the medium segments the last eyePaths wrote, from the
    // pass's volume maps (spec.volume, spec.volumeCaustic), summed → volume.
    virtual void volumeEstimate() = 0;
    // Per-photon radii of a volume map: each photon's squared distance to its k-th nearest other
    // photon within rMax, −1 where fewer (pipeline/volume_estimate, volumeKthNeighbourDist2).
    virtual std::vector<float> volumeKthNeighbourDist2(const std::vector<PclPhoton>& photons, uint32_t k,
                                                       float rMax) = 0;
    // The chunk's records and the parts it got (the others zero-filled), `count` each.
    virtual void readChunk(uint32_t count, ChunkParts parts, ChunkResult& out) = 0;
    // The accumulate stage: per record the radiance the film adds, the emitted light (0 inside
    // an emitter span) + the parts spec.parts names, added in float in that order
    // (kernels/accumulate.cl), spec.count of them. 16 bytes a record where readChunk reads 192
    // and more: what the render reads unless it writes AOVs (which need the parts apart).
    virtual void readSampleRadiance(const SampleRadianceSpec& spec, std::vector<PclRadiance>& out) = 0;
};

}  // namespace pcl
