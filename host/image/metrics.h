// Error metrics between a test image and a reference: what `photoncl compare` prints and what
// `sweep` charts against time.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"

namespace pcl {

struct ImageErrors {
    double rmse = 0.0;        // sqrt(mean over pixels and channels of (a - b)^2)
    double relMse = 0.0;      // mean of (a - b)^2 / (b^2 + epsilon), b the reference
    double meanRatio = 0.0;   // mean(a) / mean(b) over pixels and channels (1: same total energy)
    double maxAbsDiff = 0.0;  // max |a - b| over pixels and channels
    size_t values = 0;        // pixel channels compared
};

// epsilon keeps relMSE finite on black reference pixels; 1e-2 is the value used in the
// denoising / rendering literature (e.g. Rousselle et al. 2011, Bitterli et al. 2016).
constexpr double kRelMseEpsilon = 1e-2;

// Compares `a` (test) against `b` (reference). Different sizes: InputError naming both.
// mean(b) == 0 gives meanRatio 1 if mean(a) is 0 too, otherwise +inf.
ImageErrors compare(const Image& a, const Image& b, double relMseEpsilon = kRelMseEpsilon);
// The same over the pixels whose `keep` entry is nonzero (one per pixel, row-major; InputError
// when its size is not the pixel count or it keeps no pixel).
ImageErrors compare(const Image& a, const Image& b, const std::vector<uint8_t>& keep,
                    double relMseEpsilon = kRelMseEpsilon);

// Per-pixel Z-test of K independent renders against a reference: is what
// differs from the reference only the renders' own noise? Per pixel, the value is the channel
// sum R+G+B; with m and s² the mean and (unbiased) variance of the K renders' values and r the
// reference's, z = (m − r) / sqrt(s²/K + v_ref), v_ref the reference's own variance if known
// (else 0). For unbiased renders with Gaussian-like pixel errors z follows Student's t with K−1
// degrees of freedom, so the expected pass rate at a threshold is known (t_{15}: P(|t| < 4) =
// 0.9988, P(|t| < 3.29) = 0.995); a bias larger than about threshold × the standard error of
// the mean fails the pixel. A pixel whose K values are all equal (a black corner, a lamp seen
// straight on) passes when they equal the reference within `constantTolerance` relative
// (default 1e-3: references stored as half floats round at 2^-11), never by dividing by zero.
struct ZTestResult {
    size_t pixels = 0;     // pixels tested
    size_t passed = 0;     // |z| < threshold
    size_t nonFinite = 0;  // pixels where a render or the reference is NaN/Inf (counted as failed)
    double threshold = 0.0;
    double meanAbsZ = 0.0;  // over the finite pixels (≈ 0.8 for pure noise)
    double maxAbsZ = 0.0;
    std::vector<size_t> failed;  // indices (y · width + x) of the pixels that did not pass
    double passFraction() const { return pixels ? static_cast<double>(passed) / pixels : 0.0; }
};

// `runs` (K ≥ 2, all the reference's size); `referenceVariance`, if given, holds the reference's
// per-pixel variance of the channel sum in its R channel. Size mismatch or K < 2: InputError.
ZTestResult perPixelZTest(const std::vector<Image>& runs, const Image& reference, double threshold = 4.0,
                          const Image* referenceVariance = nullptr, double constantTolerance = 1e-3);

std::string formatZTest(const ZTestResult& z);

// True when every value of the image is finite; `firstBad` (if given) receives the pixel index
// of the first NaN/Inf.
bool allFinite(const Image& image, size_t* firstBad = nullptr);

// One line for the command line: "RMSE 0.0123  relMSE 0.00456  mean ratio 1.0012  max diff 0.789".
std::string formatErrors(const ImageErrors& e);

// 2×2, 4×4 … box average, each output pixel the mean of factor² input pixels (the film's box
// filter makes it the expectation of a render at the smaller size). InputError unless factor
// divides both sides.
Image boxDownsample(const Image& image, int factor);

}  // namespace pcl
