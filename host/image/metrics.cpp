#include "image/metrics.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.h"

namespace pcl {

ImageErrors compare(const Image& a, const Image& b, double relMseEpsilon) {
    if (a.width != b.width || a.height != b.height)
        throw InputError("compare: image sizes differ: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                         " and " + std::to_string(b.width) + "x" + std::to_string(b.height));
    ImageErrors e;
    e.values = a.rgb.size();
    if (e.values == 0) throw InputError("compare: images are empty");
    // Sums in double: a 4K image has 25M values.
    double se = 0.0, rel = 0.0, sumA = 0.0, sumB = 0.0, maxDiff = 0.0;
    for (size_t i = 0; i < e.values; ++i) {
        double x = a.rgb[i], r = b.rgb[i], d = x - r;
        se += d * d;
        rel += d * d / (r * r + relMseEpsilon);
        sumA += x;
        sumB += r;
        maxDiff = std::max(maxDiff, std::abs(d));
        if (std::isnan(d)) maxDiff = d;  // a NaN anywhere must show, not vanish in max()
    }
    double n = static_cast<double>(e.values);
    e.rmse = std::sqrt(se / n);
    e.relMse = rel / n;
    e.meanRatio = sumB != 0.0 ? sumA / sumB : (sumA == 0.0 ? 1.0 : std::numeric_limits<double>::infinity());
    e.maxAbsDiff = maxDiff;
    return e;
}

std::string formatErrors(const ImageErrors& e) {
    char line[256];
    std::snprintf(line, sizeof line, "RMSE %.6g  relMSE %.6g  mean ratio %.6g  max diff %.6g", e.rmse, e.relMse,
                  e.meanRatio, e.maxAbsDiff);
    return line;
}

}  // namespace pcl
