// Builds small scenes directly as SceneData (no loader involved), for tests whose answer is
// known analytically.
#pragma once

#include <cmath>

#include "scene_data.h"

namespace partita::test {

inline Material lambertMaterial(Rgb albedo, Rgb emission = Rgb(0.0f), bool doubleSided = true) {
    Material m;
    m.baseColor = albedo;
    m.metallic = 0;
    m.roughness = 1;
    m.emissiveFactor = emission;
    m.doubleSided = doubleSided;
    return m;
}

inline Material mirrorMaterial() {
    Material m;
    m.baseColor = Rgb(0.9f);
    m.metallic = 1;
    m.roughness = 0;
    return m;
}

inline Material glassMaterial(float ior = 1.5f) {
    Material m;
    m.baseColor = Rgb(1.0f);
    m.metallic = 0;
    m.roughness = 0;
    m.transmission = 1;
    m.ior = ior;
    return m;
}

/// A quad p, p+a, p+a+b, p+b with normal along a x b.
inline TriangleMesh quad(Vec3f p, Vec3f a, Vec3f b, int material) {
    TriangleMesh m;
    m.positions = {p, p + a, p + a + b, p + b};
    Vec3f n = normalize(cross(a, b));
    m.normals = {n, n, n, n};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    return m;
}

/// An axis-aligned box whose faces point inwards (a room seen from inside) or outwards.
inline TriangleMesh box(Vec3f lo, Vec3f hi, int material, bool inward) {
    TriangleMesh out;
    Vec3f d = hi - lo;
    auto addQuad = [&](Vec3f p, Vec3f a, Vec3f b) {
        if (inward) std::swap(a, b);
        TriangleMesh q = quad(inward ? p : p, a, b, material);
        uint32_t base = uint32_t(out.positions.size());
        for (size_t i = 0; i < 4; ++i) {
            out.positions.push_back(q.positions[i]);
            out.normals.push_back(q.normals[i]);
        }
        for (uint32_t i : q.indices) out.indices.push_back(base + i);
    };
    Vec3f X(d.x, 0, 0), Y(0, d.y, 0), Z(0, 0, d.z);
    addQuad(lo, Y, X);      // -z face, normal -z
    addQuad(lo + Z, X, Y);  // +z face
    addQuad(lo, Z, Y);      // -x face
    addQuad(lo + X, Y, Z);  // +x face
    addQuad(lo, X, Z);      // -y face
    addQuad(lo + Y, Z, X);  // +y face
    out.material = material;
    return out;
}

/// A UV sphere with smooth normals.
inline TriangleMesh sphere(Vec3f center, float radius, int material, int rings = 24,
                           int segments = 48) {
    TriangleMesh m;
    for (int r = 0; r <= rings; ++r) {
        float theta = kPi * float(r) / float(rings);
        for (int s = 0; s <= segments; ++s) {
            float phi = 2 * kPi * float(s) / float(segments);
            Vec3f n(std::sin(theta) * std::cos(phi), std::cos(theta),
                    std::sin(theta) * std::sin(phi));
            m.positions.push_back(center + n * radius);
            m.normals.push_back(n);
        }
    }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            uint32_t a = uint32_t(r * (segments + 1) + s), b = a + uint32_t(segments + 1);
            m.indices.insert(m.indices.end(), {a, a + 1, b, a + 1, b + 1, b});
        }
    m.material = material;
    return m;
}

inline CameraDesc lookAtCamera(Vec3f eye, Vec3f target, float yfov) {
    Vec3f f = normalize(target - eye);
    Vec3f up = std::abs(f.y) > 0.99f ? Vec3f(0, 0, 1) : Vec3f(0, 1, 0);
    Vec3f r = normalize(cross(f, up));
    Vec3f u = cross(r, f);
    CameraDesc c;
    c.name = "test";
    Mat4 m = Mat4::identity();
    for (int k = 0; k < 3; ++k) {
        m.m[0][k] = r[k];
        m.m[1][k] = u[k];
        m.m[2][k] = -f[k];
        m.m[3][k] = eye[k];
    }
    c.cameraToWorld = m;
    c.yfov = yfov;
    return c;
}

/// A closed box whose walls all emit Le and reflect diffusely with albedo rho, seen from inside.
/// Every path sees radiance Le (1 + rho + rho^2 + ...) = Le / (1 - rho); the paths with k
/// diffuse vertices (type L D^k E) carry exactly Le rho^k, whichever strategy samples them.
inline SceneData furnaceScene(float rho, float le) {
    SceneData s;
    s.materials = {lambertMaterial(Rgb(rho), Rgb(le), true)};
    s.meshes.push_back(box({-1, -1, -1}, {1, 1, 1}, 0, true));
    s.cameras.push_back(lookAtCamera({0, 0, 0.5f}, {0, 0, -1}, 1.2f));
    return s;
}

/// A Cornell-like box with a ceiling light, a mirror sphere and a glass sphere: it produces
/// D and S vertices and many path types.
inline SceneData specularBoxScene() {
    SceneData s;
    s.materials = {lambertMaterial(Rgb(0.7f)), lambertMaterial(Rgb(0.0f), Rgb(8.0f), false),
                   mirrorMaterial(), glassMaterial()};
    s.meshes.push_back(box({-1, 0, -1}, {1, 2, 1}, 0, true));
    s.meshes.push_back(quad({-0.3f, 1.99f, -0.3f}, {0.6f, 0, 0}, {0, 0, 0.6f}, 1));  // faces down
    s.meshes.push_back(sphere({-0.45f, 0.35f, -0.2f}, 0.35f, 2, 12, 24));
    s.meshes.push_back(sphere({0.45f, 0.35f, 0.2f}, 0.35f, 3, 12, 24));
    s.cameras.push_back(lookAtCamera({0, 1, 0.95f}, {0, 0.8f, -1}, 1.3f));
    return s;
}

}  // namespace partita::test
