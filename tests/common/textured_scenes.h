// Textures and textured scenes built in code for the texture tests (unit, stages, accuracy).
#pragma once

#include <algorithm>
#include <cmath>

#include "common/test_scenes.h"
#include "scene/scene.h"

namespace pcl::test_scenes {

// A w × h checkerboard of squares `cell` texels wide, colours a and b (a at texel (0, 0)).
inline Image checkerImage(int w, int h, int cell, Vec3 a, Vec3 b) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.set(x, y, ((x / cell + y / cell) % 2 == 0) ? a : b);
    return img;
}

// A w × h image linear in the texel index: texel (i, j) = (0.1 + 0.8 i/(w−1), 0.1 + 0.8 j/(h−1),
// 0.5). Bilinear filtering reproduces the linear function exactly between the texel centres.
inline Image gradientImage(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.set(x, y, Vec3(0.1f + 0.8f * float(x) / float(w - 1), 0.1f + 0.8f * float(y) / float(h - 1), 0.5f));
    return img;
}

// The gradient's value at continuous coordinates (u, v) inside [½/W, 1 − ½/W] × [½/H, 1 − ½/H].
inline Vec3 gradientAt(int w, int h, float u, float v) {
    const float x = u * float(w) - 0.5f, y = v * float(h) - 0.5f;
    return Vec3(0.1f + 0.8f * x / float(w - 1), 0.1f + 0.8f * y / float(h - 1), 0.5f);
}

// Adds `image` as a texture; returns its index.
inline int addTexture(Scene& s, Image image, TextureWrap wrapU = TextureWrap::Repeat,
                      TextureWrap wrapV = TextureWrap::Repeat, TextureTransform transform = {}) {
    Texture t;
    t.path = "(in memory " + std::to_string(s.textures.size()) + ")";
    t.image = std::move(image);
    t.wrapU = wrapU;
    t.wrapV = wrapV;
    t.transform = transform;
    s.textures.push_back(std::move(t));
    return int(s.textures.size()) - 1;
}

// addQuad with texture coordinates (0,0), (1,0), (1,1), (0,1) at corner, +u, +u+v, +v (a JSON quad's).
inline int addTexturedQuad(Scene& s, Vec3 corner, Vec3 u, Vec3 v, int material) {
    const int m = addQuad(s, corner, u, v, material);
    s.meshes[size_t(m)].uv[0] = {0, 0, 1, 0, 1, 1, 0, 1};
    return m;
}

// The quad tests' set: the 2 × 2 quad in y = 0 with `material` (its image upright seen from
// above), seen straight down from (0, 4, 0) through a 30° size × size camera.
inline void addQuadSeenFromAbove(Scene& s, int material, int size) {
    addTexturedQuad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), material);
    setCamera(s, Vec3(0, 4, 0), Vec3(0, 0, 0), Vec3(0, 0, -1), 30.0f, size, size);
}

// The quad's coordinates where film point (x + fx, y + fy) of addQuadSeenFromAbove's camera looks.
inline void quadUvAt(const Camera& cam, int x, int y, float fx, float fy, float& u, float& v) {
    const Vec3 d = pinholeDirection(cam, x, y, fx, fy);
    const Vec3 p = cam.position + d * (-cam.position.y / d.y);
    u = (p.x + 1.0f) / 2.0f;
    v = (1.0f - p.z) / 2.0f;
}

// Whether pixel (x, y)'s footprint lies in [loU, hiU] × [loV, hiV] of the quad's coordinates.
inline bool quadFootprintInside(const Camera& cam, int x, int y, float loU, float hiU, float loV, float hiV) {
    for (float fx : {0.0f, 1.0f})
        for (float fy : {0.0f, 1.0f}) {
            float u, v;
            quadUvAt(cam, x, y, fx, fy, u, v);
            if (!(u >= loU && u <= hiU && v >= loV && v <= hiV)) return false;
        }
    return true;
}

struct GradientPixelError {
    double worstOutside = 0.0;  // relative distance outside the footprint's range of L
    double meanRatio = 0.0;     // mean of pixel / L(pixel centre) over pixels and channels
    int compared = 0;
};

