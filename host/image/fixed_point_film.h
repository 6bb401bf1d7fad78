// FixedPointFilm: per-pixel sums of radiance and weight as 128-bit fixed-point integers, so that
// adding passes (or shards of passes) gives the same bits whatever the grouping: integer
// addition is associative, floating-point addition is not. Each pass is rendered into a Film
// (doubles, samples added in a fixed order), then its per-pixel sums are rounded to fixed point
// once and added (so the merge of N batch shards is bit-identical to one run of the same passes).
//
// Scale: 2^32 (kFractionBits). A value's step is 2^-32 ≈ 2.3e-10 (one rounding per pixel and
// pass, far below a float's resolution of any value above ~1e-2 once divided by the samples),
// and a pixel's sum must stay below 2^95 ≈ 4.0e28 in magnitude (__int128: 127 bits less 32
// fraction bits), so lights in SI units fit: the sun seen directly (~2e7 W/(m² sr)) overflows
// 64-bit sums (±2^31) after ~100 one-sample passes, 128-bit ones after ~2e21. A sum outside the
// range throws InputError naming the pixel: it is never silently wrapped.
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
    // A pixel channel's |sum| must stay below this: 2^127 / 2^32 (a pass's value below it
    // rounds to an integer below 2^127; sums are checked on every addition).
    static constexpr double kMaxValue = 39614081257132168796771975168.0;  // 2^95
    using Fixed = __int128;                                               // GCC/Clang; 16 bytes, two's complement

    FixedPointFilm() = default;
    FixedPointFilm(int width, int height);
    // From stored sums (a shard file): 3 per pixel and 1 weight per pixel; sizes checked.
    FixedPointFilm(int width, int height, std::vector<Fixed> sums, std::vector<Fixed> weights);

    int width() const { return width_; }
    int height() const { return height_; }

    // Rounds `pass`'s per-pixel sums and weights to fixed point and adds them. A pass with a
    // sum beyond kMaxValue, or a total that would overflow, throws InputError naming the pixel.
    void addPass(const Film& pass);
    // Adds another film's integers (exact); size mismatch or overflow: InputError.
    void add(const FixedPointFilm& other);

    // The sums as a Film of doubles (fixed · 2^-32, exact where |fixed| < 2^53, else rounded to
    // the nearest double).
    Film toFilm() const;
    // sum / weight per pixel (black where no sample landed): the same bits as
    // toFilm().resolve(), without the film of doubles (a merge's peak: 265 MB at 4K).
    Image resolve() const;

    const std::vector<Fixed>& sums() const { return sum_; }
    const std::vector<Fixed>& weights() const { return weight_; }

private:
    int width_ = 0, height_ = 0;
    std::vector<Fixed> sum_;     // 3 per pixel
    std::vector<Fixed> weight_;  // 1 per pixel (64 bytes per pixel in all)
};

}  // namespace pcl
