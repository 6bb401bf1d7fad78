// Error metrics between a test image and a reference: what `photoncl compare` prints and what
// `sweep` charts against time.
#pragma once
#include <string>

#include "image/image.h"

namespace pcl {

struct ImageErrors {
    double rmse = 0.0;         // sqrt(mean over pixels and channels of (a - b)^2)
    double relMse = 0.0;       // mean of (a - b)^2 / (b^2 + epsilon), b the reference
    double meanRatio = 0.0;    // mean(a) / mean(b) over pixels and channels (1: same total energy)
    double maxAbsDiff = 0.0;   // max |a - b| over pixels and channels
    size_t values = 0;         // pixel channels compared
};

// epsilon keeps relMSE finite on black reference pixels; 1e-2 is the value used in the
// denoising / rendering literature (e.g. Rousselle et al. 2011, Bitterli et al. 2016).
constexpr double kRelMseEpsilon = 1e-2;

// Compares `a` (test) against `b` (reference). Different sizes: InputError naming both.
// mean(b) == 0 gives meanRatio 1 if mean(a) is 0 too, otherwise +inf.
ImageErrors compare(const Image& a, const Image& b, double relMseEpsilon = kRelMseEpsilon);

// One line for the command line: "RMSE 0.0123  relMSE 0.00456  mean ratio 1.0012  max diff 0.789".
std::string formatErrors(const ImageErrors& e);

}  // namespace pcl
