#include "image/metrics.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "core/error.h"

namespace pcl {

ImageErrors compare(const Image& a, const Image& b, double relMseEpsilon) {
    return compare(a, b, std::vector<uint8_t>(a.rgb.size() / 3, 1), relMseEpsilon);
}

ImageErrors compare(const Image& a, const Image& b, const std::vector<uint8_t>& keep, double relMseEpsilon) {
    if (a.width != b.width || a.height != b.height)
        throw InputError("compare: image sizes differ: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                         " and " + std::to_string(b.width) + "x" + std::to_string(b.height));
    if (a.rgb.empty()) throw InputError("compare: images are empty");
    if (keep.size() != a.rgb.size() / 3)
        throw InputError("compare: a mask of " + std::to_string(keep.size()) + " pixels for " +
                         std::to_string(a.width) + "x" + std::to_string(a.height));
    ImageErrors e;
    // Sums in double: a 4K image has 25M values.
    double se = 0.0, rel = 0.0, sumA = 0.0, sumB = 0.0, maxDiff = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        if (!keep[i / 3]) continue;
        ++e.values;
        double x = a.rgb[i], r = b.rgb[i], d = x - r;
        se += d * d;
        rel += d * d / (r * r + relMseEpsilon);
        sumA += x;
        sumB += r;
        maxDiff = std::max(maxDiff, std::abs(d));
        if (std::isnan(d)) maxDiff = d;  // a NaN anywhere must show, not vanish in max()
    }
    if (e.values == 0) throw InputError("compare: the mask keeps no pixel");
    double n = static_cast<double>(e.values);
    e.rmse = std::sqrt(se / n);
    e.relMse = rel / n;
    e.meanRatio = sumB != 0.0 ? sumA / sumB : (sumA == 0.0 ? 1.0 : std::numeric_limits<double>::infinity());
    e.maxAbsDiff = maxDiff;
    return e;
}

ZTestResult perPixelZTest(const std::vector<Image>& runs, const Image& reference, double threshold,
                          const Image* referenceVariance, double constantTolerance) {
    if (runs.size() < 2)
        throw InputError("Z-test: needs at least 2 independent renders, got " + std::to_string(runs.size()));
    for (const Image& run : runs)
        if (run.width != reference.width || run.height != reference.height)
            throw InputError("Z-test: render " + std::to_string(run.width) + "x" + std::to_string(run.height) +
                             " against a " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                             " reference");
    if (referenceVariance &&
        (referenceVariance->width != reference.width || referenceVariance->height != reference.height))
        throw InputError("Z-test: reference variance image size differs from the reference");
    ZTestResult z;
    z.threshold = threshold;
    z.pixels = reference.pixelCount();
    const double k = static_cast<double>(runs.size());
    double sumAbsZ = 0.0;
    size_t finite = 0;
    auto value = [](const Image& img, size_t i) {
        return static_cast<double>(img.rgb[3 * i]) + img.rgb[3 * i + 1] + img.rgb[3 * i + 2];
    };
    for (size_t i = 0; i < z.pixels; ++i) {
        double r = value(reference, i);
        bool bad = !std::isfinite(r);
        double sum = 0.0;
        for (const Image& run : runs) {
            double x = value(run, i);
            bad = bad || !std::isfinite(x);
            sum += x;
        }
        if (bad) {
            ++z.nonFinite;
            z.failed.push_back(i);
            continue;
        }
        double mean = sum / k, ss = 0.0;
        for (const Image& run : runs) ss += (value(run, i) - mean) * (value(run, i) - mean);
        double var = ss / (k - 1.0) / k + (referenceVariance ? std::max(0.0f, referenceVariance->rgb[3 * i]) : 0.0);
        double diff = std::abs(mean - r), absZ;
        if (var > 0.0) absZ = diff / std::sqrt(var);
        else absZ = diff <= constantTolerance * std::abs(r) ? 0.0 : std::numeric_limits<double>::infinity();
        if (absZ < threshold) ++z.passed;
        else z.failed.push_back(i);
        if (std::isfinite(absZ)) sumAbsZ += absZ;
        z.maxAbsZ = std::max(z.maxAbsZ, absZ);
        ++finite;
    }
    z.meanAbsZ = finite ? sumAbsZ / static_cast<double>(finite) : 0.0;
    return z;
}

std::string formatZTest(const ZTestResult& z) {
    char line[256];
    std::snprintf(line, sizeof line, "Z-test |z| < %.3g: %zu of %zu pixels (%.3f%%), mean |z| %.3f, max |z| %.3g%s",
                  z.threshold, z.passed, z.pixels, 100.0 * z.passFraction(), z.meanAbsZ, z.maxAbsZ,
                  z.nonFinite ? (", " + std::to_string(z.nonFinite) + " non-finite").c_str() : "");
    return line;
}

bool allFinite(const Image& image, size_t* firstBad) {
    for (size_t i = 0; i < image.rgb.size(); ++i)
        if (!std::isfinite(image.rgb[i])) {
            if (firstBad) *firstBad = i / 3;
            return false;
        }
    return true;
}

std::string formatErrors(const ImageErrors& e) {
    char line[256];
    std::snprintf(line, sizeof line, "RMSE %.6g  relMSE %.6g  mean ratio %.6g  max diff %.6g", e.rmse, e.relMse,
                  e.meanRatio, e.maxAbsDiff);
    return line;
}

Image boxDownsample(const Image& image, int factor) {
    if (factor < 1 || image.width % factor || image.height % factor)
        throw InputError("cannot box-downsample a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                         " image by " + std::to_string(factor));
    Image out(image.width / factor, image.height / factor);
    const double inv = 1.0 / (double(factor) * factor);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            double c[3] = {0, 0, 0};
            for (int dy = 0; dy < factor; ++dy)
                for (int dx = 0; dx < factor; ++dx) {
                    Vec3 v = image.at(x * factor + dx, y * factor + dy);
                    c[0] += v.x, c[1] += v.y, c[2] += v.z;
                }
            out.set(x, y, Vec3(float(c[0] * inv), float(c[1] * inv), float(c[2] * inv)));
        }
    return out;
}

}  // namespace pcl