// An image of addQuadSeenFromAbove's quad whose radiance is `scale` × the 5 × 4 gradient, per
// pixel against the closed form. A box-filtered pixel is a convex combination of L at its
// samples, which lie in its footprint; L is affine there, so the pixel lies between L's values at
// the footprint's corners, and its mean over many pixels is L at the centres (the jitter averages
// out). Only pixels inside the exact region of the gradient (between the outer texel centres).
inline GradientPixelError compareQuadGradient(const Camera& cam, const Image& img, Vec3 scale) {
    GradientPixelError e;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            if (!quadFootprintInside(cam, x, y, 0.1f, 0.9f, 0.125f, 0.875f)) continue;
            Vec3 lo(1e30f), hi(-1e30f);
            for (float fx : {0.0f, 1.0f})
                for (float fy : {0.0f, 1.0f}) {
                    float u, v;
                    quadUvAt(cam, x, y, fx, fy, u, v);
                    const Vec3 L = gradientAt(5, 4, u, v) * scale;
                    lo = vmin(lo, L);
                    hi = vmax(hi, L);
                }
            float u, v;
            quadUvAt(cam, x, y, 0.5f, 0.5f, u, v);
            const Vec3 centre = gradientAt(5, 4, u, v) * scale;
            const Vec3 got = img.at(x, y);
            for (int c = 0; c < 3; ++c) {
                const double outside = std::max({0.0, double(lo[c]) - got[c], double(got[c]) - hi[c]});
                e.worstOutside = std::max(e.worstOutside, outside / centre[c]);
                e.meanRatio += double(got[c]) / centre[c];
            }
            ++e.compared;
        }
    e.meanRatio /= std::max(1, 3 * e.compared);
    return e;
}

inline void addDirectionalLight(Scene& s, Vec3 direction, Vec3 irradiance) {
    Light l;
    l.type = LightType::Directional;
    l.direction = direction;
    l.irradiance = irradiance;
    s.lights.push_back(l);
}

// Mesh `mesh` (of an emissive material) as an area light: what validateScene does for a loaded
// scene's emitters (the scenes here are built in code and prepared without it).
inline void addAreaLightFor(Scene& s, int mesh) {
    Light l;
    l.type = LightType::Area;
    l.name = "area " + std::to_string(mesh);
    l.mesh = mesh;
    s.lights.push_back(l);
}

// A textured emitter: a material emitting `factor` × the texture `texture` (rhoD 0).
inline int addTexturedEmitter(Scene& s, int texture, Vec3 factor) {
    const int m = addEmitter(s, Vec3(0.0f), factor);
    s.materials[size_t(m)].emissionTexture = texture;
    return m;
}

// A closed 2 × 2 × 2 room lit by a point light under the ceiling, seen from inside: a checkered
// floor (repeat, the transform scales by 3 and turns by 0.3 rad), a gradient back wall (mirror
// and clamp wrap, scaled by 2, read through coordinate set 1), the other walls plain; a mirror-and-diffuse block so some paths reach a
// texture after a specular bounce. Exercises every textured stage of both passes.
inline Scene texturedRoom(int width = 48, int height = 36) {
    Scene s;
    s.path = "(textured room)";
    const int plain = addMaterial(s, Vec3(0.6f, 0.6f, 0.6f));
    TextureTransform floorT;
    floorT.scale[0] = floorT.scale[1] = 3.0f;
    floorT.rotation = 0.3f;
    floorT.offset[0] = 0.25f;
    const int checker = addTexture(s, checkerImage(8, 8, 2, Vec3(0.9f, 0.7f, 0.2f), Vec3(0.1f, 0.2f, 0.6f)),
                                   TextureWrap::Repeat, TextureWrap::Repeat, floorT);
    TextureTransform wallT;
    wallT.scale[0] = wallT.scale[1] = 2.0f;
    const int gradient = addTexture(s, gradientImage(5, 4), TextureWrap::Mirror, TextureWrap::Clamp, wallT);
    s.textures[size_t(gradient)].texCoord = 1;
    const int floorMat = addMaterial(s, Vec3(1.0f));
    s.materials[size_t(floorMat)].rhoDTexture = checker;
    const int wallMat = addMaterial(s, Vec3(0.9f, 0.9f, 0.9f));
    s.materials[size_t(wallMat)].rhoDTexture = gradient;
    const int block = addMaterial(s, Vec3(0.3f), Vec3(0.6f), SpecularKind::Mirror);
    addTexturedQuad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), floorMat);                  // floor, facing +y
    const int wall = addTexturedQuad(s, Vec3(-1, 0, -1), Vec3(2, 0, 0), Vec3(0, 2, 0), wallMat);  // back wall, +z
    s.meshes[size_t(wall)].uv[1] = {0, 1, 0, 0, 1, 0, 1, 1};                          // set 1: set 0 turned a quarter
    addQuad(s, Vec3(-1, 2, -1), Vec3(2, 0, 0), Vec3(0, 0, 2), plain);                 // ceiling, −y
    addQuad(s, Vec3(-1, 0, 1), Vec3(0, 0, -2), Vec3(0, 2, 0), plain);                 // left, +x
    addQuad(s, Vec3(1, 0, -1), Vec3(0, 0, 2), Vec3(0, 2, 0), plain);                  // right, −x
    addQuad(s, Vec3(1, 0, 1), Vec3(-2, 0, 0), Vec3(0, 2, 0), plain);                  // front, −z
    addQuad(s, Vec3(0.2f, 0.0f, -0.2f), Vec3(0, 0, -0.4f), Vec3(0, 0.6f, 0), block);  // a mirror panel
    Light l = pointLight(Vec3(0.0f, 1.8f, 0.0f));
    l.intensity = Vec3(4.0f);
    s.lights.push_back(l);
    setCamera(s, Vec3(0.0f, 1.0f, 0.9f), Vec3(0.0f, 0.6f, -1.0f), Vec3(0, 1, 0), 70.0f, width, height);
    return s;
}

