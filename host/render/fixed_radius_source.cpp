#include "render/fixed_radius_source.h"

#include <vector>

#include "core/error.h"
#include "render/fixed_radius.h"

namespace pcl {

std::shared_ptr<IrradianceSource> fixedRadiusSource(const PhotonMapOnDevice& map, uint32_t maxK,
                                                    const EstimateSettings& settings, float radius2,
                                                    const DeviceScene* scene) {
    if (settings.filter != EstimateFilter::Box)
        throw InternalError("fixed-radius estimate: needs the box filter, got " +
                            std::string(estimateFilterName(settings.filter)));
    if (!(radius2 > 0.0f)) throw InternalError("fixed-radius estimate: radius² must be positive");
    std::shared_ptr<IrradianceSource> knn = estimateIrradianceSource(map, maxK, settings, scene);
    auto source = std::make_shared<IrradianceSource>();
    source->name = "fixed-radius estimate (box, r² " + std::to_string(radius2) + ")";
    source->strideFloats = 8;  // PclEstimate
    IrradianceSource* self = source.get();
    source->evaluate = [knn, maxK, radius2, self](Device& device, const cl::Buffer& queries, size_t count) {
        cl::Buffer results = knn->evaluate(device, queries, count);
        self->seconds = knn->seconds;
        // The rescale runs on the host: one pass over count records, small beside the search.
        std::vector<PclEstimate> e = device.download<PclEstimate>(results, count);
        std::vector<PclEstimateQuery> q = device.download<PclEstimateQuery>(queries, count);
        for (size_t i = 0; i < count; ++i) rescaleToFixedRadius(e[i], q[i], maxK, radius2);
        return device.upload(e, CL_MEM_READ_WRITE, "fixed-radius estimate: results");
    };
    return source;
}

}  // namespace pcl
