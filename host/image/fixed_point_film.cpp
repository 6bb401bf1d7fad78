#include "image/fixed_point_film.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "core/error.h"

namespace pcl {
namespace {

using Fixed = FixedPointFilm::Fixed;

[[noreturn]] void overflow(int width, size_t pixel, double value) {
    char range[32];
    std::snprintf(range, sizeof range, "%.3g", FixedPointFilm::kMaxValue);
    char sum[32];
    std::snprintf(sum, sizeof sum, "%.6g", value);
    throw InputError("fixed-point film: pixel (" + std::to_string(pixel % width) + ", " +
                     std::to_string(pixel / width) + ") sums to " + sum + ", beyond the film's range ±" + range +
                     " (2^95: 128-bit fixed point with 32 fraction bits); render fewer passes per image or scale the "
                     "scene's light down");
}

// Rounds v · 2^32 to the nearest integer, ties away from zero (std::round: the same on every
// machine; exact, as v · 2^32 is exact). |v| < 2^95 keeps the result below 2^127.
Fixed quantise(double v, int width, size_t pixel) {
    if (!(std::fabs(v) < FixedPointFilm::kMaxValue)) overflow(width, pixel, v);
    return Fixed(std::round(v * FixedPointFilm::kScale));
}

Fixed addChecked(Fixed a, Fixed b, int width, size_t pixel) {
    Fixed out;
    if (__builtin_add_overflow(a, b, &out)) overflow(width, pixel, (double(a) + double(b)) / FixedPointFilm::kScale);
    return out;
}

}  // namespace

FixedPointFilm::FixedPointFilm(int width, int height) : width_(width), height_(height) {
    if (width <= 0 || height <= 0)
        throw InputError("fixed-point film: expected a positive resolution, got " + std::to_string(width) + "x" +
                         std::to_string(height));
    sum_.assign(size_t(width) * height * 3, 0);
    weight_.assign(size_t(width) * height, 0);
}

FixedPointFilm::FixedPointFilm(int width, int height, std::vector<Fixed> sums, std::vector<Fixed> weights)
    : width_(width), height_(height), sum_(std::move(sums)), weight_(std::move(weights)) {
    const size_t pixels = width > 0 && height > 0 ? size_t(width) * height : 0;
    if (!pixels || sum_.size() != 3 * pixels || weight_.size() != pixels)
        throw InputError("fixed-point film: expected " + std::to_string(3 * pixels) + " sums and " +
                         std::to_string(pixels) + " weights for " + std::to_string(width) + "x" +
                         std::to_string(height) + ", got " + std::to_string(sum_.size()) + " and " +
                         std::to_string(weight_.size()));
}

void FixedPointFilm::addPass(const Film& pass) {
    if (pass.width() != width_ || pass.height() != height_)
        throw InputError("fixed-point film: expected a " + std::to_string(width_) + "x" + std::to_string(height_) +
                         " pass, got " + std::to_string(pass.width()) + "x" + std::to_string(pass.height()));
    const std::vector<double>& s = pass.sums();
    const std::vector<double>& w = pass.weights();
    for (size_t i = 0; i < sum_.size(); ++i)
        sum_[i] = addChecked(sum_[i], quantise(s[i], width_, i / 3), width_, i / 3);
    for (size_t i = 0; i < weight_.size(); ++i)
        weight_[i] = addChecked(weight_[i], quantise(w[i], width_, i), width_, i);
}

void FixedPointFilm::add(const FixedPointFilm& other) {
    if (other.width_ != width_ || other.height_ != height_)
        throw InputError("fixed-point film: expected " + std::to_string(width_) + "x" + std::to_string(height_) +
                         ", got " + std::to_string(other.width_) + "x" + std::to_string(other.height_));
    for (size_t i = 0; i < sum_.size(); ++i) sum_[i] = addChecked(sum_[i], other.sum_[i], width_, i / 3);
    for (size_t i = 0; i < weight_.size(); ++i) weight_[i] = addChecked(weight_[i], other.weight_[i], width_, i);
}

Film FixedPointFilm::toFilm() const {
    if (width_ == 0) return Film();
    std::vector<double> s(sum_.size()), w(weight_.size());
    for (size_t i = 0; i < s.size(); ++i) s[i] = double(sum_[i]) / kScale;
    for (size_t i = 0; i < w.size(); ++i) w[i] = double(weight_[i]) / kScale;
    return Film(width_, height_, std::move(s), std::move(w));
}

Image FixedPointFilm::resolve() const {
    if (width_ == 0) return Image();
    Image image(width_, height_);
    for (size_t i = 0; i < weight_.size(); ++i) {
        const double w = double(weight_[i]) / kScale;  // as toFilm() then Film::resolve()
        for (int c = 0; c < 3; ++c)
            image.rgb[3 * i + c] = w > 0.0 ? static_cast<float>(double(sum_[3 * i + c]) / kScale / w) : 0.0f;
    }
    return image;
}

}  // namespace pcl
