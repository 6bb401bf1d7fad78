#include "prep/emission_texture.h"

#include <algorithm>
#include <cmath>

#include "prep/texture_buffers.h"
#include "shared/texture.h"

namespace pcl {
namespace {

// The texture coordinates of `texture`'s set at barycentrics (bu, bv), interpolated as the
// kernels do (kernels/shared/texture.h, texture_emission_at).
void texCoordAt(const TriangleMesh& mesh, uint32_t triangle, int set, float bu, float bv, float& u, float& v) {
    const uint32_t* idx = &mesh.indices[3 * size_t(triangle)];
    const float* uv = mesh.uv[set].data();
    const float bw = 1.0f - bu - bv;
    u = bw * uv[2 * idx[0]] + bu * uv[2 * idx[1]] + bv * uv[2 * idx[2]];
    v = bw * uv[2 * idx[0] + 1] + bu * uv[2 * idx[1] + 1] + bv * uv[2 * idx[2] + 1];
}

}  // namespace

Vec3 emissionAt(const Scene& scene, const TriangleMesh& mesh, uint32_t triangle, float bu, float bv) {
    const Material& m = scene.materials[size_t(mesh.material)];
    if (m.emissionTexture < 0) return m.emission;
    const Texture& texture = scene.textures[size_t(m.emissionTexture)];
    float u, v, texel[3];
    texCoordAt(mesh, triangle, texture.texCoord, bu, bv, u, v);
    texture_bilinear(textureDescriptor(texture, 0), texture.image.rgb.data(), u, v, texel);
    return Vec3(m.emission.x * texel[0], m.emission.y * texel[1], m.emission.z * texel[2]);
}

Vec3 meanEmission(const Scene& scene, const TriangleMesh& mesh, uint32_t triangle) {
    const Material& m = scene.materials[size_t(mesh.material)];
    if (m.emissionTexture < 0 || !m.emits()) return m.emission;
    const Texture& texture = scene.textures[size_t(m.emissionTexture)];
    const PclTexture d = textureDescriptor(texture, 0);
    // The corners' coordinates after the transform, in texels (texel centres at integers).
    const float corners[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    double x[3], y[3];
    for (int k = 0; k < 3; ++k) {
        float u, v, tu, tv;
        texCoordAt(mesh, triangle, texture.texCoord, corners[k][0], corners[k][1], u, v);
        texture_transform_uv(d, u, v, &tu, &tv);
        x[k] = double(tu) * texture.image.width - 0.5;
        y[k] = double(tv) * texture.image.height - 0.5;
    }
    // The largest texel bilinear filtering can read anywhere on the triangle: every texel index
    // from floor(min) to floor(max) + 1 of the footprint's box, wrapped as the lookup wraps it
    // (the whole image once the box spans a period). 0: the triangle emits nothing anywhere.
    auto range = [](const double* c, int n, pcl_i32& lo, pcl_i32& count) {
        const double a = std::min({c[0], c[1], c[2]}), b = std::max({c[0], c[1], c[2]});
        if (!std::isfinite(a) || !std::isfinite(b) || b - a >= n) {
            lo = 0, count = n;
            return;
        }
        lo = pcl_i32(std::floor(a));
        count = std::min(n, pcl_i32(std::floor(b)) + 2 - lo);
    };
    const pcl_i32 W = texture.image.width, H = texture.image.height;
    pcl_i32 x0, nx, y0, ny;
    range(x, W, x0, nx);
    range(y, H, y0, ny);
    Vec3 top(0.0f);
    for (pcl_i32 j = 0; j < ny; ++j)
        for (pcl_i32 i = 0; i < nx; ++i)
            top = vmax(top, texture.image.at(texture_wrap_texel(x0 + i, W, d.wrap & 0xFFu),
                                             texture_wrap_texel(y0 + j, H, (d.wrap >> 8) & 0xFFu)));
    if (!(maxComponent(top) > 0.0f)) return Vec3(0.0f);

    // The mean at the centroids of g² congruent sub-triangles, g about twice the texels the
    // triangle spans along a side: upright (i + ⅓, j + ⅓)/g, inverted (i + ⅔, j + ⅔)/g.
    const double texels = 0.5 * std::abs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]));
    const int g = int(std::clamp(std::ceil(2.0 * std::sqrt(std::isfinite(texels) ? texels : 0.0)), 4.0, 64.0));
    double sum[3] = {0, 0, 0};
    int n = 0;
    auto add = [&](double a, double b) {
        const Vec3 e = emissionAt(scene, mesh, triangle, float(a / g), float(b / g));
        sum[0] += e.x, sum[1] += e.y, sum[2] += e.z;
        ++n;
    };
    for (int i = 0; i < g; ++i)
        for (int j = 0; i + j < g; ++j) {
            add(i + 1.0 / 3.0, j + 1.0 / 3.0);
            if (i + j + 2 <= g) add(i + 2.0 / 3.0, j + 2.0 / 3.0);
        }
    const Vec3 mean(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
    if (maxComponent(mean) > 0.0f) return mean;
    // Light the samples missed: a spot smaller than their spacing (about half a texel), so less
    // than about one sample's share of the triangle. Count it as one sample at the footprint's
    // largest texel: small (a triangle whose box reaches a bright texel it does not cover is
    // chosen rarely) but positive, so the triangle can still be chosen.
    const float share = 1.0f / float(n);
    return Vec3(m.emission.x * top.x * share, m.emission.y * top.y * share, m.emission.z * top.z * share);
}

}  // namespace pcl
