#include "integrators/pt/path_sampler.h"

#include <cmath>

#include "bsdf.h"
#include "bsdfs/bound_bsdf.h"
#include "integrators/pt/film_sink.h"
#include "medium.h"
#include "render_scene.h"

namespace partita {

namespace {

/// State carried from one vertex of the camera path to the next.
struct PathState {
    Rgb beta{1.0f};   // throughput f/p of the path so far
    PathType type;    // scattering vertices so far, camera first
    Vec3f prevPoint;  // previous scattering vertex, for the light pdf in MIS
    float prevBsdfPdf = 0;
    bool prevSpecular = true;  // camera rays count as specular: emitters seen directly get weight 1
    float etaScale = 1;        // radiance scaling from refraction, removed for Russian roulette
    Rgb mediumAbsorption{0.0f};
    bool inMedium = false;  // mediumAbsorption is not black
    int contributions = 0;
};

/// Sink: ContributionSink (virtual) or FilmSink (inlined); both have add(const PathContribution&).
template <typename Sink>
class PathSampler {
  public:
    PathSampler(const RenderScene& scene, Rng& rng, const PathSamplerSettings& settings, Sink& sink,
                PathCounters& counters)
        : scene_(scene), rng_(rng), settings_(settings), sink_(sink), counters_(counters) {}
    // Rays are counted here and added to the shared counters once: two samplers in lockstep
    // would otherwise chain their steps through one counter in memory.
    ~PathSampler() { counters_.rays += rays_; }
    PathSampler(const PathSampler&) = delete;
    PathSampler& operator=(const PathSampler&) = delete;

    /// The whole path from `from`: a primary Ray or a PathStart (see start).
    template <typename Start>
    void run(const Start& from) {
        start(from);
        while (step()) {
        }
    }

    /// Starts the path at `primary`; step() then extends it one vertex at a time.
    void start(const Ray& primary) {
        // Ray directions are unit vectors: the primary's by contract, and sampled BSDF
        // directions are unit (up to rounding), so wo needs no normalisation at each vertex.
        ray_ = primary;
        depth_ = 0;
    }

    /// Starts the path of `path`. When its primary ray was traced already, the first step()
    /// takes its hit (or miss) instead of tracing the ray again.
    void start(const PathStart& path) {
        start(path.primary);
        primaryTraced_ = path.traced;
        primaryFound_ = path.traced && path.hit != nullptr;
        if (primaryFound_) hit_ = *path.hit;
    }

    /// Traces the current ray and handles the vertex it finds: emission, next-event estimation
    /// and the continuation. False when the path has ended.
    bool step() {
        SurfaceHit& hit = hit_;
        ++rays_;
        bool found;
        if (primaryTraced_) {
            primaryTraced_ = false;
            found = primaryFound_;
        } else {
            found = scene_.intersect(ray_, hit);
        }
        if (!found) {
            addEnvironment(ray_.d);
            return false;
        }
        if (state_.inMedium)
            state_.beta *= beerLambert(state_.mediumAbsorption, hit.t * length(ray_.d));
        addEmission(hit, -ray_.d);
        // This hit becomes scattering vertex number depth + 1.
        if (depth_ + 1 > settings_.maxDepth) return false;
        Bsdf bsdf = scene_.bsdfAt(hit);
        BoundBsdf bound(bsdf, -ray_.d);
        bool delta = bound.isDelta();
        PathType typeHere = state_.type.withVertex(delta);
        RayOrigins origins(hit.p, hit.ng);
        // The point on a light and the continuation are both sampled before either is used
        // (drawing the random numbers in the same order, light first): the two are
        // independent, so the processor overlaps their chains of divisions and square roots
        // instead of waiting for each in turn.
        LightSample light;
        int lightIndex = delta ? -1 : sampleNextEvent(hit, light);
        float uc = rng_.nextFloat();
        Vec2f u{rng_.nextFloat(), rng_.nextFloat()};
        BsdfSample bs;
        bool continues = bound.sample(uc, u, bs);
        if (lightIndex >= 0) addNextEvent(hit, bound, origins, light, lightIndex, typeHere);
        if (!continues || !continuePath(hit, bs, origins, typeHere, ray_, depth_)) return false;
        ++depth_;
        return true;
    }

  private:
    void report(PathType type, Rgb value, bool viaNextEvent) {
        int index = state_.contributions++;
        if constexpr (requires { sink_.add(type, value); }) {
            // A sink that needs only type and value (FilmSink) gets them without a
            // PathContribution assembled in memory and read back at once.
            sink_.add(type, value);
        } else {
            PathContribution c;
            c.type = type;
            c.value = value;
            c.index = index;
            c.viaNextEvent = viaNextEvent;
            sink_.add(c);
        }
    }

    /// Emission seen by a BSDF-sampled (or camera) ray, MIS-weighted against light sampling.
    void addEmission(const SurfaceHit& hit, Vec3f towardsPrevious) {
        int light = scene_.areaLightIndex(hit);
        if (light < 0) return;
        Rgb le = scene_.emittedRadiance(hit, towardsPrevious);
        if (isBlack(le)) return;
        float weight = 1;
        if (!state_.prevSpecular) {
            float lightPdf =
                scene_.lightSelectionPmf(light) * scene_.areaLightPdf(light, state_.prevPoint, hit);
            weight = powerHeuristic(state_.prevBsdfPdf, lightPdf);
        }
        report(state_.type, state_.beta * le * weight, false);
    }

