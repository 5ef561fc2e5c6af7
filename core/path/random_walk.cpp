#include "path/random_walk.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include "bsdfs/bound_bsdf.h"
#include "camera.h"
#include "light_emission.h"
#include "path/transmittance.h"
#include "render_scene.h"

namespace partita {

PathVertex surfaceVertex(const RenderScene& scene, const SurfaceHit& hit, Vec3f wo) {
    PathVertex v;
    v.kind = VertexKind::Surface;
    v.p = hit.p;
    v.ng = hit.ng;
    v.hit = hit;
    v.light = scene.areaLightIndex(hit);
    v.bsdf = scene.bsdfAt(hit);
    v.delta = BoundBsdf(v.bsdf, wo).isDelta();
    return v;
}

namespace {

/// Extends `path` (whose last vertex emitted `ray`) by surface hits until it is absorbed,
/// escapes, fails Russian roulette or reaches the vertex limit.
class Walk {
  public:
    Walk(const RenderScene& scene, Rng& rng, const WalkSettings& settings, TransportMode mode,
         std::vector<PathVertex>& path, uint64_t& rays)
        : scene_(scene), rng_(rng), settings_(settings), mode_(mode), path_(path), rays_(rays) {}

    /// `pdf` is the density of the ray's direction in solid angle at the emitting vertex, or,
    /// when `parallel` (an orthographic camera, a directional light), the density of its origin
    /// on a plane perpendicular to it.
    void run(Ray ray, Rgb beta, float pdf, bool parallel) {
        startLevel_ = std::max(maxComponent(beta), 1e-30f);
        while (int(path_.size()) < settings_.maxVertices) {
            if (!hitNext(ray, beta, pdf, parallel)) return;
            if (int(path_.size()) >= settings_.maxVertices) return;
            if (!scatter(ray, beta, pdf)) return;
            parallel = false;
        }
    }

    /// Continues the walk from the path's last vertex (a surface seen from the vertex before
    /// it): samples its BSDF, then runs on. The path's betas are not used.
    void extend() {
        if (path_.size() < 2 || !path_.back().isSurface()) return;
        startLevel_ = 1;
        wo_ = normalize(path_[path_.size() - 2].p - path_.back().p);
        Ray ray;
        Rgb beta(1.0f);
        float pdf = 0;
        if (int(path_.size()) >= settings_.maxVertices || !scatter(ray, beta, pdf)) return;
        run(ray, beta, pdf, false);
    }

  private:
    /// Traces `ray` from the last vertex and appends the surface it hits; false when it misses
    /// (the environment's vertex is appended first, for camera walks) or the vertex is useless.
    bool hitNext(const Ray& ray, Rgb& beta, float pdf, bool parallel) {
        SurfaceHit hit;
        ++rays_;
        if (!scene_.intersect(ray, hit)) {
            if (mode_ == TransportMode::Radiance) addEnvironmentVertex(ray, beta, pdf);
            return false;
        }
        Vec3f wo = wo_ = -ray.d;
        PathVertex v = surfaceVertex(scene_, hit, wo);
        beta *= edgeTransmittance(scene_, path_.back(), v);
        float cosG = absDot(hit.ng, wo);
        float density = parallel ? pdf * cosG : solidAngleToArea(pdf, path_.back(), v);
        forwardPdf(v) = density;
        if (mode_ == TransportMode::Importance) {
            if (!(cosG > 0)) return false;
            beta *= absDot(hit.ns, wo) / cosG;
        }
        v.beta = beta;
        path_.push_back(v);
        return true;
    }

