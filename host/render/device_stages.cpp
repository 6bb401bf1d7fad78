#include "render/device_stages.h"

#include <algorithm>
#include <cmath>

#include <stdexcept>
#include "pipeline/accumulate.h"
#include "pipeline/camera_rays.h"
#include "pipeline/connect_caustics.h"
#include "pipeline/estimate.h"
#include "pipeline/eye_estimate.h"
#include "pipeline/eye_paths.h"
#include "pipeline/final_gather.h"
#include "pipeline/irradiance_source.h"
#include "pipeline/precomputed_irradiance.h"
#include "pipeline/volume_estimate.h"
#include "render/fixed_radius_source.h"

namespace pcl {

struct DeviceRenderStages::Maps {
    std::unique_ptr<PhotonMapOnDevice> global, caustic, histogram;
    std::unique_ptr<DeviceVolumeMap> volume[2];  // the global and the caustic volume map
    VolumeEstimateSettings volumeSettings[2];
    std::unique_ptr<DeviceIrradianceMap> irradiance;
    std::shared_ptr<IrradianceSource> globalSource, causticSource;
};

DeviceRenderStages::DeviceRenderStages(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                       const SceneBuffers& buffers, const PhotonRenderSettings& s)
    : device_(device), geometry_(geometry), buffers_(buffers), s_(s), dscene_(device, geometry, buffers),
      lights_(device, buildAreaLightTable(buffers, geometry.primitiveCount())), maps_(std::make_unique<Maps>()) {
    const size_t passSamples = size_t(scene.camera.width) * scene.camera.height * s.strata * s.strata;
    chunk_ = eyeChunkSamples(s, device.info().maxAlloc, passSamples);
    rays_ = device.allocate<PclRay>(chunk_, CL_MEM_READ_WRITE, "render: camera rays");
    hits_ = device.allocate<PclEyeHit>(chunk_, CL_MEM_READ_WRITE, "render: eye hits");
    directRad_ = device.allocate<PclRadiance>(chunk_, CL_MEM_READ_WRITE, "render: direct radiance");
    causticRad_ = device.allocate<PclRadiance>(chunk_, CL_MEM_READ_WRITE, "render: caustic radiance");
    indirectRad_ = device.allocate<PclRadiance>(chunk_, CL_MEM_READ_WRITE, "render: indirect radiance");
    sampleRad_ = device.allocate<PclRadiance>(chunk_, CL_MEM_READ_WRITE, "render: sample radiance");
    spans_ = device.allocate<int32_t>(1, CL_MEM_READ_ONLY, "render: emitter spans");
}

DeviceRenderStages::~DeviceRenderStages() = default;

size_t DeviceRenderStages::chunkSamples(size_t passSamples) const { return std::min(chunk_, passSamples); }

PassPhotons DeviceRenderStages::tracePhotons(const PhotonPassOptions& options) {
    PhotonMaps maps = runPhotonPass(device_, geometry_, buffers_, options);
    PassPhotons p;
    p.global = std::move(maps.global);
    p.caustic = std::move(maps.caustic);
    p.causticTimes = std::move(maps.causticTimes);
    p.volume = std::move(maps.volume);
    p.volumeCaustic = std::move(maps.volumeCaustic);
    p.globalEmitted = maps.stats.global.emitted;
    p.causticEmitted = maps.stats.caustic.emitted;
    return p;
}

void DeviceRenderStages::buildMaps(const PassMapSpec& spec) {
    maps_ = std::make_unique<Maps>();
    const float searchRadius = std::sqrt(spec.radius2);
    auto build = [&](const MapSpec& m, std::unique_ptr<PhotonMapOnDevice>& map,
                     std::shared_ptr<IrradianceSource>& source) {
        switch (m.reader) {
            case MapReader::None: break;
            case MapReader::Estimate:
                map = std::make_unique<PhotonMapOnDevice>(device_, *m.photons, s_.structure, searchRadius);
                source = estimateIrradianceSource(*map, m.maxK, m.estimate, &dscene_);
                break;
            case MapReader::FixedRadius:
                map = std::make_unique<PhotonMapOnDevice>(device_, *m.photons, s_.structure, searchRadius);
                source = fixedRadiusSource(*map, m.maxK, m.estimate, spec.radius2, &dscene_);
                break;
            case MapReader::Precomputed:
                maps_->irradiance = std::make_unique<DeviceIrradianceMap>(
                    precomputeIrradiance(device_, *m.photons, m.precomputed, &dscene_));
                source = precomputedIrradianceSource(*maps_->irradiance);
                break;
        }
    };
    build(spec.global, maps_->global, maps_->globalSource);
    build(spec.caustic, maps_->caustic, maps_->causticSource);
    const VolumeMapSpec* volume[2] = {&spec.volume, &spec.volumeCaustic};
    for (int v = 0; v < 2; ++v)
        if (volume[v]->photons && !volume[v]->photons->empty()) {
            maps_->volume[v] =
                std::make_unique<DeviceVolumeMap>(buildVolumeMap(device_, *volume[v]->photons, volume[v]->settings));
            maps_->volumeSettings[v] = volume[v]->settings;
        }
    if (spec.histogramPhotons)
        maps_->histogram =
            std::make_unique<PhotonMapOnDevice>(device_, *spec.histogramPhotons, s_.structure, searchRadius);
}

void DeviceRenderStages::cameraRays(const PclCameraParams& params) { generateCameraRays(device_, params, rays_); }

void DeviceRenderStages::eyePaths(const PclEyeParams& params) {
    // Media: the chunk's segment slots (for the volume estimate), allocated at the first chunk
    // that needs them; one-element placeholders otherwise.
    const size_t slots = std::max<size_t>(1, size_t(params.volumeSegments) * chunk_);
    if (!segmentCounts_() || slots > segmentSlots_) {
        segments_ = device_.allocate<PclVolumeSegment>(slots, CL_MEM_READ_WRITE, "render: eye segments");
        segmentCounts_ = device_.allocate<uint32_t>(params.volumeSegments > 0 ? chunk_ : 1, CL_MEM_READ_WRITE,
                                                    "render: eye segment counts");
        segmentSlots_ = slots;
    }
    traceEyePaths(device_, dscene_, lights_, params, rays_, hits_, segments_, segmentCounts_);
    lastEye_ = params;
}

std::vector<float> DeviceRenderStages::volumeKthNeighbourDist2(const std::vector<PclPhoton>& photons, uint32_t k,
                                                               float rMax) {
    return pcl::volumeKthNeighbourDist2(device_, photons, k, rMax);
}

void DeviceRenderStages::volumeEstimate() {
    if (lastEye_.volumeSegments == 0)
        throw std::logic_error("render: a volume estimate asked of eye paths without medium segments");
    for (int v = 0; v < 2; ++v) {
        volumeParts_[v] = maps_->volume[v] != nullptr;
        if (!volumeParts_[v]) continue;
        if (!volumeRad_[v]())
            volumeRad_[v] = device_.allocate<PclRadiance>(
                chunk_, CL_MEM_READ_WRITE, v == 0 ? "render: volume radiance" : "render: volume caustics");
        const PclVolumeEstimateParams p = volumeEstimateParams(*maps_->volume[v], maps_->volumeSettings[v],
                                                               lastEye_.sampleCount, lastEye_.volumeSegments,
                                                               uint32_t(buffers_.media.size()));
        volumeEstimateBeams(device_, p, segments_, segmentCounts_, dscene_.media, *maps_->volume[v], volumeRad_[v]);
    }
}

void DeviceRenderStages::gatherHistograms(const PclGatherParams& params) {
    if (!maps_->histogram)
        throw std::logic_error("render: importance histograms asked of a pass without the global map");
    histograms_ = buildGatherHistograms(device_, *maps_->histogram, params, hits_);
}

void DeviceRenderStages::directLight(const PclDirectParams& params) {
    if (params.histogramCells > 0) pcl::directLight(device_, dscene_, lights_, params, hits_, histograms_, directRad_);
    else pcl::directLight(device_, dscene_, lights_, params, hits_, directRad_);
}

void DeviceRenderStages::causticEstimate(const PclEyeEstimateParams& params) {
    causticRadiance(device_, params, hits_, dscene_.primInfo, *maps_->causticSource, causticRad_);
}

std::vector<PclSplat> DeviceRenderStages::connectCaustics(const PclConnectParams& params, const PclCameraParams& camera,
                                                          const std::vector<PclPhoton>& photons,
                                                          const std::vector<float>& times) {
    return pcl::connectCaustics(device_, dscene_, params, camera, photons, times);
}

void DeviceRenderStages::globalEstimate(const PclEyeEstimateParams& params) {
    estimateAtEyeHits(device_, params, hits_, dscene_.primInfo, *maps_->globalSource, indirectRad_);
}

void DeviceRenderStages::finalGather(const PclGatherParams& params) {
    if (params.histogramCells > 0)
        pcl::finalGather(device_, dscene_, lights_, params, hits_, histograms_, *maps_->globalSource, indirectRad_);
    else pcl::finalGather(device_, dscene_, lights_, params, hits_, *maps_->globalSource, indirectRad_);
}

void DeviceRenderStages::readChunk(uint32_t count, ChunkParts parts, ChunkResult& out) {
    device_.downloadInto(hits_, count, out.hits);
    auto part = [&](bool have, const cl::Buffer& b, std::vector<PclRadiance>& v) {
        if (have) device_.downloadInto(b, count, v);
        else v.assign(count, PclRadiance{0, 0, 0, 0});
    };
    part(parts.direct, directRad_, out.direct);
    part(parts.caustic, causticRad_, out.caustic);
    part(parts.indirect, indirectRad_, out.indirect);
    // The two volume maps' parts, added on the host.
    out.volume.assign(count, PclRadiance{0, 0, 0, 0});
    if (!parts.volume) return;
    std::vector<PclRadiance> v;
    for (int m = 0; m < 2; ++m) {
        if (!volumeParts_[m]) continue;
        device_.downloadInto(volumeRad_[m], count, v);
        for (uint32_t i = 0; i < count; ++i) {
            out.volume[i].r += v[i].r;
            out.volume[i].g += v[i].g;
            out.volume[i].b += v[i].b;
        }
    }
}

void DeviceRenderStages::readSampleRadiance(const SampleRadianceSpec& spec, std::vector<PclRadiance>& out) {
    PclAccumulateParams p{};
    p.firstPixel = static_cast<uint32_t>(spec.first / spec.samplesPerPixel);
    p.firstSubsample = static_cast<uint32_t>(spec.first % spec.samplesPerPixel);
    p.sampleCount = spec.count;
    p.samplesPerPixel = spec.samplesPerPixel;
    p.width = spec.width;
    p.parts = (spec.parts.direct ? PCL_ACCUMULATE_DIRECT : 0u) | (spec.parts.caustic ? PCL_ACCUMULATE_CAUSTIC : 0u) |
              (spec.parts.indirect ? PCL_ACCUMULATE_INDIRECT : 0u) |
              (spec.parts.volume && volumeParts_[0] ? PCL_ACCUMULATE_VOLUME0 : 0u) |
              (spec.parts.volume && volumeParts_[1] ? PCL_ACCUMULATE_VOLUME1 : 0u);
    p.emitterSpans = spec.emitterSpans && !spec.emitterSpans->empty() ? 1u : 0u;
    if (p.emitterSpans && *spec.emitterSpans != spansOnHost_) {  // set once a render
        spansOnHost_ = *spec.emitterSpans;
        spans_ = device_.upload(spansOnHost_, CL_MEM_READ_ONLY, "render: emitter spans");
    }
    // Parts not named are not read: any buffer stands in for them.
    const cl::Buffer& v0 = volumeParts_[0] ? volumeRad_[0] : directRad_;
    const cl::Buffer& v1 = volumeParts_[1] ? volumeRad_[1] : directRad_;
    accumulateSamples(device_, p, hits_, directRad_, causticRad_, indirectRad_, v0, v1, spans_, sampleRad_);
    device_.downloadInto(sampleRad_, spec.count, out);
}

}  // namespace pcl
