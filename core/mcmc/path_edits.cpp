#include "mcmc/path_edits.h"

#include "bsdfs/bound_bsdf.h"
#include "camera.h"
#include "light_emission.h"
#include "path/dirac_vertex.h"
#include "path/random_walk.h"
#include "ray.h"
#include "render_scene.h"

namespace partita {

std::optional<PathVertex> traceVertex(const RenderScene& scene, const PathVertex& from, Vec3f w,
                                      uint64_t& rays) {
    Ray ray = isBlack(from.ng) ? Ray{from.p, w, kInf} : spawnRay(from.p, from.ng, w);
    SurfaceHit hit;
    ++rays;
    if (scene.intersect(ray, hit)) return surfaceVertex(scene, hit, -w);
    int env = scene.environmentLightIndex();
    if (env < 0) return std::nullopt;
    const auto& light = std::get<EnvironmentLight>(scene.lights()[size_t(env)]);
    Vec3f far = from.p + w * (2 * light.sceneRadius + length(from.p - light.sceneCenter));
    return lightVertex(scene, env, far, Vec3f(0.0f), {}, w);
}

bool isRefraction(const PathVertex& v, Vec3f a, Vec3f b) {
    return (dot(a, v.ng) > 0) != (dot(b, v.ng) > 0);
}

std::optional<Vec3f> followBranch(const PathVertex& v, Vec3f wo, bool refraction,
                                  TransportMode mode) {
    BoundBsdf bound(v.bsdf, wo);
    BsdfSample s;
    // The Dirac lobes reflect for small uc and refract for large uc (smooth_dielectric.h).
    for (float uc : {0.0f, 0x1.fffffep-1f})
        if (bound.sample(uc, Vec2f{0.5f, 0.5f}, s, mode) && s.isDelta &&
            s.isTransmission == refraction)
            return s.wi;
    return std::nullopt;
}

int retraceChain(const RenderScene& scene, const MarkovPath& x, const PathVertex& from, Vec3f w,
                 int first, int step, std::vector<PathVertex>& out, uint64_t& rays) {
    TransportMode mode = step > 0 ? TransportMode::Radiance : TransportMode::Importance;
    const PathVertex* previous = &from;
    for (int i = first; i >= 1 && i < x.size(); i += step) {
        std::optional<PathVertex> v = traceVertex(scene, *previous, w, rays);
        if (!v) return -1;
        const PathVertex& old = x[i];
        bool last = i == x.size() - 1;
        if (old.delta && !last) {
            if (!v->isSurface() || !v->delta) return -1;
            Vec3f before = normalize(x[i - step].p - old.p),
                  after = normalize(x[i + step].p - old.p);
            std::optional<Vec3f> next =
                followBranch(*v, -w, isRefraction(old, before, after), mode);
            if (!next) return -1;
            w = *next;
            out.push_back(*v);
            previous = &out.back();
            continue;
        }
        if (last) {
            // A light seen through the chain: the same kind of light again.
            bool sameKind = old.atInfinity ? v->atInfinity : v->isSurface() && v->light >= 0;
            if (!sameKind) return -1;
            out.push_back(v->atInfinity ? *v : asLightVertex(scene, *v));
        } else {
            if (!v->isSurface() || v->delta) return -1;
            out.push_back(*v);
        }
        return i;
    }
    return -1;
}

bool visible(const RenderScene& scene, const PathVertex& a, const PathVertex& b, uint64_t& rays) {
    ++rays;
    return !scene.occluded(spawnShadowRay(a.p, a.ng, b.p, b.ng));
}

PathVertex asLightVertex(const RenderScene& scene, PathVertex v) {
    v.kind = VertexKind::Light;
    if (v.light >= 0) v.delta = !cameraCanConnectTo(scene.lights()[size_t(v.light)]);
    return v;
}

bool isInfiniteLightVertex(const RenderScene& scene, const PathVertex& v) {
    return v.kind == VertexKind::Light && v.light >= 0 &&
           isInfiniteLight(scene.lights()[size_t(v.light)]);
}

PathVertex reanchoredLight(const RenderScene& scene, const PathVertex& light, Vec3f old,
                           Vec3f neighbour) {
    Vec3f w = normalize(light.p - old);
    const Light& l = scene.lights()[size_t(light.light)];
    Vec3f center;
    float radius = 1;
    if (const auto* env = std::get_if<EnvironmentLight>(&l)) {
        center = env->sceneCenter;
        radius = env->sceneRadius;
    } else if (const auto* dir = std::get_if<DirectionalLight>(&l)) {
        center = dir->sceneCenter;
        radius = dir->sceneRadius;
    }
    PathVertex v = light;
    v.p = neighbour + w * (2 * radius + length(neighbour - center));
    return v;
}

bool reconnect(const RenderScene& scene, const Camera& camera, const MarkovPath& x, int c,
               std::vector<PathVertex>& y, uint64_t& rays) {
    int n = x.size();
    PathVertex next = x[c + 1];
    bool last = c + 1 == n - 1;
    if (last && isInfiniteLightVertex(scene, next))
        next = reanchoredLight(scene, next, x[c].p, y.back().p);
    if (!connectable(camera, y.back(), next, last) || !visible(scene, y.back(), next, rays))
        return false;
    y.push_back(next);
    y.insert(y.end(), x.vertices.begin() + c + 2, x.vertices.end());
    return true;
}

bool connectable(const Camera& camera, const PathVertex& a, const PathVertex& b, bool bIsLast) {
    if (a.kind == VertexKind::Camera) return camera.isConnectable() && !b.delta;
    if (!a.isSurface() || a.delta) return false;
    return !b.delta || bIsLast;
}

int firstNonDirac(const MarkovPath& x, int from) {
    for (int i = from; i < x.size(); ++i)
        if (!x[i].delta || i == x.size() - 1) return i;
    return -1;
}

double retracedEyeDensity(const Camera& camera, const MarkovPath& x, int last) {
    Vec3f w = normalize(x[1].p - x[0].p);
    double p = solidAngleToArea(camera.directionPdf(w), x[0], x[1]);
    for (int i = 2; i <= last; ++i) p *= retracedDensity(x[i - 1], x[i]);
    return p;
}

double retracedLightDensity(const MarkovPath& x, int a) {
    double p = retracedDensity(x[a], x[a - 1]);
    for (int i = a - 2; i >= 1; --i) {
        const PathVertex& dirac = x[i + 1];
        DiracBranch b =
            diracBranch(dirac, normalize(x[i].p - dirac.p), normalize(x[i + 2].p - dirac.p));
        p *= double(b.jacobian) * retracedDensity(dirac, x[i]);
    }
    return p;
}

float cameraSupportScale(const Camera& camera) {
    double w = camera.width(), h = camera.height();
    return float(w * h / ((w + 1) * (h + 1)));
}

Vec2f sampleSupportRaster(const Camera& camera, Vec2f u) {
    return {-0.5f + u.x * float(camera.width() + 1), -0.5f + u.y * float(camera.height() + 1)};
}

}  // namespace partita
