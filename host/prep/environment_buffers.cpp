#include "prep/environment_buffers.h"

#include <cmath>

#include "core/math.h"

namespace pcl {

EnvironmentBuffers buildEnvironmentBuffers(const Environment& environment) {
    EnvironmentBuffers b;
    b.data.assign(1, 0.0f);
    if (!environment.active()) return b;
    const bool image = !environment.image.rgb.empty();
    const uint32_t W = image ? uint32_t(environment.image.width) : 1u;
    const uint32_t H = image ? uint32_t(environment.image.height) : 1u;
    PclEnvironment& e = b.environment;
    e.width = W;
    e.height = H;
    e.rowCdfOffset = 3u * W * H;
    e.columnCdfOffset = e.rowCdfOffset + H + 1u;
    const double radians = double(environment.rotationDegrees) * kPiD / 180.0;
    e.cosRot = float(std::cos(radians));
    e.sinRot = float(std::sin(radians));
    b.data.assign(size_t(e.columnCdfOffset) + size_t(H) * (W + 1u), 0.0f);

    // Texels (float, as the kernels read them); weights Y(L) Ω in double from those floats.
    std::vector<double> rowWeight(H, 0.0);
    double total = 0.0, integral[3] = {0.0, 0.0, 0.0};
    for (uint32_t y = 0; y < H; ++y) {
        const double omega = 2.0 * kPiD / W * (std::cos(kPiD * y / H) - std::cos(kPiD * (y + 1) / H));
        float* column = &b.data[e.columnCdfOffset + size_t(y) * (W + 1u)];
        double row = 0.0;
        for (uint32_t x = 0; x < W; ++x) {
            const Vec3 L = image ? environment.image.at(int(x), int(y)) * environment.scale : environment.scale;
            float* t = &b.data[3 * (size_t(y) * W + x)];
            t[0] = L.x;
            t[1] = L.y;
            t[2] = L.z;
            row += double(env_luminance(t)) * omega;
            column[x + 1] = float(row);
            for (int c = 0; c < 3; ++c) integral[c] += double(t[c]) * omega;
        }
        for (uint32_t x = 1; x <= W; ++x) column[x] = row > 0.0 ? float(column[x] / row) : float(x) / float(W);
        column[W] = 1.0f;
        rowWeight[y] = row;
        total += row;
    }
    b.integral = Vec3(float(integral[0]), float(integral[1]), float(integral[2]));
    if (!(total > 0.0)) {  // a black sky (the loader refuses one): nothing to sample
        b.environment = PclEnvironment{};
        b.data.assign(1, 0.0f);
        return b;
    }
    double running = 0.0;
    float* rowCdf = &b.data[e.rowCdfOffset];
    for (uint32_t y = 0; y < H; ++y) {
        running += rowWeight[y];
        rowCdf[y + 1] = float(running / total);
    }
    rowCdf[H] = 1.0f;
    e.integral = float(total);
    return b;
}

PclLight environmentLight(const EnvironmentBuffers& sky, Vec3 centre, float radius) {
    PclLight l{};
    l.type = PCL_LIGHT_ENVIRONMENT;
    l.prim = PCL_NO_HIT;
    l.p[0] = centre.x;
    l.p[1] = centre.y;
    l.p[2] = centre.z;
    l.radius = radius;
    const float disc = kPi * radius * radius;
    l.power[0] = disc * sky.integral.x;
    l.power[1] = disc * sky.integral.y;
    l.power[2] = disc * sky.integral.z;
    return l;
}

}  // namespace pcl
