#include "render/twin_stages.h"

#include <algorithm>

#include <stdexcept>
#include "reference/camera_rays.h"
#include "reference/connect_caustics.h"
#include "reference/direct_light.h"
#include "reference/estimate.h"
#include "reference/eye_estimate.h"
#include "reference/eye_paths.h"
#include "reference/final_gather.h"
#include "reference/photon_pass.h"
#include "reference/precomputed_irradiance.h"
#include "reference/volume_estimate.h"
#include "render/fixed_radius.h"

namespace pcl {

TwinRenderStages::TwinRenderStages(const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers)
    : scene_(scene), geometry_(geometry), buffers_(buffers) {}

size_t TwinRenderStages::chunkSamples(size_t passSamples) const { return std::min(passSamples, size_t(1) << 18); }

PassPhotons TwinRenderStages::tracePhotons(const PhotonPassOptions& options) {
    ReferencePhotonPassSettings r;
    r.seed = options.seed;
    r.pass = options.pass;
    r.globalPhotons = options.buildGlobal ? options.globalPhotons : 0;
    r.causticPhotons = options.buildCaustic ? options.causticPhotons : 0;
    r.maxDepth = options.maxDepth;
    r.causticTimes = options.causticTimes;
    ReferencePhotonMaps maps = runPhotonPassReference(buffers_, geometry_, r);
    PassPhotons p;
    p.causticTimes = std::move(maps.causticTimes);
    p.global = std::move(maps.global);
    p.caustic = std::move(maps.caustic);
    p.volume = std::move(maps.volume);
    p.volumeCaustic = std::move(maps.volumeCaustic);
    p.globalEmitted = maps.globalStats.paths;
    p.causticEmitted = maps.causticStats.paths;
    return p;
}

void TwinRenderStages::buildMaps(const PassMapSpec& spec) {
    spec_ = spec;
    points_.clear();
    cover_.clear();
    nondirect_.clear();
    // (The k-nearest readers search by brute force: nothing to build.)
    for (const MapSpec* m : {&spec.global, &spec.caustic})
        if (m->reader == MapReader::Precomputed)
            points_ = referencePrecomputeIrradiance(*m->photons, m->precomputed, &geometry_, 0, &cover_, &nondirect_);
}

std::vector<Vec3> TwinRenderStages::irradiance(const MapSpec& m, const std::vector<PclEstimateQuery>& queriesIn) const {
    std::vector<Vec3> E(queriesIn.size(), Vec3(0.0f));
    if (m.reader == MapReader::None) throw std::logic_error("render (twin): a map the pass does not read was read");
    if (m.reader == MapReader::Precomputed) {
        return referencePrecomputedIrradiance(points_, cover_, m.precomputed.estimate.minNormalCos,
                                              nondirect_)(queriesIn);
    }
    // As the device's estimate: a query's k above maxK is searched with maxK.
    std::vector<PclEstimateQuery> queries = queriesIn;
    for (PclEstimateQuery& q : queries) q.k = std::min(q.k & PCL_QUERY_K_MASK, m.maxK) | (q.k & PCL_QUERY_NONDIRECT);
    std::vector<PclEstimate> e = referenceEstimate(*m.photons, queries, m.estimate, &geometry_);
    for (size_t i = 0; i < E.size(); ++i) {
        if (m.reader == MapReader::FixedRadius) rescaleToFixedRadius(e[i], queries[i], m.maxK, spec_.radius2);
        E[i] = Vec3(e[i].r, e[i].g, e[i].b);
    }
    return E;
}

void TwinRenderStages::cameraRays(const PclCameraParams& params) { rays_ = referenceCameraRays(scene_.camera, params); }

void TwinRenderStages::eyePaths(const PclEyeParams& params) {
    hits_ = referenceEyePaths(geometry_, buffers_, rays_, params, &segments_);
}

void TwinRenderStages::gatherHistograms(const PclGatherParams& params) {
    if (!spec_.histogramPhotons)
        throw std::logic_error("render (twin): importance histograms asked of a pass without the global map");
    histograms_ = referenceGatherHistograms(*spec_.histogramPhotons, hits_, params);
}

void TwinRenderStages::directLight(const PclDirectParams& params) {
    direct_ =
        referenceDirectLight(geometry_, buffers_, hits_, params, params.histogramCells > 0 ? &histograms_ : nullptr);
}

void TwinRenderStages::causticEstimate(const PclEyeEstimateParams& params) {
    caustic_ =
        referenceEstimateAtEyeHits(hits_, params, buffers_.primInfo, [&](const std::vector<PclEstimateQuery>& q) {
            return irradiance(spec_.caustic, q);
        });
}

std::vector<PclSplat> TwinRenderStages::connectCaustics(const PclConnectParams& params, const PclCameraParams& camera,
                                                        const std::vector<PclPhoton>& photons,
                                                        const std::vector<float>& times) {
    return referenceConnectCaustics(scene_, geometry_, params, camera, photons, times);
}

void TwinRenderStages::globalEstimate(const PclEyeEstimateParams& params) {
    indirect_ =
        referenceEstimateAtEyeHits(hits_, params, buffers_.primInfo,
                                   [&](const std::vector<PclEstimateQuery>& q) { return irradiance(spec_.global, q); });
}

void TwinRenderStages::finalGather(const PclGatherParams& params) {
    indirect_ = referenceFinalGather(
                    geometry_, buffers_, hits_, params,
                    [&](const std::vector<PclEstimateQuery>& q) { return irradiance(spec_.global, q); },
                    params.histogramCells > 0 ? &histograms_ : nullptr)
                    .radiance;
}

std::vector<float> TwinRenderStages::volumeKthNeighbourDist2(const std::vector<PclPhoton>& photons, uint32_t k,
                                                             float rMax) {
    return referenceKthNeighbourDist2(photons, k, rMax);
}

void TwinRenderStages::volumeEstimate() {
    if (segments_.perRecord == 0)
        throw std::logic_error("render (twin): a volume estimate asked of eye paths without medium segments");
    VolumeSegments segments;
    segments.sampleCount = uint32_t(hits_.size());
    segments.maxSegments = segments_.perRecord;
    segments.segments = segments_.segments;
    segments.counts = segments_.counts;
    volume_.assign(hits_.size(), PclRadiance{0, 0, 0, 0});
    for (const VolumeMapSpec* v : {&spec_.volume, &spec_.volumeCaustic}) {
        if (!v->photons || v->photons->empty()) continue;
        const std::vector<PclRadiance> part =
            referenceVolumeEstimate(*v->photons, v->settings, segments, buffers_.media);
        for (size_t i = 0; i < part.size(); ++i) {
            volume_[i].r += part[i].r;
            volume_[i].g += part[i].g;
            volume_[i].b += part[i].b;
        }
    }
}

void TwinRenderStages::readChunk(uint32_t count, ChunkParts parts, ChunkResult& out) {
    if (hits_.size() != count)
        throw std::logic_error("render (twin): chunk of " + std::to_string(count) + " records read after " +
                               std::to_string(hits_.size()) + " were traced");
    out.hits = hits_;
    auto part = [&](bool have, const std::vector<PclRadiance>& v, std::vector<PclRadiance>& o) {
        if (have) o = v;
        else o.assign(count, PclRadiance{0, 0, 0, 0});
    };
    part(parts.direct, direct_, out.direct);
    part(parts.caustic, caustic_, out.caustic);
    part(parts.indirect, indirect_, out.indirect);
    part(parts.volume, volume_, out.volume);
}

void TwinRenderStages::readSampleRadiance(const SampleRadianceSpec& spec, std::vector<PclRadiance>& out) {
    if (hits_.size() != spec.count)
        throw std::logic_error("render (twin): chunk of " + std::to_string(spec.count) + " records summed after " +
                               std::to_string(hits_.size()) + " were traced");
    const PclRadiance zero{0, 0, 0, 0};
    out.resize(spec.count);
    for (uint32_t i = 0; i < spec.count; ++i) {
        const size_t pixel = (spec.first + i) / spec.samplesPerPixel;
        const int x = int(pixel % spec.width), y = int(pixel / spec.width);
        const std::vector<int32_t>* spans = spec.emitterSpans;
        const bool inSpan = spans && !spans->empty() && x >= (*spans)[2 * y] && x < (*spans)[2 * y + 1];
        const float* e = hits_[i].emitted;
        const PclRadiance em = inSpan ? zero : PclRadiance{e[0], e[1], e[2], 0};
        const PclRadiance& d = spec.parts.direct ? direct_[i] : zero;
        const PclRadiance& c = spec.parts.caustic ? caustic_[i] : zero;
        const PclRadiance& n = spec.parts.indirect ? indirect_[i] : zero;
        const PclRadiance& v = spec.parts.volume ? volume_[i] : zero;
        out[i] = {em.r + d.r + c.r + n.r + v.r, em.g + d.g + c.g + n.g + v.g, em.b + d.b + c.b + n.b + v.b, 0};
    }
}

}  // namespace pcl
