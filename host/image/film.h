// Film: per-pixel sums of weighted radiance samples and their weights (box filter: every
// sample counts toward the pixel it was taken in). Films of the same size merge by adding
// sums, so passes, threads and batch shards combine exactly; resolve() divides.
#pragma once
#include <vector>

#include "core/vec3.h"
#include "image/image.h"

namespace pcl {

class Film {
public:
    Film() = default;
    Film(int width, int height);
    // From stored sums (3 per pixel) and weights (1 per pixel); sizes checked (InputError).
    Film(int width, int height, std::vector<double> sums, std::vector<double> weights);

    int width() const { return width_; }
    int height() const { return height_; }

    // Adds weight * radiance to pixel (x, y) and weight to its weight sum.
    void add(int x, int y, Vec3 radiance, double weight = 1.0);
    // Adds `value` to pixel (x, y)'s sum and nothing to its weight: a light tracer's splat,
    // whose pixel is where its light lands, not where a sample was taken (pbrt's AddSplat).
    // With W the weight the film's samples give the pixel, the splats must sum to W times
    // their estimate of the pixel.
    void splat(int x, int y, Vec3 value);
    // Adds another film's sums pixel by pixel; a size mismatch is an InputError.
    void merge(const Film& other);
    // Estimate per pixel: sum / weight (black where no sample landed).
    Image resolve() const;

    Vec3 sum(int x, int y) const;
    double weight(int x, int y) const { return weight_[index(x, y)]; }
    double totalWeight() const;
    // The sums as held (doubles, 3 per pixel) and the weights (1 per pixel): for exact copies
    // (image/fixed_point_film.h rounds them to fixed point).
    const std::vector<double>& sums() const { return sum_; }
    const std::vector<double>& weights() const { return weight_; }

private:
    size_t index(int x, int y) const { return static_cast<size_t>(y) * width_ + x; }
    int width_ = 0, height_ = 0;
    std::vector<double> sum_;     // 3 per pixel; double so long runs and merges lose nothing
    std::vector<double> weight_;  // 1 per pixel
};

}  // namespace pcl