// texturedRoom with textured specular lobes (kernels/shared/texture.h): the mirror panel's ρs
// by the checker; on the left wall a glossy panel whose ρs is the gradient and whose exponent
// runs over [4, 200] with the checker's R; on the right wall a glTF-style metallic-roughness
// panel (base colour the gradient, metallic B and roughness G of a third texture). Photons and
// eye paths meet each of them directly and after other bounces.
inline Scene specularTexturedRoom(int width = 48, int height = 36) {
    Scene s = texturedRoom(width, height);
    s.path = "(specular textured room)";
    const int checker = 0, gradient = 1;                                  // texturedRoom's textures
    s.materials[size_t(s.meshes.back().material)].rhoSTexture = checker;  // the mirror panel
    const int glossy = addMaterial(s, Vec3(0.2f), Vec3(0.7f), SpecularKind::Glossy, Vec3(0.0f), 200.0f);
    s.materials[size_t(glossy)].rhoSTexture = gradient;
    s.materials[size_t(glossy)].exponentTexture = checker;
    s.materials[size_t(glossy)].exponentRange[0] = 4.0f;
    s.materials[size_t(glossy)].exponentRange[1] = 200.0f;
    addTexturedQuad(s, Vec3(-0.99f, 0.3f, 0.5f), Vec3(0, 0, -1.2f), Vec3(0, 1.2f, 0), glossy);
    // Metallic (B) from 0.1 to 0.9 across u, roughness (G) from 0.1 to 0.9 down v.
    Image mr(6, 6);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 6; ++x) mr.set(x, y, Vec3(0.0f, 0.1f + 0.16f * float(y), 0.1f + 0.16f * float(x)));
    const int mrTexture = addTexture(s, std::move(mr));
    const int metal = addMaterial(s, Vec3(0.5f), Vec3(0.5f), SpecularKind::Glossy, Vec3(0.0f), 1.0f);
    Material& m = s.materials[size_t(metal)];
    m.rhoDTexture = gradient;
    m.exponentTexture = mrTexture;
    m.metallicRoughness.active = true;
    m.metallicRoughness.baseColor = Vec3(0.9f, 0.8f, 0.7f);
    m.metallicRoughness.metallic = 1.0f;
    m.metallicRoughness.roughness = 0.8f;
    m.metallicRoughness.f0 = 0.04f;
    addTexturedQuad(s, Vec3(0.99f, 0.3f, -0.7f), Vec3(0, 0, 1.2f), Vec3(0, 1.2f, 0), metal);
    return s;
}

// texturedRoom with a textured lamp: a 0.8 × 0.6 panel under the ceiling, facing down, emitting
// (6, 5, 4) × the checker (repeat, the transform scales by 2: some triangles' texels are all
// dark, none all black) beside the point light. Photons, direct light, the glossy chain's light
// samples and the gather rays all meet its texture.
inline Scene emissiveTexturedRoom(int width = 48, int height = 36) {
    Scene s = specularTexturedRoom(width, height);
    s.path = "(emissive textured room)";
    TextureTransform t;
    t.scale[0] = t.scale[1] = 2.0f;
    const int checker = addTexture(s, checkerImage(8, 8, 2, Vec3(1.0f, 0.9f, 0.8f), Vec3(0.05f, 0.0f, 0.1f)),
                                   TextureWrap::Repeat, TextureWrap::Repeat, t);
    const int lamp = addTexturedEmitter(s, checker, Vec3(6.0f, 5.0f, 4.0f));
    const int panel = addTexturedQuad(s, Vec3(-0.4f, 1.98f, -0.7f), Vec3(0.8f, 0, 0), Vec3(0, 0, 0.6f), lamp);
    addAreaLightFor(s, panel);
    return s;
}

}  // namespace pcl::test_scenes
