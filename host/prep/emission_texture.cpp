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
    // Texels the triangle covers: its area in (transformed) texture coordinates × W × H.
    float u[3], v[3];
    const float corners[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    for (int k = 0; k < 3; ++k) texCoordAt(mesh, triangle, texture.texCoord, corners[k][0], corners[k][1], u[k], v[k]);
    const TextureTransform& t = texture.transform;
    const double uvArea = 0.5 * std::abs(double(u[1] - u[0]) * (v[2] - v[0]) - double(u[2] - u[0]) * (v[1] - v[0]));
    const double texels = uvArea * std::abs(double(t.scale[0]) * t.scale[1]) * texture.image.width * texture.image.height;
    const int g = int(std::clamp(std::ceil(2.0 * std::sqrt(std::isfinite(texels) ? texels : 0.0)), 4.0, 64.0));
    // Centroids of the g² sub-triangles: upright (i + ⅓, j + ⅓)/g, inverted (i + ⅔, j + ⅔)/g.
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
    Vec3 top(0.0f);
    for (size_t i = 0; i + 2 < texture.image.rgb.size(); i += 3)
        top = vmax(top, Vec3(texture.image.rgb[i], texture.image.rgb[i + 1], texture.image.rgb[i + 2]));
    return Vec3(m.emission.x * top.x, m.emission.y * top.y, m.emission.z * top.z);
}

}  // namespace pcl
