#include "image/film.h"

#include <string>
#include <utility>

#include "core/error.h"

namespace pcl {

Film::Film(int width, int height) : width_(width), height_(height) {
    if (width <= 0 || height <= 0)
        throw InputError("film: expected a positive resolution, got " + std::to_string(width) + "x" +
                         std::to_string(height));
    sum_.assign(static_cast<size_t>(width) * height * 3, 0.0);
    weight_.assign(static_cast<size_t>(width) * height, 0.0);
}

Film::Film(int width, int height, std::vector<double> sums, std::vector<double> weights)
    : width_(width), height_(height), sum_(std::move(sums)), weight_(std::move(weights)) {
    // (No zero-filled arrays first: a 4K film is 265 MB.)
    const size_t pixels = width > 0 && height > 0 ? size_t(width) * height : 0;
    if (!pixels || sum_.size() != 3 * pixels || weight_.size() != pixels)
        throw InputError("film: expected " + std::to_string(3 * pixels) + " sums and " + std::to_string(pixels) +
                         " weights for " + std::to_string(width) + "x" + std::to_string(height) + ", got " +
                         std::to_string(sum_.size()) + " and " + std::to_string(weight_.size()));
}

void Film::add(int x, int y, Vec3 radiance, double weight) {
    size_t i = index(x, y);
    sum_[3 * i + 0] += weight * radiance.x;
    sum_[3 * i + 1] += weight * radiance.y;
    sum_[3 * i + 2] += weight * radiance.z;
    weight_[i] += weight;
}

void Film::splat(int x, int y, Vec3 value) {
    size_t i = index(x, y);
    sum_[3 * i + 0] += value.x;
    sum_[3 * i + 1] += value.y;
    sum_[3 * i + 2] += value.z;
}

void Film::merge(const Film& other) {
    if (other.width_ != width_ || other.height_ != height_)
        throw InputError("film merge: expected " + std::to_string(width_) + "x" + std::to_string(height_) + ", got " +
                         std::to_string(other.width_) + "x" + std::to_string(other.height_));
    for (size_t i = 0; i < sum_.size(); ++i) sum_[i] += other.sum_[i];
    for (size_t i = 0; i < weight_.size(); ++i) weight_[i] += other.weight_[i];
}

Image Film::resolve() const {
    Image image(width_, height_);
    for (size_t i = 0; i < weight_.size(); ++i) {
        double w = weight_[i];
        for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = w > 0.0 ? static_cast<float>(sum_[3 * i + c] / w) : 0.0f;
    }
    return image;
}

Vec3 Film::sum(int x, int y) const {
    size_t i = index(x, y);
    return {static_cast<float>(sum_[3 * i]), static_cast<float>(sum_[3 * i + 1]), static_cast<float>(sum_[3 * i + 2])};
}

double Film::totalWeight() const {
    double t = 0.0;
    for (double w : weight_) t += w;
    return t;
}

}  // namespace pcl