    /// The environment seen by a ray that leaves the scene, MIS-weighted against sampling it.
    void addEnvironment(Vec3f d) {
        if (!scene_.hasEnvironment()) return;
        Rgb le = scene_.environmentRadiance(d);
        if (isBlack(le)) return;
        float weight = state_.prevSpecular
                           ? 1.0f
                           : powerHeuristic(state_.prevBsdfPdf, scene_.environmentPdf(d));
        report(state_.type, state_.beta * le * weight, false);
    }

    /// Next-event estimation, first half: one light chosen by power, one point on it. Returns
    /// the light's index, or -1 when there is nothing to connect to.
    int sampleNextEvent(const SurfaceHit& hit, LightSample& ls) {
        if (!scene_.hasLights()) return -1;
        float uLight = rng_.nextFloat();
        Vec2f uPoint{rng_.nextFloat(), rng_.nextFloat()};
        int light = int(scene_.lightSelection().sample(uLight));
        if (!scene_.sampleLight(light, hit.p, uPoint, ls) || ls.pdf <= 0) return -1;
        return light;
    }

    /// Next-event estimation, second half: the BSDF, visibility and the MIS-weighted
    /// contribution of the sampled light point.
    void addNextEvent(const SurfaceHit& hit, const BoundBsdf& bsdf, RayOrigins& origins,
                      const LightSample& ls, int light, PathType typeHere) {
        // The pdf is needed only if the light is visible, but with f it costs little more.
        BoundBsdf::Value b = bsdf.evalPdf(ls.wi);
        Rgb f = b.f * absDot(ls.wi, hit.ns);
        if (isBlack(f)) return;
        ++rays_;
        Ray shadow = shadowRayFrom(origins.towards(ls.point - hit.p), hit.p, ls.point, ls.normal);
        if (scene_.occluded(shadow)) return;
        float lightPdf = scene_.lightSelectionPmf(light) * ls.pdf;
        float weight = ls.isDelta ? 1.0f : powerHeuristic(lightPdf, b.pdf);
        report(typeHere, state_.beta * f * ls.radiance * (weight / lightPdf), true);
    }

    /// Follows the sampled BSDF direction; false when the path ends here.
    bool continuePath(const SurfaceHit& hit, const BsdfSample& bs, RayOrigins& origins,
                      PathType typeHere, Ray& ray, int depth) {
        state_.beta *= bs.f * (absDot(bs.wi, hit.ns) / bs.pdf);
        if (isBlack(state_.beta) || !isFinite(state_.beta)) return false;
        state_.type = typeHere;
        state_.prevPoint = hit.p;
        state_.prevBsdfPdf = bs.pdf;
        state_.prevSpecular = bs.isDelta;
        if (bs.isTransmission) {
            state_.etaScale *= sqr(bs.eta);
            // Entering when the new direction goes against the outward normal.
            state_.mediumAbsorption =
                dot(bs.wi, hit.ng) < 0 ? absorptionOf(scene_.materialOf(hit)) : Rgb(0.0f);
            state_.inMedium = !isBlack(state_.mediumAbsorption);
        }
        if (!russianRoulette(depth)) return false;
        ray = {origins.towards(bs.wi), bs.wi, kInf};  // spawnRay(hit.p, hit.ng, wi)
        return true;
    }

    bool russianRoulette(int depth) {
        if (depth + 1 < settings_.rouletteStartDepth) return true;
        float survival = std::min(1.0f, maxComponent(state_.beta) * state_.etaScale);
        if (survival >= 1) return true;
        survival = std::max(survival, 0.05f);
        if (rng_.nextFloat() >= survival) return false;
        state_.beta /= survival;
        return true;
    }

    const RenderScene& scene_;
    Rng& rng_;
    const PathSamplerSettings& settings_;
    Sink& sink_;
    PathCounters& counters_;
    uint64_t rays_ = 0;
    PathState state_;
    Ray ray_;
    SurfaceHit hit_;
    int depth_ = 0;
    bool primaryTraced_ = false;  // hit_ holds the primary ray's hit (if primaryFound_)
    bool primaryFound_ = false;
};

}  // namespace

void samplePath(const RenderScene& scene, const Ray& primary, Rng& rng,
                const PathSamplerSettings& settings, ContributionSink& sink,
                PathCounters& counters) {
    PathSampler<ContributionSink>(scene, rng, settings, sink, counters).run(primary);
}

void samplePath(const RenderScene& scene, const Ray& primary, Rng& rng,
                const PathSamplerSettings& settings, FilmSink& sink, PathCounters& counters) {
    PathSampler<FilmSink>(scene, rng, settings, sink, counters).run(primary);
}

void samplePath(const RenderScene& scene, const PathStart& path,
                const PathSamplerSettings& settings, PathCounters& counters) {
    PathSampler<FilmSink>(scene, path.rng, settings, path.sink, counters).run(path);
}

void samplePathPair(const RenderScene& scene, const PathStart& a, const PathStart& b,
                    const PathSamplerSettings& settings, PathCounters& counters) {
    PathSampler<FilmSink> first(scene, a.rng, settings, a.sink, counters);
    PathSampler<FilmSink> second(scene, b.rng, settings, b.sink, counters);
    first.start(a);
    second.start(b);
    // Alternate one vertex of each: consecutive ray queries then belong to independent paths,
    // so the processor overlaps one path's traversal with the other's shading (as it overlaps
    // the independent queries of a bare Embree loop) instead of waiting on each hit in turn.
    bool firstAlive = true, secondAlive = true;
    while (firstAlive && secondAlive) {
        firstAlive = first.step();
        secondAlive = second.step();
    }
    while (firstAlive) firstAlive = first.step();
    while (secondAlive) secondAlive = second.step();
}

}  // namespace partita
