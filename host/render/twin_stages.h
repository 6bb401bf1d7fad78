// The render's stages on the CPU twin (render/render_stages.h; host/reference): the same seeds
// and parameters as the device, each stage the twin `check` compares the kernel with, on host
// vectors, multi-threaded (reference/parallel_for.h). No OpenCL: it renders where no device
// exists. Its k-nearest searches and precomputed-irradiance lookups are brute force (the twin's
// definition of the answer), so it suits small images: a witness for the device render.
#pragma once
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/scene_buffers.h"
#include "reference/eye_paths.h"
#include "render/render_stages.h"
#include "scene/scene.h"

namespace pcl {

class TwinRenderStages : public RenderStages {
public:
    TwinRenderStages(const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers);

    // Up to 2^18 samples a chunk (the device's largest chunk): bounds the gather queries held.
    size_t chunkSamples(size_t passSamples) const override;
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
    // E rgb at each query (maxRadius2 = 0 gives 0) from one map as the spec reads it.
    std::vector<Vec3> irradiance(const MapSpec& map, const std::vector<PclEstimateQuery>& queries) const;

    const Scene& scene_;
    const SceneGeometry& geometry_;
    const SceneBuffers& buffers_;
    PassMapSpec spec_;
    std::vector<PclIrradiancePoint> points_;  // precomputed irradiance: the points and their covers
    std::vector<float> cover_;
    std::vector<float> nondirect_;  // 4 floats per point: the irradiance of the photons of bounce > 0
    std::vector<PclRay> rays_;
    std::vector<PclEyeHit> hits_;
    EyeVolumeSegments segments_;  // media: the records' medium segments (eyePaths)
    std::vector<float> histograms_;
    std::vector<PclRadiance> direct_, caustic_, indirect_, volume_;
};

}  // namespace pcl