    /// Samples the BSDF of the last vertex: the next ray, the throughput and the direction's
    /// density; false when the walk ends there (no sample, black, Russian roulette).
    bool scatter(Ray& ray, Rgb& beta, float& pdf) {
        const PathVertex& here = path_.back();
        if (settings_.stopAfterNonSpecular && scatteredNonSpecular_) return false;
        Vec3f wo = wo_;
        BoundBsdf bound(here.bsdf, wo);
        float uc = rng_.nextFloat();
        Vec2f u{rng_.nextFloat(), rng_.nextFloat()};
        BsdfSample bs;
        if (!bound.sample(uc, u, bs, mode_)) return false;
        float cosOut = absDot(bs.wi, mode_ == TransportMode::Radiance ? here.hit.ns : here.hit.ng);
        beta *= bs.f * (cosOut / bs.pdf);
        if (isBlack(beta) || !isFinite(beta)) return false;
        // The density of the previous vertex when sampled from here (the reverse walk).
        PathVertex& previous = path_[path_.size() - 2];
        reversePdf(previous) =
            bs.isDelta ? 0 : solidAngleToArea(BoundBsdf(here.bsdf, bs.wi).pdf(wo), here, previous);
        if (bs.isTransmission && mode_ == TransportMode::Radiance) etaScale_ *= sqr(bs.eta);
        int scattering = int(path_.size()) - 1;
        if (!survivesRoulette(scattering, beta)) return false;
        ray = spawnRay(here.hit.p, here.hit.ng, bs.wi);
        pdf = bs.isDelta ? 0 : bs.pdf;
        scatteredNonSpecular_ = scatteredNonSpecular_ || !here.delta;
        return true;
    }

    /// A camera ray that leaves the scene reaches the environment, if there is one: a vertex
    /// at infinity, with the ray's direction density (solid angle) as its density.
    void addEnvironmentVertex(const Ray& ray, Rgb beta, float pdf) {
        int env = scene_.environmentLightIndex();
        if (env < 0) return;
        const auto& light = std::get<EnvironmentLight>(scene_.lights()[size_t(env)]);
        Vec3f far = ray.o + ray.d * (2 * light.sceneRadius + length(ray.o - light.sceneCenter));
        PathVertex v = lightVertex(scene_, env, far, Vec3f(0.0f), {}, ray.d);
        v.pdfFromEye = pdf;
        v.beta = beta;
        path_.push_back(v);
    }

    /// The density in the walk's own direction, and the other one.
    float& forwardPdf(PathVertex& v) const {
        return mode_ == TransportMode::Radiance ? v.pdfFromEye : v.pdfFromLight;
    }
    float& reversePdf(PathVertex& v) const {
        return mode_ == TransportMode::Radiance ? v.pdfFromLight : v.pdfFromEye;
    }

    /// pt's rule: from the given number of scattering vertices on, survive with probability
    /// min(1, throughput) (relative to the start for light walks), at least 0.05.
    bool survivesRoulette(int scattering, Rgb& beta) {
        if (scattering < settings_.rouletteStartDepth) return true;
        float survival = std::min(1.0f, maxComponent(beta) * etaScale_ / startLevel_);
        if (survival >= 1) return true;
        survival = std::max(survival, 0.05f);
        if (rng_.nextFloat() >= survival) return false;
        beta /= survival;
        return true;
    }

