// An affine 4x4 transform for placing imported geometry: glTF node matrices / TRS and the JSON
// `transform` object. Kept in double so deep node hierarchies compose without visible drift.
#pragma once
#include <cmath>

#include "core/math.h"
#include "core/vec3.h"

namespace pcl {

struct Transform {
    // Row-major, acting on column vectors: p' = m * [p, 1].
    double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

    static Transform translate(double x, double y, double z) {
        Transform t;
        t.m[0][3] = x;
        t.m[1][3] = y;
        t.m[2][3] = z;
        return t;
    }
    static Transform scale(double x, double y, double z) {
        Transform t;
        t.m[0][0] = x;
        t.m[1][1] = y;
        t.m[2][2] = z;
        return t;
    }
    // Unit quaternion (x, y, z, w), glTF's rotation convention. Normalised here so a
    // slightly-off quaternion from a file still gives a rotation.
    static Transform quaternion(double x, double y, double z, double w) {
        double n = std::sqrt(x * x + y * y + z * z + w * w);
        if (n > 0) {
            x /= n;
            y /= n;
            z /= n;
            w /= n;
        }
        Transform t;
        t.m[0][0] = 1 - 2 * (y * y + z * z);
        t.m[0][1] = 2 * (x * y - z * w);
        t.m[0][2] = 2 * (x * z + y * w);
        t.m[1][0] = 2 * (x * y + z * w);
        t.m[1][1] = 1 - 2 * (x * x + z * z);
        t.m[1][2] = 2 * (y * z - x * w);
        t.m[2][0] = 2 * (x * z - y * w);
        t.m[2][1] = 2 * (y * z + x * w);
        t.m[2][2] = 1 - 2 * (x * x + y * y);
        return t;
    }
    // Rotation by `degrees` about `axis` (right-handed), as a quaternion.
    static Transform rotate(double degrees, double ax, double ay, double az) {
        double n = std::sqrt(ax * ax + ay * ay + az * az);
        double half = degrees * kPiD / 360.0;
        double s = std::sin(half) / n;
        return quaternion(ax * s, ay * s, az * s, std::cos(half));
    }
    static Transform rowMajor(const double* v) {
        Transform t;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) t.m[r][c] = v[4 * r + c];
        return t;
    }
    static Transform columnMajor(const double* v) {  // glTF's node.matrix layout
        Transform t;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) t.m[r][c] = v[4 * c + r];
        return t;
    }

    Transform operator*(const Transform& b) const {
        Transform t;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) {
                double s = 0;
                for (int k = 0; k < 4; ++k) s += m[r][k] * b.m[k][c];
                t.m[r][c] = s;
            }
        return t;
    }

    Vec3 point(Vec3 p) const {
        return {float(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3]),
                float(m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3]),
                float(m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3])};
    }
    Vec3 vector(Vec3 v) const {
        return {float(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z),
                float(m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z),
                float(m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z)};
    }
    double determinant3() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    // Normals transform by the inverse transpose; the cofactor matrix is that times det, and the
    // sign of det is put back so the normal keeps its side. Result is normalised.
    Vec3 normal(Vec3 n) const {
        double c[3][3];
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) {
                int r1 = (r + 1) % 3, r2 = (r + 2) % 3, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
                c[r][k] = m[r1][k1] * m[r2][k2] - m[r1][k2] * m[r2][k1];
            }
        double s = determinant3() < 0 ? -1.0 : 1.0;
        double x = s * (c[0][0] * n.x + c[0][1] * n.y + c[0][2] * n.z);
        double y = s * (c[1][0] * n.x + c[1][1] * n.y + c[1][2] * n.z);
        double z = s * (c[2][0] * n.x + c[2][1] * n.y + c[2][2] * n.z);
        double l = std::sqrt(x * x + y * y + z * z);
        return l > 0 ? Vec3(float(x / l), float(y / l), float(z / l)) : Vec3(0.0f);
    }
    bool isFinite() const {
        for (auto& row : m)
            for (double v : row)
                if (!std::isfinite(v)) return false;
        return true;
    }
    // A mirroring transform turns counter-clockwise triangles clockwise; loaders swap two
    // indices so the front side stays the side the normals point to.
    bool flipsWinding() const { return determinant3() < 0; }
};

}  // namespace pcl
