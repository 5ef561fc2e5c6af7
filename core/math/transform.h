// Column-major 4x4 affine transforms, as glTF stores node matrices.
#pragma once

#include <array>

#include "math/vec.h"

namespace partita {

struct Mat4 {
    // m[col][row], matching glTF's column-major storage.
    std::array<std::array<float, 4>, 4> m{};

    static Mat4 identity();
    static Mat4 fromColumnMajor(const double* values);
    static Mat4 translation(Vec3f t);
    static Mat4 scale(Vec3f s);
    /// Rotation from a unit quaternion (x, y, z, w), glTF's convention.
    static Mat4 rotation(float qx, float qy, float qz, float qw);

    Mat4 operator*(const Mat4& o) const;
    Vec3f transformPoint(Vec3f p) const;
    Vec3f transformVector(Vec3f v) const;
    /// Normals transform with the inverse transpose of the upper 3x3.
    Vec3f transformNormal(Vec3f n) const;
    float determinant3x3() const;
    Mat4 inverse() const;
};

}  // namespace partita
