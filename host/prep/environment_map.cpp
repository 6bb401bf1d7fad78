#include "prep/environment_map.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "scene/scene_error.h"

namespace pcl {

EnvironmentMap::EnvironmentMap(const Environment& environment) {
    if (!environment.active()) return;
    scale_ = environment.scale;
    if (!environment.image.rgb.empty()) {
        image_ = &environment.image;
        width_ = environment.image.width;
        height_ = environment.image.height;
    }
    const double radians = double(environment.rotationDegrees) * kPiD / 180.0;
    cosRot_ = float(std::cos(radians));
    sinRot_ = float(std::sin(radians));

    // Each texel's weight: its luminance times its solid angle (its share of ∫ Y(L) dω).
    std::vector<double> weight(size_t(width_) * size_t(height_));
    double total = 0.0;
    for (int y = 0; y < height_; ++y) {
        const double omega = rowSolidAngle(y);
        for (int x = 0; x < width_; ++x) {
            const Vec3 L = texel(x, y);
            weight[size_t(y) * size_t(width_) + size_t(x)] = double(luminance(L)) * omega;
            total += weight[size_t(y) * size_t(width_) + size_t(x)];
            integral_ += L * float(omega);
        }
    }
    if (!(total > 0.0)) return;  // inactive: nothing to sample (the loader refuses such a sky)
    rowCdf_.assign(size_t(height_) + 1, 0.0);
    columnCdf_.assign(size_t(height_) * (size_t(width_) + 1), 0.0);
    texelProbability_.resize(weight.size());
    for (int y = 0; y < height_; ++y) {
        double row = 0.0;
        double* cdf = &columnCdf_[size_t(y) * (size_t(width_) + 1)];
        for (int x = 0; x < width_; ++x) {
            row += weight[size_t(y) * size_t(width_) + size_t(x)];
            cdf[x + 1] = row;
            texelProbability_[size_t(y) * size_t(width_) + size_t(x)] =
                float(weight[size_t(y) * size_t(width_) + size_t(x)] / total);
        }
        for (int x = 1; x <= width_; ++x) cdf[x] = row > 0.0 ? cdf[x] / row : double(x) / width_;
        rowCdf_[size_t(y) + 1] = rowCdf_[size_t(y)] + row / total;
    }
    rowCdf_.back() = 1.0;
    // Texel shares p_i = Y_i Ω_i / Σ: ∫ Y² dω / (∫ Y dω)² = Σ p_i² / Ω_i.
    double squares = 0.0;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const double p = weight[size_t(y) * size_t(width_) + size_t(x)] / total;
            squares += p * p / rowSolidAngle(y);
        }
    effectiveSolidAngle_ = squares > 0.0 ? 1.0 / squares : 0.0;
}

float EnvironmentMap::rowSolidAngle(int y) const {
    const double theta0 = kPiD * y / height_, theta1 = kPiD * (y + 1) / height_;
    return float(2.0 * kPiD / width_ * (std::cos(theta0) - std::cos(theta1)));
}

Vec3 EnvironmentMap::texel(int x, int y) const { return image_ ? image_->at(x, y) * scale_ : scale_; }

// Turning the sky by +α about y turns a world direction back by −α into the map's frame.
Vec3 EnvironmentMap::toLocal(Vec3 w) const {
    return {cosRot_ * w.x - sinRot_ * w.z, w.y, sinRot_ * w.x + cosRot_ * w.z};
}
Vec3 EnvironmentMap::toWorld(Vec3 w) const {
    return {cosRot_ * w.x + sinRot_ * w.z, w.y, -sinRot_ * w.x + cosRot_ * w.z};
}

void EnvironmentMap::texelOf(Vec3 local, int& x, int& y) const {
    double u = std::atan2(double(local.x), -double(local.z)) / (2.0 * kPiD);
    if (u < 0.0) u += 1.0;
    const double v = std::acos(std::clamp(double(local.y), -1.0, 1.0)) / kPiD;
    x = std::clamp(int(u * width_), 0, width_ - 1);
    y = std::clamp(int(v * height_), 0, height_ - 1);
}

Vec3 EnvironmentMap::radiance(Vec3 w) const {
    if (!active()) return Vec3(0.0f);
    int x, y;
    texelOf(toLocal(w), x, y);
    return texel(x, y);
}

float EnvironmentMap::pdf(Vec3 w) const {
    if (!active()) return 0.0f;
    int x, y;
    texelOf(toLocal(w), x, y);
    return texelProbability_[size_t(y) * size_t(width_) + size_t(x)] / rowSolidAngle(y);
}

bool EnvironmentMap::sample(float u1, float u2, Vec3& w, float& pdf) const {
    if (!active()) return false;
    // The row, then the column within it, by inversion; the remainders place the direction.
    int y = int(std::upper_bound(rowCdf_.begin() + 1, rowCdf_.end(), double(u1)) - rowCdf_.begin()) - 1;
    y = std::clamp(y, 0, height_ - 1);
    while (rowCdf_[size_t(y) + 1] - rowCdf_[size_t(y)] <= 0.0 && y > 0) --y;
    const double rowWidth = rowCdf_[size_t(y) + 1] - rowCdf_[size_t(y)];
    const double s1 = std::clamp((u1 - rowCdf_[size_t(y)]) / rowWidth, 0.0, 1.0);
    const double* cdf = &columnCdf_[size_t(y) * (size_t(width_) + 1)];
    int x = int(std::upper_bound(cdf + 1, cdf + width_ + 1, double(u2)) - cdf) - 1;
    x = std::clamp(x, 0, width_ - 1);
    while (cdf[x + 1] - cdf[x] <= 0.0 && x > 0) --x;
    const double s2 = std::clamp((u2 - cdf[x]) / (cdf[x + 1] - cdf[x]), 0.0, 1.0);
    // Uniform in the texel's solid angle: φ uniform over its columns, cos θ uniform over its row.
    const double phi = 2.0 * kPiD * (x + s2) / width_;
    const double cos0 = std::cos(kPiD * y / height_), cos1 = std::cos(kPiD * (y + 1) / height_);
    const double cosTheta = cos0 + s1 * (cos1 - cos0);
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    // u = atan2(w.x, −w.z)/2π: w = (sin θ sin φ, cos θ, −sin θ cos φ).
    const Vec3 local(float(sinTheta * std::sin(phi)), float(cosTheta), float(-sinTheta * std::cos(phi)));
    w = toWorld(local);
    pdf = texelProbability_[size_t(y) * size_t(width_) + size_t(x)] / rowSolidAngle(y);
    return pdf > 0.0f;
}

void refuseEnvironmentInMediaWithoutPathTracer(const Scene& scene, const std::string& what) {
    if (!scene.environment.active() || !scene.hasMedia()) return;
    failInput(scene.path, "environment",
              "a scene without an environment light or without participating media for " + what +
                  " (the photon methods do not carry the sky through media; --method path renders both)",
              (scene.environment.imagePath.empty() ? "a constant sky" : "the sky " + scene.environment.imagePath) +
                  " and " + std::to_string(scene.media.size()) + " medium(s)");
}

bool skyCausticsByEyeRays(const Scene& scene) {
    const EnvironmentMap sky(scene.environment);
    return sky.active() && sky.effectiveSolidAngle() >= kSpreadSkySolidAngle;
}

}  // namespace pcl
