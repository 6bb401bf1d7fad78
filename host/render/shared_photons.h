// Two renders that read the same photon maps: the first records each pass's photons from its
// own stages, the second is answered from that record instead of tracing its own. The device
// and twin photon passes agree only up to what `check --stage pass` allows (≤ 0.1 % of paths
// diverge by a flipped rounding); with precomputed irradiance one divergent path shifts which
// photons are selected after it, and every point's estimate with them. Given the same photons,
// the device's and the twin's eye passes can be held per pixel (`check --stage render`, the
// render twin test); the independent photon passes are compared on their own.
//
//   PhotonPassRecord record;
//   SharedPhotonStages dev(deviceStages, record, SharedPhotonStages::Mode::Record);
//   renderPhotonMapped(dev, ...);
//   SharedPhotonStages twin(twinStages, record, SharedPhotonStages::Mode::Replay);
//   renderPhotonMapped(twin, ...);                  // the same settings: the same passes
#pragma once
#include <map>

#include "render/render_stages.h"

namespace pcl {

// Each pass's photons by the pass's global index (PhotonPassOptions::pass).
using PhotonPassRecord = std::map<uint32_t, PassPhotons>;

// Every stage is `inner`'s except tracePhotons: Record traces with `inner` and keeps a copy;
// Replay returns the recorded pass (std::logic_error when it was not recorded, or recorded
// with other photon counts).
class SharedPhotonStages : public RenderStages {
public:
    enum class Mode { Record, Replay };
    SharedPhotonStages(RenderStages& inner, PhotonPassRecord& record, Mode mode)
        : inner_(inner), record_(record), mode_(mode) {}

    PassPhotons tracePhotons(const PhotonPassOptions& options) override;

    size_t chunkSamples(size_t passSamples) const override { return inner_.chunkSamples(passSamples); }
    void wait() override { inner_.wait(); }
    void buildMaps(const PassMapSpec& spec) override { inner_.buildMaps(spec); }
    void cameraRays(const PclCameraParams& p) override { inner_.cameraRays(p); }
    void eyePaths(const PclEyeParams& p) override { inner_.eyePaths(p); }
    void gatherHistograms(const PclGatherParams& p) override { inner_.gatherHistograms(p); }
    void directLight(const PclDirectParams& p) override { inner_.directLight(p); }
    void causticEstimate(const PclEyeEstimateParams& p) override { inner_.causticEstimate(p); }
    std::vector<PclSplat> connectCaustics(const PclConnectParams& p, const PclCameraParams& camera,
                                          const std::vector<PclPhoton>& photons,
                                          const std::vector<float>& times) override {
        return inner_.connectCaustics(p, camera, photons, times);
    }
    void globalEstimate(const PclEyeEstimateParams& p) override { inner_.globalEstimate(p); }
    void finalGather(const PclGatherParams& p) override { inner_.finalGather(p); }
    void volumeEstimate() override { inner_.volumeEstimate(); }
    std::vector<float> volumeKthNeighbourDist2(const std::vector<PclPhoton>& photons, uint32_t k, float rMax) override {
        return inner_.volumeKthNeighbourDist2(photons, k, rMax);
    }
    void readChunk(uint32_t count, ChunkParts parts, ChunkResult& out) override { inner_.readChunk(count, parts, out); }
    void readSampleRadiance(const SampleRadianceSpec& spec, std::vector<PclRadiance>& out) override {
        inner_.readSampleRadiance(spec, out);
    }

private:
    RenderStages& inner_;
    PhotonPassRecord& record_;
    Mode mode_;
};

}  // namespace pcl
