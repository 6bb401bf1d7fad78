// FixedPointFilm: per-pixel sums of radiance and weight as 64-bit fixed-point integers, so that
// adding passes (or shards of passes) gives the same bits whatever the grouping: integer
// addition is associative, floating-point addition is not. Each pass is rendered into a Film
// (doubles, samples added in a fixed order), then its per-pixel sums are rounded to fixed point
// once and added (issue 8: the merge of N shards is bit-identical to one run of the same passes).
//
// Scale: 2^32 (kFractionBits). A value's step is 2^-32 ≈ 2.3e-10 (one rounding per pixel and
// pass, far below a float's resolution of any value above ~1e-2 once divided by the samples),
// and a pixel's sum may reach 2^31 ≈ 2.1e9 (e.g. radiance 1e6 over 2000 one-sample passes).
// A sum outside that range throws InputError naming the pixel: it is never silently wrapped.
#pragma once
#include <cstdint>
#include <vector>

#include "image/film.h"
#include "image/image.h"

namespace pcl {

class FixedPointFilm {
public:
    static constexpr int kFractionBits = 32;
    static constexpr double kScale = 4294967296.0;  // 2^kFractionBits
    // The largest |sum| a pixel channel may hold: 2^63 / 2^32, less a margin for rounding.
    static constexpr double kMaxValue = 2147483647.0;

    FixedPointFilm() = default;
    FixedPointFilm(int width, int height);
    // From stored sums (a shard file): 3 per pixel and 1 weight per pixel; sizes checked.
    FixedPointFilm(int width, int height, std::vector<int64_t> sums, std::vector<int64_t> weights);

    int width() const { return width_; }
    int height() const { return height_; }

    // Rounds `pass`'s per-pixel sums and weights to fixed point and adds them. A pass with a
    // sum beyond kMaxValue, or a total that would overflow, throws InputError naming the pixel.
    void addPass(const Film& pass);
    // Adds another film's integers (exact); size mismatch or overflow: InputError.
    void add(const FixedPointFilm& other);

    // The sums as a Film of doubles (each exactly fixed · 2^-32 where |fixed| < 2^53).
    Film toFilm() const;
    // sum / weight per pixel (black where no sample landed); equals toFilm().resolve().
    Image resolve() const { return toFilm().resolve(); }

    const std::vector<int64_t>& sums() const { return sum_; }
    const std::vector<int64_t>& weights() const { return weight_; }

private:
    int width_ = 0, height_ = 0;
    std::vector<int64_t> sum_;     // 3 per pixel
    std::vector<int64_t> weight_;  // 1 per pixel
};

}  // namespace pcl