    const RenderScene& scene_;
    Rng& rng_;
    const WalkSettings& settings_;
    TransportMode mode_;
    std::vector<PathVertex>& path_;
    uint64_t& rays_;
    float startLevel_ = 1, etaScale_ = 1;
    bool scatteredNonSpecular_ = false;  // a non-specular vertex has been scattered from
    Vec3f wo_;                           // at the last vertex, towards the one before it
};

}  // namespace

void traceCameraSubpath(const RenderScene& scene, const Camera& camera, const Ray& primary,
                        Rng& rng, const WalkSettings& settings, std::vector<PathVertex>& out,
                        uint64_t& rays) {
    out.clear();
    PathVertex c;
    c.kind = VertexKind::Camera;
    c.p = primary.o;
    c.beta = Rgb(1.0f);  // We cos / pdf = 1 for the camera's own rays
    c.pdfFromEye = 1;    // the pinhole's position is a delta
    out.push_back(c);
    // Densities normalised over the whole image: see Camera::directionPdf.
    float pdf = camera.directionPdf(primary.d);
    Walk(scene, rng, settings, TransportMode::Radiance, out, rays)
        .run(primary, Rgb(1.0f), pdf, camera.isOrthographic());
}

PathVertex lightVertex(const RenderScene& scene, int light, Vec3f p, Vec3f n, const SurfaceHit& hit,
                       Vec3f towardsLight) {
    const Light& l = scene.lights()[size_t(light)];
    PathVertex v;
    v.kind = VertexKind::Light;
    v.p = p;
    v.ng = n;
    v.hit = hit;
    v.light = light;
    v.delta = !cameraCanConnectTo(l);
    v.atInfinity = std::holds_alternative<EnvironmentLight>(l);
    v.pdfFromLight = lightVertexDensity(scene, light, towardsLight);
    v.beta = Rgb(v.pdfFromLight > 0 ? 1 / v.pdfFromLight : 0.0f);
    return v;
}

Rgb emittedTowards(const RenderScene& scene, const PathVertex& v, Vec3f towards) {
    const Light& l = scene.lights()[size_t(v.light)];
    if (std::holds_alternative<AreaLight>(l))
        return scene.emittedRadiance(v.hit, normalize(towards - v.p));
    if (const auto* env = std::get_if<EnvironmentLight>(&l))
        return env->map->radiance(normalize(v.p - towards));
    if (const auto* point = std::get_if<PointLight>(&l)) return point->intensity;
    if (const auto* spot = std::get_if<SpotLight>(&l))
        return spot->intensity * spot->falloff(normalize(towards - v.p));
    return std::get<DirectionalLight>(l).irradiance;
}

void traceLightSubpath(const RenderScene& scene, Rng& rng, const WalkSettings& settings,
                       std::vector<PathVertex>& out, uint64_t& rays) {
    out.clear();
    if (!scene.hasLights() || settings.maxVertices < 1) return;
    float uLight = rng.nextFloat();
    Vec2f uPos{rng.nextFloat(), rng.nextFloat()};
    Vec2f uDir{rng.nextFloat(), rng.nextFloat()};
    int light = int(scene.lightSelection().sample(uLight));
    EmittedRay e;
    if (!sampleLe(scene, light, uPos, uDir, e)) return;
    PathVertex l = lightVertex(scene, light, e.origin, e.normal, e.hit, -e.direction);
    if (!(l.pdfFromLight > 0)) return;
    out.push_back(l);
    bool infinite = isInfiniteLight(scene.lights()[size_t(light)]);
    // Le |cos at the light| / (density of the origin and of the direction). An infinite light
    // has no cosine: a directional light's irradiance, or the environment's radiance over its
    // direction density (lightVertexDensity), over the density of the ray's origin on its disk,
    // which is also the (projected) density the next vertex gets.
    float cosLight = isBlack(e.normal) ? 1.0f : absDot(e.normal, e.direction);
    Rgb beta = infinite ? e.le / (l.pdfFromLight * e.pdfPos)
                        : e.le * (cosLight / (l.pdfFromLight * e.pdfDir));
    Ray ray = isBlack(e.normal) ? Ray{e.origin, e.direction, kInf}
                                : spawnRay(e.origin, e.normal, e.direction);
    Walk(scene, rng, settings, TransportMode::Importance, out, rays)
        .run(ray, beta, infinite ? e.pdfPos : e.pdfDir, infinite);
}

void extendSubpath(const RenderScene& scene, Rng& rng, TransportMode mode, int count,
                   std::vector<PathVertex>& path, uint64_t& rays) {
    WalkSettings settings;
    settings.maxVertices = int(path.size()) + count;
    settings.rouletteStartDepth = INT32_MAX;
    Walk(scene, rng, settings, mode, path, rays).extend();
}

}  // namespace partita
