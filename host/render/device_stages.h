// The render's stages on an OpenCL device (render/render_stages.h): the scene's device buffers
// and the chunk's eye buffers live for the whole render; each pass's maps are uploaded and their
// search structures built on the device; the parts stay on the device until readChunk.
#pragma once
#include <memory>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/device_scene.h"
#include "pipeline/direct_light.h"
#include "prep/area_light_table.h"
#include "prep/scene_buffers.h"
#include "render/render_settings.h"
#include "render/render_stages.h"
#include "scene/scene.h"

namespace pcl {

class DeviceRenderStages : public RenderStages {
public:
    // s: the render's settings (the search structure, chunk size and photon batch come from it).
    DeviceRenderStages(Device& device, const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers,
                       const PhotonRenderSettings& s);
    ~DeviceRenderStages() override;

    size_t chunkSamples(size_t passSamples) const override;
    void wait() override { device_.finish(); }
    PassPhotons tracePhotons(const PhotonPassOptions& options) override;
    void buildMaps(const PassMapSpec& spec) override;
    void cameraRays(const PclCameraParams& params) override;
    void eyePaths(const PclEyeParams& params) override;
    void gatherHistograms(const PclGatherParams& params) override;
    void directLight(const PclDirectParams& params) override;
    void causticEstimate(const PclEyeEstimateParams& params) override;
    std::vector<PclSplat> connectCaustics(const PclConnectParams& params, const PclCameraParams& camera,
                                          const std::vector<PclPhoton>& photons,
                                          const std::vector<float>& times) override;
    void globalEstimate(const PclEyeEstimateParams& params) override;
    void finalGather(const PclGatherParams& params) override;
    void volumeEstimate() override;
    std::vector<float> volumeKthNeighbourDist2(const std::vector<PclPhoton>& photons, uint32_t k, float rMax) override;
    void readChunk(uint32_t count, ChunkParts parts, ChunkResult& out) override;
    void readSampleRadiance(const SampleRadianceSpec& spec, std::vector<PclRadiance>& out) override;

private:
    struct Maps;  // the pass's maps and their readers
    Device& device_;
    const SceneGeometry& geometry_;
    const SceneBuffers& buffers_;
    const PhotonRenderSettings& s_;
    DeviceScene dscene_;
    DeviceAreaLights lights_;
    size_t chunk_ = 0;
    cl::Buffer rays_, hits_, directRad_, causticRad_, indirectRad_, histograms_;
    cl::Buffer sampleRad_, spans_;         // readSampleRadiance: its output; the emitter spans (2 ints a row)
    std::vector<int32_t> spansOnHost_;     // what spans_ holds
    cl::Buffer segments_, segmentCounts_;  // media: the eye records' medium segments (eyePaths)
    size_t segmentSlots_ = 0;
    PclEyeParams lastEye_{};   // the last eyePaths launch: its records and segment slots
    cl::Buffer volumeRad_[2];  // volumeEstimate: the global and the caustic volume map's parts
    bool volumeParts_[2] = {false, false};
    std::unique_ptr<Maps> maps_;
};

}  // namespace pcl
