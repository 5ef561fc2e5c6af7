#include "guide/gbuffer.h"

#include <algorithm>
#include <optional>

#include "camera.h"
#include "mcmc/path_edits.h"
#include "path/dirac_vertex.h"
#include "path/random_walk.h"
#include "render_scene.h"
#include "thread_pool.h"

namespace partita {

static_assert(sizeof(GBufferTexel) == 40, "GBuffer::bytes() and the memory figures say 40 B");

GBuffer::GBuffer(int width, int height)
    : width_(std::max(0, width)),
      height_(std::max(0, height)),
      texels_(size_t(width_) * size_t(height_)) {}

namespace {

/// The more probable of the Dirac vertex v's branches seen from wo (the reflection on a tie, and
/// the only one of a mirror or under total internal reflection), with its direction; invalid
/// when it has none.
struct FollowedBranch {
    DiracBranch branch;
    Vec3f direction;
};

FollowedBranch likelierBranch(const PathVertex& v, Vec3f wo) {
    FollowedBranch best;
    for (bool refraction : {false, true}) {
        std::optional<Vec3f> w = followBranch(v, wo, refraction, TransportMode::Radiance);
        if (!w) continue;
        DiracBranch b = diracBranch(v, wo, *w);
        if (b.valid && (!best.branch.valid || b.probabilityEye > best.branch.probabilityEye))
            best = {b, *w};
    }
    return best;
}

/// The texel of the camera ray that first hit `hit` coming along -wo.
GBufferTexel texelFrom(const RenderScene& scene, const SurfaceHit& hit, Vec3f wo, int maxDepth,
                       uint64_t& rays) {
    GBufferTexel texel;
    PathVertex v = surfaceVertex(scene, hit, wo);
    Rgb throughput(1.0f);
    int specular = 0;
    // v is scattering vertex number specular + 1; a path may have maxDepth of them.
    while (v.delta) {
        if (specular + 2 > maxDepth) return texel;  // x_s would lie beyond maxDepth
        FollowedBranch next = likelierBranch(v, wo);
        if (!next.branch.valid) return texel;
        // The branch's weight in radiance mode: its coefficient times |cos| (dirac_vertex.h).
        throughput *= next.branch.f * absDot(next.direction, v.hit.ns);
        ++specular;
        std::optional<PathVertex> after = traceVertex(scene, v, next.direction, rays);
        if (!after || !after->isSurface()) return texel;  // into the environment or nothing
        wo = -next.direction;
        v = *after;
    }
    if (v.light >= 0) return texel;  // an emitter: x_s would be the light itself
    texel.position = v.p;
    texel.normal = faceForward(v.bsdf.frame().n, wo);
    texel.albedo = luminance(v.bsdf.albedo());
    texel.cameraTerm = luminance(throughput);
    texel.surface = v.hit.mesh;
    texel.specularVertices = uint8_t(std::min(specular, 255));
    texel.valid = true;
    return texel;
}

}  // namespace

GBuffer buildGBuffer(const RenderContext& ctx) {
    const Camera& camera = ctx.camera;
    GBuffer out(camera.width(), camera.height());
    int width = out.width(), maxDepth = std::max(1, ctx.settings.maxDepth);
    ctx.pool.parallelFor(size_t(out.height()), [&](size_t row) {
        ctx.throwIfCancelled();
        int y = int(row);
        uint64_t rays = 0;
        Ray primary[8];
        SurfaceHit hits[8];
        bool found[8];
        // Eight neighbouring camera rays at a time: Embree's packet kernel (render_scene.h).
        for (int x0 = 0; x0 < width; x0 += 8) {
            int count = std::min(8, width - x0);
            for (int i = 0; i < count; ++i)
                primary[i] = camera.generateRay(Vec2f{float(x0 + i) + 0.5f, float(y) + 0.5f});
            ctx.scene.intersect8(primary, count, hits, found);
            for (int i = 0; i < count; ++i)
                if (found[i])
                    out.at(x0 + i, y) =
                        texelFrom(ctx.scene, hits[i], -primary[i].d, maxDepth, rays);
        }
    });
    return out;
}

}  // namespace partita
