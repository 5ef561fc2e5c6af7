#include "path/connection.h"

#include <cmath>

#include "bsdfs/bound_bsdf.h"
#include "camera.h"
#include "light_emission.h"
#include "path/random_walk.h"
#include "path/short_edge_damping.h"
#include "path/transmittance.h"
#include "render_scene.h"

namespace partita {

namespace {

Vec3f directionTo(const PathVertex& from, const PathVertex& to) { return normalize(to.p - from.p); }

/// Lights a camera path can hit (the s = 0 strategy exists): area lights and the environment.
bool isHittable(const RenderScene& scene, int light) {
    return light >= 0 && isHittableLight(scene.lights()[size_t(light)]);
}

/// A point on light `light`, chosen as next-event estimation from `ref` chooses it (uniform by
/// area on a triangle; the light's own position otherwise), as a light vertex.
PathVertex sampleLightVertex(const RenderScene& scene, int light, Vec3f ref, Vec2f u) {
    const Light& l = scene.lights()[size_t(light)];
    if (const auto* area = std::get_if<AreaLight>(&l)) {
        // The point as a hit on its triangle, computed as a ray's hit is (so that a stored
        // path rebuilds it bit for bit).
        Vec2f b = sampleUniformTriangle(u);
        SurfaceHit hit = scene.hitAt(area->mesh, area->triangle, {b.y, 1 - b.x - b.y});
        return lightVertex(scene, light, hit.p, hit.ng, hit, Vec3f(0.0f));
    }
    if (const auto* point = std::get_if<PointLight>(&l))
        return lightVertex(scene, light, point->position, Vec3f(0.0f), {}, Vec3f(0.0f));
    if (const auto* spot = std::get_if<SpotLight>(&l))
        return lightVertex(scene, light, spot->position, Vec3f(0.0f), {}, Vec3f(0.0f));
    if (const auto* env = std::get_if<EnvironmentLight>(&l)) {
        // A direction by the map's importance, as pt's next-event estimation draws it.
        Vec3f d;
        float pdf;
        PathVertex none;
        if (!env->map->sample(u, d, pdf)) return none;  // density 0: no vertex
        Vec3f far = ref + d * (2 * env->sceneRadius + length(ref - env->sceneCenter));
        return lightVertex(scene, light, far, Vec3f(0.0f), {}, d);
    }
    const auto& dir = std::get<DirectionalLight>(l);
    Vec3f far = ref - dir.direction * (2 * dir.sceneRadius + length(ref - dir.sceneCenter));
    return lightVertex(scene, light, far, Vec3f(0.0f), {}, -dir.direction);
}

}  // namespace

PathType connectedType(std::span<const PathVertex> camera, int t, std::span<const PathVertex> light,
                       int s) {
    PathType type;
    for (int i = 1; i < t; ++i) type = type.withVertex(camera[size_t(i)].delta);
    for (int j = s - 1; j >= 1; --j) type = type.withVertex(light[size_t(j)].delta);
    return type;
}

bool Connector::visible(const PathVertex& a, const PathVertex& b, uint64_t& rays) const {
    ++rays;
    return !scene_.occluded(spawnShadowRay(a.p, a.ng, b.p, b.ng));
}

void Connector::assemble(std::span<const PathVertex> camera, int t,
                         std::span<const PathVertex> light, int s) {
    path_.clear();
    densities_.clear();
    ShortEdgeDamping damping(shortEdge_);
    auto add = [&](const PathVertex& v) {
        densities_.push_back({v.pdfFromEye, v.pdfFromLight, v.isConnectable()});
        if (keepPaths_) path_.push_back(v);
        if (shortEdge_ > 0) damping.add(v.p);
    };
    for (int i = 0; i < t; ++i) add(camera[size_t(i)]);
    for (int j = s - 1; j >= 0; --j) add(light[size_t(j)]);
    edgeDamping_ = damping.factor();
    const PathVertex& last = s > 0 ? light[0] : camera[size_t(t - 1)];
    info_.cameraConnectable = camera_.isConnectable() && !pathTracer_;  // no light tracing
    info_.lightHittable = isHittable(scene_, last.light);
    info_.maxLightVertices = pathTracer_ ? 1 : 1 << 30;
}

StrategySample Connector::connect(std::span<const PathVertex> camera,
                                  std::span<const PathVertex> light, int s, int t, Rng& rng,
                                  uint64_t& rays, bool weighted, MisHeuristic heuristic) {
    StrategySample r;
    if (t < 1 || s < 0 || s + t < 2 || size_t(t) > camera.size() || size_t(s) > light.size())
        return r;
    if (s == 0)
        r = emitterHit(camera, t);
    else if (t == 1)
        r = lightTracing(light, s, rays);
    else if (s == 1)
        r = nextEvent(camera, t, rng, rays);
    else
        r = edge(camera, light, s, t, rays);
    if (!r.valid) return r;
    if (isBlack(r.value) || !isFinite(r.value)) return StrategySample{};
    // The full path carries the densities the connection computed.
    for (size_t i = 0; keepPaths_ && i < path_.size(); ++i) {
        path_[i].pdfFromEye = densities_[i].fromEye;
        path_[i].pdfFromLight = densities_[i].fromLight;
    }
    r.weight = weighted ? misWeight(densities_, t, info_, heuristic) : 1.0f;
    r.edgeDamping = edgeDamping_;
    return r;
}

StrategySample Connector::emitterHit(std::span<const PathVertex> camera, int t) {
    StrategySample r;
    if (t < 2) return r;
    const PathVertex& e = camera[size_t(t - 1)];
    if (!isHittable(scene_, e.light)) return r;
    const PathVertex& before = camera[size_t(t - 2)];
    Rgb le = e.atInfinity ? emittedTowards(scene_, e, before.p)
                          : scene_.emittedRadiance(e.hit, directionTo(e, before));
    if (isBlack(le)) return r;
    assemble(camera, t, {}, 0);
    // The last camera vertex is the light vertex of this path.
    const Light& light = scene_.lights()[size_t(e.light)];
    if (keepPaths_) {
        path_.back().kind = VertexKind::Light;
        path_.back().delta = !cameraCanConnectTo(light);  // as a light vertex, whatever its BSDF
    }
    VertexDensities& x = densities_[size_t(t - 1)];
    x.fromLight = lightVertexDensity(scene_, e.light, directionTo(before, e));
    x.connectable = cameraCanConnectTo(light);
    densities_[size_t(t - 2)].fromLight = densityTowards(light, e.p, e.ng, before.p, before.ng);
    info_.lightHittable = true;
    r.valid = true;
    r.value = e.beta * le;
    r.type = connectedType(camera, t - 1, {}, 0);
    return r;
}

StrategySample Connector::nextEvent(std::span<const PathVertex> camera, int t, Rng& rng,
                                    uint64_t& rays) {
    StrategySample r;
    const PathVertex& c = camera[size_t(t - 1)];
    if (!c.isSurface() || !c.isConnectable() || !scene_.hasLights()) return r;
    float uLight = rng.nextFloat();
    Vec2f u{rng.nextFloat(), rng.nextFloat()};
    int light = int(scene_.lightSelection().sample(uLight));
    PathVertex lv = sampleLightVertex(scene_, light, c.p, u);
    if (!(lv.pdfFromLight > 0)) return r;
    const Light& l = scene_.lights()[size_t(light)];
    bool infinite = isInfiniteLight(l);
    Vec3f d = lv.p - c.p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return r;
    Vec3f w = d / std::sqrt(dist2);
    // Le times the light end of the edge, |cos_g(light)| / d^2 (1 / d^2 without a surface;
    // nothing for an infinite light: a directional light's "Le" is an irradiance, and the
    // environment's vertex density is a solid angle one).
    float geometry = infinite ? 1.0f : geometricCos(lv, w) / dist2;
    Rgb le = emittedTowards(scene_, lv, c.p);
    const PathVertex& before = camera[size_t(t - 2)];
    Vec3f wo = directionTo(c, before);
    BoundBsdf bsdf(c.bsdf, wo);
    BoundBsdf::Value fc = bsdf.evalPdf(w);
    Rgb value = c.beta * fc.f * (absDot(w, c.hit.ns) * geometry) * le * lv.beta *
                edgeTransmittance(scene_, c, lv);
    if (isBlack(value) || !visible(c, lv, rays)) return r;
    assemble(camera, t, std::span<const PathVertex>(&lv, 1), 1);
    VertexDensities& xl = densities_[size_t(t)];
    xl.fromEye = isHittable(scene_, light) ? solidAngleToArea(fc.pdf, c, lv) : 0;
    densities_[size_t(t - 1)].fromLight = densityTowards(l, lv.p, lv.ng, c.p, c.ng);
    densities_[size_t(t - 2)].fromLight = solidAngleToArea(BoundBsdf(c.bsdf, w).pdf(wo), c, before);
    r.valid = true;
    r.value = value;
    r.type = connectedType(camera, t, {}, 0);
    return r;
}

StrategySample Connector::lightTracing(std::span<const PathVertex> light, int s, uint64_t& rays) {
    StrategySample r;
    const PathVertex& l = light[size_t(s - 1)];
    if (!camera_.isConnectable() || !l.isConnectable()) return r;
    std::optional<Vec2f> raster = camera_.rasterOf(l.p);
    if (!raster || !camera_.inImportanceSupport(*raster)) return r;
    PathVertex eye;
    eye.kind = VertexKind::Camera;
    eye.p = camera_.position();
    eye.pdfFromEye = 1;
    eye.beta = Rgb(1.0f);
    Vec3f d = l.p - eye.p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return r;
    Vec3f w = d / std::sqrt(dist2);
    float we = camera_.importance(w);
    if (!(we > 0)) return r;
    // The edge camera -- l: cos at the camera, |cos_g(l)|, 1 / d^2.
    float geometry = dot(w, camera_.forward()) * geometricCos(l, w) / dist2;
    Rgb scatter;  // what l sends towards the camera per unit of its throughput
    float pdfTowardsNext = 0;
    if (s == 1) {
        scatter = emittedTowards(scene_, l, eye.p);
    } else {
        BoundBsdf bsdf(l.bsdf, -w);
        BoundBsdf::Value v = bsdf.evalPdf(directionTo(l, light[size_t(s - 2)]));
        scatter = v.f;
        pdfTowardsNext = v.pdf;
    }
    Rgb value = l.beta * scatter * (we * geometry) * edgeTransmittance(scene_, l, eye);
    if (isBlack(value) || !visible(l, eye, rays)) return r;
    PathVertex eyes[1] = {eye};
    assemble(std::span<const PathVertex>(eyes, 1), 1, light, s);
    densities_[1].fromEye = camera_.directionPdf(w) * geometricCos(l, w) / dist2;
    if (s >= 2) densities_[2].fromEye = solidAngleToArea(pdfTowardsNext, l, light[size_t(s - 2)]);
    r.valid = true;
    r.value = value;
    r.type = connectedType({}, 0, light, s);
    r.raster = *raster;
    return r;
}

StrategySample Connector::edge(std::span<const PathVertex> camera,
                               std::span<const PathVertex> light, int s, int t, uint64_t& rays) {
    StrategySample r;
    const PathVertex& c = camera[size_t(t - 1)];
    const PathVertex& l = light[size_t(s - 1)];
    if (!c.isSurface() || !l.isSurface() || !c.isConnectable() || !l.isConnectable()) return r;
    Vec3f d = l.p - c.p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return r;
    Vec3f w = d / std::sqrt(dist2);
    const PathVertex& cPrev = camera[size_t(t - 2)];
    const PathVertex& lPrev = light[size_t(s - 2)];
    Vec3f woC = directionTo(c, cPrev), wiL = directionTo(l, lPrev);
    BoundBsdf::Value fc = BoundBsdf(c.bsdf, woC).evalPdf(w);
    BoundBsdf::Value fl = BoundBsdf(l.bsdf, -w).evalPdf(wiL);
    // The new edge: |cos_s| at its camera end, |cos_g| at its light end (random_walk.h).
    float geometry = absDot(w, c.hit.ns) * geometricCos(l, w) / dist2;
    Rgb value = c.beta * fc.f * geometry * fl.f * l.beta * edgeTransmittance(scene_, c, l);
    if (isBlack(value) || !visible(c, l, rays)) return r;
    assemble(camera, t, light, s);
    densities_[size_t(t)].fromEye = solidAngleToArea(fc.pdf, c, l);
    densities_[size_t(t + 1)].fromEye = solidAngleToArea(fl.pdf, l, lPrev);
    densities_[size_t(t - 1)].fromLight = solidAngleToArea(BoundBsdf(l.bsdf, wiL).pdf(-w), l, c);
    densities_[size_t(t - 2)].fromLight = solidAngleToArea(BoundBsdf(c.bsdf, w).pdf(woC), c, cPrev);
    r.valid = true;
    r.value = value;
    r.type = connectedType(camera, t, light, s);
    return r;
}

}  // namespace partita
