// Image: a linear RGB float raster, rows top to bottom, three floats per pixel. It is what a
// Film resolves to, what image_io reads and writes, and what metrics compare.
#pragma once
#include <cstddef>
#include <vector>

#include "core/vec3.h"

namespace pcl {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  // width * height * 3, row-major, top row first

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(static_cast<size_t>(w) * h * 3, 0.0f) {}

    size_t pixelCount() const { return static_cast<size_t>(width) * height; }
    Vec3 at(int x, int y) const {
        const float* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
        return {p[0], p[1], p[2]};
    }
    void set(int x, int y, Vec3 c) {
        float* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
        p[0] = c.x;
        p[1] = c.y;
        p[2] = c.z;
    }
};

}  // namespace pcl
