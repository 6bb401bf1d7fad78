#include "pipeline/irradiance_source.h"

#include <sstream>

namespace pcl {

std::shared_ptr<IrradianceSource> estimateIrradianceSource(const PhotonMapOnDevice& map, uint32_t maxK,
                                                           const EstimateSettings& settings, const DeviceScene* scene) {
    auto src = std::make_shared<IrradianceSource>();
    std::ostringstream name;
    name << "estimate (" << (map.structure() == KnnStructure::KdTree ? "kd-tree" : "hash grid") << ", "
         << estimateFilterName(settings.filter) << ", k ≤ " << maxK << ")";
    src->name = name.str();
    src->strideFloats = sizeof(PclEstimate) / sizeof(float);
    IrradianceSource* self = src.get();
    src->evaluate = [&map, maxK, settings, scene, self](Device& device, const cl::Buffer& queries, size_t count) {
        cl::Buffer results = device.allocate<PclEstimate>(count, CL_MEM_READ_WRITE, "irradiance: estimates");
        if (count == 0) return results;
        EstimateTiming t = estimateBuffers(device, map, queries, count, maxK, settings, scene, results);
        self->seconds += t.knnSeconds + t.estimateSeconds;
        return results;
    };
    return src;
}

std::shared_ptr<IrradianceSource> precomputedIrradianceSource(const DeviceIrradianceMap& map) {
    auto src = std::make_shared<IrradianceSource>();
    src->name = "precomputed irradiance (" + std::to_string(map.count) + " points)";
    src->strideFloats = 4;
    IrradianceSource* self = src.get();
    src->evaluate = [&map, self](Device& device, const cl::Buffer& queries, size_t count) {
        DeviceIrradianceLookup out;
        if (count == 0) return device.allocate<float>(4, CL_MEM_READ_WRITE, "irradiance: lookups");
        // maxRadius2 = 0 marks no query here (a gather ray without a diffuse hit): skipping
        // their searches saved a sixth to a third of the lookups' time on cornell-box.
        self->seconds += lookupIrradiance(device, map, queries, count, out, true);
        return out.irradiance;
    };
    return src;
}

}  // namespace pcl
