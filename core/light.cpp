#include "light.h"

#include <cmath>

#include "sampling.h"

namespace partita {

float SpotLight::falloff(Vec3f wLight) const {
    float c = dot(direction, wLight);
    if (c <= cosOuter) return 0;
    if (c >= cosInner) return 1;
    float t = (c - cosOuter) / (cosInner - cosOuter);
    return t * t;  // glTF's recommended smooth attenuation
}

float lightPower(const Light& light) {
    struct Visitor {
        float operator()(const AreaLight& l) const {
            return luminance(l.emission) * l.area * kPi * (l.twoSided ? 2.f : 1.f);
        }
        float operator()(const PointLight& l) const { return 4 * kPi * luminance(l.intensity); }
        float operator()(const SpotLight& l) const {
            return 2 * kPi * (1 - 0.5f * (l.cosInner + l.cosOuter)) * luminance(l.intensity);
        }
        float operator()(const DirectionalLight& l) const {
            return kPi * l.sceneRadius * l.sceneRadius * luminance(l.irradiance);
        }
        // As a disk of the scene's radius radiating the map's mean radiance.
        float operator()(const EnvironmentLight& l) const {
            return kPi * kPi * l.sceneRadius * l.sceneRadius * l.map->meanLuminance();
        }
    };
    return std::visit(Visitor{}, light);
}

bool isDeltaLight(const Light& light) {
    return !std::holds_alternative<AreaLight>(light) &&
           !std::holds_alternative<EnvironmentLight>(light);
}

float areaLightPdf(const AreaLight& l, Vec3f ref, Vec3f p) {
    // The density sampleAreaLight gives, computed the same way.
    Vec3f d = p - ref;
    float dist2 = lengthSquared(d);
    if (dist2 <= 0) return 0;
    float cosD = absDot(l.normal, d);
    if (cosD <= 0) return 0;
    return dist2 * std::sqrt(dist2) / (cosD * l.area);
}

std::optional<LightSample> samplePunctualLight(const Light& light, Vec3f ref) {
    LightSample s;
    s.isDelta = true;
    s.pdf = 1;
    if (auto* pl = std::get_if<PointLight>(&light)) {
        Vec3f d = pl->position - ref;
        float dist2 = lengthSquared(d);
        if (dist2 <= 0) return std::nullopt;
        s.distance = std::sqrt(dist2);
        s.wi = d / s.distance;
        s.point = pl->position;
        s.normal = -s.wi;
        s.radiance = pl->intensity / dist2;
        return s;
    }
    if (auto* sl = std::get_if<SpotLight>(&light)) {
        Vec3f d = sl->position - ref;
        float dist2 = lengthSquared(d);
        if (dist2 <= 0) return std::nullopt;
        s.distance = std::sqrt(dist2);
        s.wi = d / s.distance;
        s.point = sl->position;
        s.normal = -s.wi;
        s.radiance = sl->intensity * (sl->falloff(-s.wi) / dist2);
        if (isBlack(s.radiance)) return std::nullopt;
        return s;
    }
    if (auto* dl = std::get_if<DirectionalLight>(&light)) {
        s.wi = -dl->direction;
        s.distance = kInf;
        s.point = ref + s.wi * (2 * dl->sceneRadius + length(ref - dl->sceneCenter));
        s.normal = dl->direction;
        s.radiance = dl->irradiance;
        return s;
    }
    return std::nullopt;
}

}  // namespace partita
