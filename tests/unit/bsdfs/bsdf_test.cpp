// BSDF lobes, the Bsdf wrapper, and the glTF material -> BSDF mapping.
//
// Statistical tests use fixed seeds. Their thresholds come from the estimators' own standard
// errors or from the chi-square distribution (see chi2.h), never from hand-tuned constants.
// Deterministic float comparisons use a relative epsilon stated at each use.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <ostream>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "bsdf.h"
#include "bsdfs/fresnel.h"
#include "chi2.h"
#include "material_mapping.h"
#include "rng.h"
#include "sampling.h"

using namespace partita;
using partita::test::Chi2Options;

namespace partita {
// gtest value printer for vectors and colours (internal linkage: other test files may have
// their own).
[[maybe_unused]] static void PrintTo(const Vec3f& v, std::ostream* os) {
    *os << "(" << v.x << ", " << v.y << ", " << v.z << ")";
}
}  // namespace partita
using partita::test::chi2Test;

namespace {

// ---------------------------------------------------------------------------------------------
// Shared helpers

Vec3f direction(float thetaDeg, float phi) {
    float t = thetaDeg * kPi / 180;
    return Vec3f(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
}
Vec3f below(Vec3f w) { return Vec3f(w.x, w.y, -w.z); }

const char* lobeName(const BsdfLobe& lobe) {
    static const char* names[] = {"Lambert", "Conductor",        "Dielectric",
                                  "Mirror",  "SmoothDielectric", "DiffuseConductorMix"};
    return names[lobe.index()];
}

std::string describe(const BsdfLobe& lobe, Vec3f wo) {
    std::string s = lobeName(lobe);
    std::visit(
        [&](const auto& l) {
            using L = std::decay_t<decltype(l)>;
            if constexpr (std::is_same_v<L, ConductorLobe>)
                s += " alpha=" + std::to_string(l.alpha);
            if constexpr (std::is_same_v<L, DielectricLobe>)
                s += " alpha=" + std::to_string(l.alpha) + " eta=" + std::to_string(l.eta);
            if constexpr (std::is_same_v<L, DiffuseConductorMixLobe>)
                s += " alpha=" + std::to_string(l.conductor.alpha) +
                     " m=" + std::to_string(l.metallic);
        },
        lobe);
    return s + " wo=(" + std::to_string(wo.x) + "," + std::to_string(wo.y) + "," +
           std::to_string(wo.z) + ")";
}

Rgb lobeEval(const BsdfLobe& lobe, Vec3f wo, Vec3f wi, TransportMode mode) {
    return std::visit([&](const auto& l) { return l.eval(wo, wi, mode); }, lobe);
}
float lobePdf(const BsdfLobe& lobe, Vec3f wo, Vec3f wi) {
    return std::visit([&](const auto& l) { return l.pdf(wo, wi); }, lobe);
}
std::optional<BsdfSample> lobeSample(const BsdfLobe& lobe, Vec3f wo, Rng& rng, TransportMode mode) {
    float uc = rng.nextFloat();
    Vec2f u(rng.nextFloat(), rng.nextFloat());
    return std::visit([&](const auto& l) { return l.sample(wo, uc, u, mode); }, lobe);
}

bool isTransmissiveLobe(const BsdfLobe& lobe) {
    return std::holds_alternative<DielectricLobe>(lobe) ||
           std::holds_alternative<SmoothDielectricLobe>(lobe);
}

// wo directions: normal incidence, two oblique ones and a grazing one (cos = 0.052).
std::vector<Vec3f> outsideDirections() {
    return {Vec3f(0, 0, 1), direction(35, 0.3f), direction(70, 2.1f), direction(87, 4.0f)};
}
std::vector<Vec3f> bothSideDirections() {
    std::vector<Vec3f> w = outsideDirections();
    for (Vec3f v : outsideDirections()) w.push_back(below(v));
    return w;
}

struct LobeCase {
    BsdfLobe lobe;
    Vec3f wo;
};

// Every non-Dirac lobe at several roughness values and wo (both sides for the dielectric).
std::vector<LobeCase> nonDiracCases() {
    std::vector<LobeCase> cases;
    for (Vec3f wo : outsideDirections()) cases.push_back({LambertLobe{Rgb(0.8f, 0.6f, 0.4f)}, wo});
    for (float roughness : {0.3f, 0.6f, 0.9f}) {
        float alpha = roughness * roughness;
        for (Vec3f wo : outsideDirections())
            cases.push_back({ConductorLobe{Rgb(0.9f, 0.6f, 0.3f), alpha}, wo});
        for (Vec3f wo : outsideDirections())
            cases.push_back(
                {DiffuseConductorMixLobe{LambertLobe{Rgb(0.7f)},
                                         ConductorLobe{Rgb(0.9f, 0.6f, 0.3f), alpha}, 0.4f},
                 wo});
        for (Vec3f wo : bothSideDirections())
            cases.push_back({DielectricLobe{1.5f, alpha, Rgb(1.0f)}, wo});
    }
    // Water-like index, and an index below one (normal pointing into the denser medium).
    for (Vec3f wo : bothSideDirections())
        cases.push_back({DielectricLobe{1.33f, 0.25f, Rgb(1.0f)}, wo});
    for (Vec3f wo : bothSideDirections())
        cases.push_back({DielectricLobe{1 / 1.5f, 0.16f, Rgb(1.0f)}, wo});
    return cases;
}

// Family-wise significance of all chi-square tests in this file.
constexpr double kFamilyAlpha = 1e-3;

int chi2FamilySize() { return int(nonDiracCases().size()) + 2; }  // + the fine-grid cases

void runChi2(const BsdfLobe& lobe, Vec3f wo, uint64_t stream, const Chi2Options& opts = {}) {
    Rng rng(20240611, stream);
    auto sampler = [&](Rng& r) -> std::optional<Vec3f> {
        auto s = lobeSample(lobe, wo, r, TransportMode::Radiance);
        if (!s) return std::nullopt;
        return s->wi;
    };
    auto pdf = [&](Vec3f wi) { return double(lobePdf(lobe, wo, wi)); };
    auto result = chi2Test(sampler, pdf, rng, opts);
    double level = partita::test::sidakLevel(kFamilyAlpha, chi2FamilySize());
    EXPECT_GE(result.pValue, level) << describe(lobe, wo) << ": " << result.describe();
    // The pdf may lose mass to failed samples but can never integrate to more than one (the
    // quadrature error is far below the 1e-2 allowed here).
    EXPECT_LE(result.pdfIntegral, 1.01) << describe(lobe, wo);
}

void runChi2ForLobe(size_t lobeIndex) {
    auto cases = nonDiracCases();
    int ran = 0;
    for (size_t i = 0; i < cases.size(); ++i) {
        if (cases[i].lobe.index() != lobeIndex) continue;
        runChi2(cases[i].lobe, cases[i].wo, i);
        ++ran;
    }
    EXPECT_GT(ran, 0);
}

template <class T>
size_t lobeIndexOf() {
    return BsdfLobe(T{}).index();
}

// Mean and standard error of a sample of weights.
struct MeanEstimate {
    double sum = 0, sumSq = 0;
    long n = 0;
    void add(double v) {
        sum += v;
        sumSq += v * v;
        ++n;
    }
    double mean() const { return sum / double(n); }
    double standardError() const {
        double m = mean();
        double var = std::max(0.0, sumSq / double(n) - m * m);
        return std::sqrt(var / double(n - 1));
    }
};

// Directional albedo of a lobe (luminance of f |cos| / pdf) by its own sampling.
MeanEstimate sampledAlbedo(const BsdfLobe& lobe, Vec3f wo, TransportMode mode, int n, Rng& rng) {
    MeanEstimate e;
    for (int i = 0; i < n; ++i) {
        auto s = lobeSample(lobe, wo, rng, mode);
        if (!s) {
            e.add(0);
            continue;
        }
        e.add(luminance(s->f) * std::abs(s->wi.z) / s->pdf);
    }
    return e;
}

// The same integral from eval() alone, with uniform directions on the sphere.
MeanEstimate uniformAlbedo(const BsdfLobe& lobe, Vec3f wo, TransportMode mode, int n, Rng& rng) {
    MeanEstimate e;
    for (int i = 0; i < n; ++i) {
        Vec3f wi = sampleUniformSphere({rng.nextFloat(), rng.nextFloat()});
        e.add(luminance(lobeEval(lobe, wo, wi, mode)) * std::abs(wi.z) / uniformSpherePdf());
    }
    return e;
}

// Reference Fresnel from the angle form (Fresnel's sine and tangent laws), independent of the
// algebraic form in fresnel.h. etaI / etaT: indices on the incident / transmitted side.
double referenceFresnel(double thetaI, double etaI, double etaT) {
    double sinT = etaI / etaT * std::sin(thetaI);
    if (sinT >= 1) return 1;
    double thetaT = std::asin(sinT);
    if (thetaI == 0) return std::pow((etaT - etaI) / (etaT + etaI), 2);
    double rs = std::sin(thetaI - thetaT) / std::sin(thetaI + thetaT);
    double rp = std::tan(thetaI - thetaT) / std::tan(thetaI + thetaT);
    return 0.5 * (rs * rs + rp * rp);
}

// Relative agreement for deterministic float results: float carries 2^-24 ~ 6e-8 relative
// precision; the recomputed half vector and the powers in D, G and Fresnel amplify it by at most
// a few hundred at the roughness values tested, so 1e-4 separates round-off from real errors
// (which change values by percents) with a wide margin.
constexpr float kRelEps = 1e-4f;
bool nearlyEqual(float a, float b, float rel = kRelEps) {
    return std::abs(a - b) <= rel * std::max({std::abs(a), std::abs(b), 1e-20f});
}
bool nearlyEqual(Rgb a, Rgb b, float rel = kRelEps) {
    return nearlyEqual(a.x, b.x, rel) && nearlyEqual(a.y, b.y, rel) && nearlyEqual(a.z, b.z, rel);
}

}  // namespace

// =============================================================================================
// The chi-square helper itself

TEST(Chi2Helper, IncompleteGammaMatchesClosedForms) {
    // Q(1, x) = exp(-x); Q(1/2, x) = erfc(sqrt(x)); both branches (x < a + 1 and x >= a + 1).
    for (double x : {0.1, 0.7, 1.5, 3.0, 12.0, 40.0}) {
        EXPECT_NEAR(partita::test::regularizedGammaQ(1.0, x), std::exp(-x),
                    1e-12 + 1e-10 * std::exp(-x));
        EXPECT_NEAR(partita::test::regularizedGammaQ(0.5, x), std::erfc(std::sqrt(x)), 1e-12);
    }
    // Q(n, x) = exp(-x) sum_{k<n} x^k / k! for integer n.
    for (double x : {2.0, 9.0, 25.0}) {
        double sum = 0, term = 1;
        for (int k = 0; k < 6; ++k) {
            sum += term;
            term *= x / (k + 1);
        }
        EXPECT_NEAR(partita::test::regularizedGammaQ(6.0, x), std::exp(-x) * sum, 1e-12);
    }
    // Tabulated chi-square critical values: P(X >= 23.209) = 0.01 for 10 dof, P(X >= 3.841) =
    // 0.05 for 1 dof (tables give 4 significant digits).
    EXPECT_NEAR(partita::test::chi2SurvivalProbability(23.209, 10), 0.01, 1e-5);
    EXPECT_NEAR(partita::test::chi2SurvivalProbability(3.841, 1), 0.05, 1e-4);
}

TEST(Chi2Helper, AcceptsCorrectAndRejectsWrongSamplers) {
    Rng rng(7, 1);
    auto cosine = [](Rng& r) -> std::optional<Vec3f> {
        return sampleCosineHemisphere({r.nextFloat(), r.nextFloat()});
    };
    auto cosinePdf = [](Vec3f w) { return double(cosineHemispherePdf(w.z)); };
    auto uniformHemispherePdf = [](Vec3f w) { return w.z > 0 ? 1 / (2 * kPi) : 0.0; };
    double level = partita::test::sidakLevel(kFamilyAlpha, chi2FamilySize());
    EXPECT_GE(chi2Test(cosine, cosinePdf, rng).pValue, level);
    // Wrong shape.
    EXPECT_LT(chi2Test(cosine, uniformHemispherePdf, rng).pValue, level);
    // Right shape, 2% of the mass claimed to be lost: caught by the failure cell.
    auto leaky = [&](Vec3f w) { return 0.98 * cosinePdf(w); };
    EXPECT_LT(chi2Test(cosine, leaky, rng).pValue, level);
    // A GGX sampler tested against a pdf with a 10% larger alpha.
    ConductorLobe a{Rgb(1.0f), 0.36f}, b{Rgb(1.0f), 0.36f * 1.1f};
    Vec3f wo = direction(35, 0.3f);
    auto ggx = [&](Rng& r) -> std::optional<Vec3f> {
        auto s =
            a.sample(wo, r.nextFloat(), {r.nextFloat(), r.nextFloat()}, TransportMode::Radiance);
        if (!s) return std::nullopt;
        return s->wi;
    };
    EXPECT_GE(chi2Test(
                  ggx, [&](Vec3f w) { return double(a.pdf(wo, w)); }, rng)
                  .pValue,
              level);
    EXPECT_LT(chi2Test(
                  ggx, [&](Vec3f w) { return double(b.pdf(wo, w)); }, rng)
                  .pValue,
              level);
}

TEST(Chi2Helper, PoolsLowCountCellsAndFlagsSupportViolations) {
    Rng rng(7, 2);
    // All samples at the pole, the pdf claims the upper hemisphere is uniform: the upper bins
    // have expectation and the lower ones none. A sampler that leaks into the lower hemisphere
    // must be flagged.
    auto lowerLeak = [](Rng& r) -> std::optional<Vec3f> {
        return sampleUniformSphere({r.nextFloat(), r.nextFloat()});
    };
    auto upperPdf = [](Vec3f w) { return w.z > 0 ? 1 / (2 * kPi) : 0.0; };
    auto result = chi2Test(lowerLeak, upperPdf, rng);
    EXPECT_GT(result.supportViolations, 0);
    EXPECT_EQ(result.pValue, 0);
    // Few samples: most cells fall below 5 and are pooled, and the test still accepts.
    Chi2Options few;
    few.sampleCount = 3000;
    auto uniformUpper = [](Rng& r) -> std::optional<Vec3f> {
        Vec3f w = sampleUniformSphere({r.nextFloat(), r.nextFloat()});
        return Vec3f(w.x, w.y, std::abs(w.z));
    };
    result = chi2Test(uniformUpper, upperPdf, rng, few);
    EXPECT_GT(result.pooledCells, 0);
    EXPECT_GT(result.dof, 10);
    EXPECT_GE(result.pValue, partita::test::sidakLevel(kFamilyAlpha, chi2FamilySize()));
}

// =============================================================================================
// Chi-square: sample() against pdf() for every non-Dirac lobe

TEST(BsdfChi2, Lambert) { runChi2ForLobe(lobeIndexOf<LambertLobe>()); }
TEST(BsdfChi2, Conductor) { runChi2ForLobe(lobeIndexOf<ConductorLobe>()); }
TEST(BsdfChi2, DiffuseConductorMix) { runChi2ForLobe(lobeIndexOf<DiffuseConductorMixLobe>()); }
TEST(BsdfChi2, Dielectric) { runChi2ForLobe(lobeIndexOf<DielectricLobe>()); }

TEST(BsdfChi2, SmallRoughnessOnFineGrid) {
    // alpha = 0.0225 (roughness 0.15): the lobe spans a few coarse bins only, so use a grid
    // 4x finer in both angles and more samples.
    Chi2Options fine;
    fine.thetaBins = 64;
    fine.phiBins = 128;
    fine.sampleCount = 400000;
    runChi2(ConductorLobe{Rgb(0.9f), 0.0225f}, direction(50, 1.0f), 1000, fine);
    runChi2(DielectricLobe{1.5f, 0.0225f, Rgb(1.0f)}, below(direction(30, 1.0f)), 1001, fine);
}

// =============================================================================================
// Non-Dirac lobes: consistency, reciprocity, energy

TEST(BsdfLobes, SampleAgreesWithEvalAndPdf) {
    auto cases = nonDiracCases();
    for (size_t c = 0; c < cases.size(); ++c) {
        const auto& [lobe, wo] = cases[c];
        Rng rng(99, c);
        int checked = 0;
        for (int i = 0; i < 2000; ++i) {
            for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
                auto s = lobeSample(lobe, wo, rng, mode);
                if (!s) continue;
                ++checked;
                ASSERT_GT(s->pdf, 0) << describe(lobe, wo);
                EXPECT_FALSE(s->isDelta);
                EXPECT_TRUE(isFinite(s->f));
                EXPECT_NEAR(length(s->wi), 1.0f, 1e-5f);
                EXPECT_TRUE(nearlyEqual(s->f, lobeEval(lobe, wo, s->wi, mode)))
                    << describe(lobe, wo) << " sample f " << s->f.x << " eval "
                    << lobeEval(lobe, wo, s->wi, mode).x;
                EXPECT_TRUE(nearlyEqual(s->pdf, lobePdf(lobe, wo, s->wi)))
                    << describe(lobe, wo) << " sample pdf " << s->pdf << " pdf "
                    << lobePdf(lobe, wo, s->wi);
                bool crossed = wo.z * s->wi.z < 0;
                EXPECT_EQ(s->isTransmission, crossed) << describe(lobe, wo);
                if (!isTransmissiveLobe(lobe)) {
                    EXPECT_FALSE(crossed);
                }
                if (crossed) {
                    float eta = std::get<DielectricLobe>(lobe).eta;
                    EXPECT_FLOAT_EQ(s->eta, wo.z > 0 ? eta : 1 / eta);
                } else {
                    EXPECT_EQ(s->eta, 1.0f);
                }
            }
        }
        EXPECT_GT(checked, 1000) << describe(lobe, wo);
    }
}

TEST(BsdfLobes, Reciprocity) {
    Rng rng(5, 5);
    auto cases = nonDiracCases();
    for (const auto& [lobe, unusedWo] : cases) {
        (void)unusedWo;
        int nonZeroReflection = 0, nonZeroTransmission = 0;
        for (int i = 0; i < 3000; ++i) {
            Vec3f a = sampleUniformSphere({rng.nextFloat(), rng.nextFloat()});
            Vec3f b = sampleUniformSphere({rng.nextFloat(), rng.nextFloat()});
            if (!isTransmissiveLobe(lobe)) {
                a.z = std::abs(a.z);
                b.z = std::abs(b.z);
            }
            if (a.z * b.z > 0) {
                // Reflection: f(a, b) = f(b, a), in either transport mode.
                Rgb fab = lobeEval(lobe, a, b, TransportMode::Radiance);
                Rgb fba = lobeEval(lobe, b, a, TransportMode::Radiance);
                // The exact dielectric Fresnel has a square-root singularity at the critical
                // angle, so round-off eps in the cosine (evaluated from a or from b) can move F
                // by ~sqrt(eps) = 2.4e-4; allow 4 sqrt(eps) there.
                float tolerance = isTransmissiveLobe(lobe) ? kRelEps + 4 * 0x1p-12f : kRelEps;
                EXPECT_TRUE(nearlyEqual(fab, fba, tolerance))
                    << describe(lobe, a) << " " << fab.x << " " << fba.x;
                EXPECT_TRUE(nearlyEqual(fab, lobeEval(lobe, a, b, TransportMode::Importance)));
                nonZeroReflection += maxComponent(fab) > 0;
            } else {
                // Transmission: the importance BTDF is the adjoint of the radiance one,
                // f_importance(a, b) = f_radiance(b, a) (Veach's thesis, sec. 5.2).
                Rgb fImp = lobeEval(lobe, a, b, TransportMode::Importance);
                Rgb fRad = lobeEval(lobe, b, a, TransportMode::Radiance);
                nonZeroTransmission += maxComponent(fImp) > 0;
                // Conditioning: with c the smaller |cos| between a or b and the generalised half
                // vector, the transmittance 1 - F and the projected-area factors vanish
                // linearly as c -> 0, so float round-off (eps = 2^-24) in the half vector grows
                // to about eps / c^2 relative; allow 16 eps / c^2 on top of kRelEps.
                float eta = std::get<DielectricLobe>(lobe).eta;
                Vec3f wm = normalize(a + b * (a.z > 0 ? eta : 1 / eta));
                float c = std::min(absDot(a, wm), absDot(b, wm));
                float tolerance = kRelEps + 16 * 0x1p-24f / std::max(c * c, 1e-12f);
                EXPECT_TRUE(nearlyEqual(fImp, fRad, tolerance))
                    << describe(lobe, a) << " " << fImp.x << " " << fRad.x << " c=" << c;
            }
        }
        EXPECT_GT(nonZeroReflection, 100) << lobeName(lobe);
        if (isTransmissiveLobe(lobe)) {
            EXPECT_GT(nonZeroTransmission, 100) << lobeName(lobe);
        }
    }
}

// White versions of the non-Dirac cases: energy conservation is a statement about them.
BsdfLobe whiten(BsdfLobe lobe) {
    std::visit(
        [](auto& l) {
            using L = std::decay_t<decltype(l)>;
            if constexpr (std::is_same_v<L, LambertLobe>) l.reflectance = Rgb(1.0f);
            if constexpr (std::is_same_v<L, ConductorLobe>) l.f0 = Rgb(1.0f);
            if constexpr (std::is_same_v<L, DielectricLobe>) l.tint = Rgb(1.0f);
            if constexpr (std::is_same_v<L, DiffuseConductorMixLobe>) {
                l.diffuse.reflectance = Rgb(1.0f);
                l.conductor.f0 = Rgb(1.0f);
            }
        },
        lobe);
    return lobe;
}

TEST(BsdfLobes, EnergyConservation) {
    // The directional albedo int f |cos| dwi may not exceed one. For transmission that holds in
    // importance mode from both sides (it is the radiance BSDF's conservation of energy, read
    // through the adjoint); in radiance mode it holds from the rarer side (wo outside for
    // eta > 1), where the 1 / etap^2 factor is below one. Rejection when the estimate exceeds 1 by
    // more than 4 standard errors: a one-sided false alarm of 3e-5 per case.
    auto cases = nonDiracCases();
    for (size_t c = 0; c < cases.size(); ++c) {
        BsdfLobe lobe = whiten(cases[c].lobe);
        Vec3f wo = cases[c].wo;
        Rng rng(31, c);
        std::vector<TransportMode> modes = {TransportMode::Importance};
        bool rarerSide = true;
        if (auto* d = std::get_if<DielectricLobe>(&lobe)) rarerSide = (wo.z > 0) == (d->eta > 1);
        if (rarerSide) modes.push_back(TransportMode::Radiance);
        for (TransportMode mode : modes) {
            MeanEstimate e = sampledAlbedo(lobe, wo, mode, 20000, rng);
            EXPECT_LE(e.mean(), 1 + 4 * e.standardError())
                << describe(lobe, wo) << " albedo " << e.mean() << " +- " << e.standardError();
        }
    }
}

TEST(BsdfLobes, SampledAlbedoMatchesIntegralOfEval) {
    // Two estimators of int f |cos| dwi: the lobe's own sampling (tests sample's f / pdf) and
    // uniform sphere directions through eval() (independent of sample and pdf). They must agree
    // within 4 combined standard errors (two-sided false alarm 6e-5 per case). This catches a
    // pdf or f that is consistently off by a factor, which the chi-square test (shape) and the
    // sample-vs-eval check (pointwise agreement) cannot see when both sides share the error.
    auto cases = nonDiracCases();
    for (size_t c = 0; c < cases.size(); ++c) {
        const auto& [lobe, wo] = cases[c];
        Rng rng(77, c);
        for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
            MeanEstimate sampled = sampledAlbedo(lobe, wo, mode, 20000, rng);
            MeanEstimate uniform = uniformAlbedo(lobe, wo, mode, 100000, rng);
            double se = std::hypot(sampled.standardError(), uniform.standardError());
            EXPECT_NEAR(sampled.mean(), uniform.mean(), 4 * se)
                << describe(lobe, wo) << " sampled " << sampled.mean() << " uniform "
                << uniform.mean();
        }
    }
}

TEST(BsdfLobes, LambertAlbedoEqualsReflectance) {
    LambertLobe lobe{Rgb(0.8f, 0.5f, 0.2f)};
    for (Vec3f wo : outsideDirections()) {
        Rng rng(3, 3);
        MeanEstimate e = uniformAlbedo(lobe, wo, TransportMode::Radiance, 200000, rng);
        EXPECT_NEAR(e.mean(), luminance(lobe.reflectance), 4 * e.standardError());
        EXPECT_GT(e.standardError(), 0);
        // Cosine sampling has zero variance: every weight is the reflectance.
        for (int i = 0; i < 100; ++i) {
            auto s = lobe.sample(wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()},
                                 TransportMode::Radiance);
            ASSERT_TRUE(s);
            EXPECT_TRUE(nearlyEqual(s->f * (s->wi.z / s->pdf), lobe.reflectance));
        }
    }
}

TEST(BsdfLobes, OpaqueLobesAreZeroBelowTheSurface) {
    for (const auto& [lobe, wo] : nonDiracCases()) {
        if (isTransmissiveLobe(lobe) || wo.z <= 0) continue;
        Rng rng(1, 1);
        EXPECT_FALSE(lobeSample(lobe, below(wo), rng, TransportMode::Radiance));
        Vec3f up = direction(20, 1.0f);
        EXPECT_EQ(lobeEval(lobe, below(wo), up, TransportMode::Radiance), Rgb(0.0f));
        EXPECT_EQ(lobeEval(lobe, wo, below(up), TransportMode::Radiance), Rgb(0.0f));
        EXPECT_EQ(lobePdf(lobe, wo, below(up)), 0.0f);
        EXPECT_EQ(lobePdf(lobe, below(wo), up), 0.0f);
    }
}

TEST(BsdfLobes, ConductorFresnelTintAndAlphaClamp) {
    // At the specular configuration the conductor's colour is Schlick's F with F0 = tint.
    Vec3f wo = direction(60, 0.0f), wi = Vec3f(-wo.x, -wo.y, wo.z);
    ConductorLobe lobe{Rgb(0.9f, 0.5f, 0.1f), 0.3f};
    Rgb f = lobe.eval(wo, wi, TransportMode::Radiance);
    Rgb fresnel = fresnelSchlick(wo.z, lobe.f0);
    EXPECT_TRUE(nearlyEqual(f.y / f.x, fresnel.y / fresnel.x));
    EXPECT_TRUE(nearlyEqual(f.z / f.x, fresnel.z / fresnel.x));
    // Alpha below kMinAlpha renders as kMinAlpha.
    ConductorLobe tiny{Rgb(1.0f), 1e-6f}, clamped{Rgb(1.0f), kMinAlpha};
    Vec3f wiNear = normalize(wi + Vec3f(1e-3f, 0, 0));
    EXPECT_EQ(tiny.eval(wo, wiNear, TransportMode::Radiance),
              clamped.eval(wo, wiNear, TransportMode::Radiance));
    EXPECT_EQ(tiny.pdf(wo, wiNear), clamped.pdf(wo, wiNear));
}

// =============================================================================================
// Dirac lobes

TEST(BsdfDirac, MirrorReflectsWithSchlickFresnel) {
    MirrorLobe mirror{Rgb(0.9f, 0.6f, 0.3f)};
    EXPECT_TRUE(mirror.isDelta());
    for (Vec3f wo : outsideDirections()) {
        auto s = mirror.sample(wo, 0.5f, {0.3f, 0.7f}, TransportMode::Radiance);
        ASSERT_TRUE(s);
        EXPECT_TRUE(s->isDelta);
        EXPECT_FALSE(s->isTransmission);
        EXPECT_EQ(s->pdf, 1.0f);
        EXPECT_TRUE(nearlyEqual(s->wi, Vec3f(-wo.x, -wo.y, wo.z)));
        EXPECT_TRUE(
            nearlyEqual(s->f * (std::abs(s->wi.z) / s->pdf), fresnelSchlick(wo.z, mirror.tint)));
        EXPECT_EQ(mirror.eval(wo, s->wi, TransportMode::Radiance), Rgb(0.0f));
        EXPECT_EQ(mirror.pdf(wo, s->wi), 0.0f);
        EXPECT_FALSE(mirror.sample(below(wo), 0.5f, {0.3f, 0.7f}, TransportMode::Radiance));
    }
}

TEST(BsdfDirac, SmoothDielectricSnellAndFresnelBranches) {
    for (float eta : {1.5f, 1.33f, 1 / 1.5f}) {
        SmoothDielectricLobe lobe{eta, Rgb(1.0f)};
        EXPECT_TRUE(lobe.isDelta());
        for (Vec3f wo : bothSideDirections()) {
            bool outside = wo.z > 0;
            double etaI = outside ? 1.0 : eta, etaT = outside ? eta : 1.0;
            double thetaI = std::acos(std::min(1.0, std::abs(double(wo.z))));
            double fresnel = referenceFresnel(thetaI, etaI, etaT);
            // Reflection is chosen below uc = F, refraction above.
            float ucReflect = float(fresnel) * 0.999f;
            float ucRefract = float(fresnel + (1 - fresnel) * 0.001);
            auto r = lobe.sample(wo, ucReflect, {0.5f, 0.5f}, TransportMode::Importance);
            if (fresnel > 0) {
                ASSERT_TRUE(r);
                EXPECT_FALSE(r->isTransmission);
                EXPECT_TRUE(r->isDelta);
                EXPECT_TRUE(nearlyEqual(r->wi, Vec3f(-wo.x, -wo.y, wo.z)));
                EXPECT_NEAR(r->pdf, fresnel, 1e-5);
                EXPECT_EQ(lobe.eval(wo, r->wi, TransportMode::Radiance), Rgb(0.0f));
                EXPECT_EQ(lobe.pdf(wo, r->wi), 0.0f);
            }
            if (fresnel >= 1) {  // total internal reflection: never refracts
                auto t = lobe.sample(wo, 0.999999f, {0.5f, 0.5f}, TransportMode::Importance);
                ASSERT_TRUE(t);
                EXPECT_FALSE(t->isTransmission);
                EXPECT_EQ(t->pdf, 1.0f);
                continue;
            }
            auto t = lobe.sample(wo, ucRefract, {0.5f, 0.5f}, TransportMode::Importance);
            ASSERT_TRUE(t);
            EXPECT_TRUE(t->isTransmission);
            EXPECT_NEAR(t->pdf, 1 - fresnel, 1e-5);
            EXPECT_FLOAT_EQ(t->eta, float(etaT / etaI));
            // Snell: other side, etaI sin(thetaI) = etaT sin(thetaT), opposite azimuth.
            EXPECT_LT(t->wi.z * wo.z, 0);
            EXPECT_NEAR(length(t->wi), 1.0f, 1e-5f);
            double sinI = std::hypot(wo.x, wo.y), sinT = std::hypot(t->wi.x, t->wi.y);
            EXPECT_NEAR(etaI * sinI, etaT * sinT, 1e-5);
            if (sinI > 0) {
                EXPECT_NEAR(dot(Vec3f(wo.x, wo.y, 0), Vec3f(t->wi.x, t->wi.y, 0)), -sinI * sinT,
                            1e-5);
            }
            // Energy, white dielectric, importance: F * 1 + (1 - F) * 1 = 1.
            double wR = fresnel > 0 ? luminance(r->f) * std::abs(r->wi.z) / r->pdf : 0;
            double wT = luminance(t->f) * std::abs(t->wi.z) / t->pdf;
            EXPECT_NEAR(fresnel * wR + (1 - fresnel) * wT, 1.0, 1e-5);
            // Radiance: the transmitted weight is 1 / etap^2.
            auto tr = lobe.sample(wo, ucRefract, {0.5f, 0.5f}, TransportMode::Radiance);
            ASSERT_TRUE(tr);
            EXPECT_NEAR(luminance(tr->f) * std::abs(tr->wi.z) / tr->pdf,
                        (etaI * etaI) / (etaT * etaT), 1e-5);
        }
    }
}

TEST(BsdfDirac, SmoothDielectricTintsTransmissionOnly) {
    SmoothDielectricLobe lobe{1.5f, Rgb(0.2f, 0.5f, 0.9f)};
    Vec3f wo = direction(40, 0.2f);
    float fresnel = fresnelDielectric(wo.z, 1.5f);
    auto r = lobe.sample(wo, 0.0f, {}, TransportMode::Importance);
    auto t = lobe.sample(wo, 0.999f, {}, TransportMode::Importance);
    ASSERT_TRUE(r && t);
    EXPECT_TRUE(nearlyEqual(r->f * (std::abs(r->wi.z) / r->pdf), Rgb(1.0f)));
    EXPECT_TRUE(nearlyEqual(t->f * (std::abs(t->wi.z) / t->pdf), lobe.tint));
    EXPECT_NEAR(r->pdf, fresnel, 1e-6f);
}

TEST(BsdfDirac, BranchFrequenciesMatchFresnel) {
    // With random uc the fraction of reflections estimates F; it must be within 4 binomial
    // standard errors.
    SmoothDielectricLobe lobe{1.5f, Rgb(1.0f)};
    Rng rng(11, 0);
    for (Vec3f wo : bothSideDirections()) {
        double fresnel = fresnelDielectric(wo.z, 1.5f);
        const int n = 20000;
        int reflections = 0;
        for (int i = 0; i < n; ++i) {
            auto s = lobe.sample(wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()},
                                 TransportMode::Radiance);
            ASSERT_TRUE(s);
            reflections += !s->isTransmission;
        }
        double se = std::sqrt(fresnel * (1 - fresnel) / n);
        EXPECT_NEAR(double(reflections) / n, fresnel, 4 * se + 1.0 / n);
    }
}

// =============================================================================================
// The Bsdf wrapper: frames, two-sidedness, shading-normal leak guard, albedo()

TEST(BsdfWorld, WorldQueriesMatchLocalLobe) {
    Vec3f n = normalize(Vec3f(0.3f, -0.5f, 0.8f));
    Frame frame = Frame::fromNormal(n);
    ConductorLobe lobe{Rgb(0.9f, 0.7f, 0.5f), 0.2f};
    Bsdf bsdf(frame, n, lobe);
    Rng rng(4, 4);
    int nonZero = 0;
    for (int i = 0; i < 500; ++i) {
        Vec3f woL = sampleCosineHemisphere({rng.nextFloat(), rng.nextFloat()});
        Vec3f wiL = sampleCosineHemisphere({rng.nextFloat(), rng.nextFloat()});
        Vec3f wo = frame.toWorld(woL), wi = frame.toWorld(wiL);
        woL = frame.toLocal(wo);
        wiL = frame.toLocal(wi);
        EXPECT_TRUE(
            nearlyEqual(bsdf.eval(wo, wi), lobe.eval(woL, wiL, TransportMode::Radiance), 1e-3f));
        EXPECT_TRUE(nearlyEqual(bsdf.pdf(wo, wi), lobe.pdf(woL, wiL), 1e-3f));
        float uc = rng.nextFloat();
        Vec2f u(rng.nextFloat(), rng.nextFloat());
        auto s = bsdf.sample(wo, uc, u);
        auto sl = lobe.sample(woL, uc, u, TransportMode::Radiance);
        ASSERT_EQ(bool(s), bool(sl));
        if (!s) continue;
        ++nonZero;
        EXPECT_LT(length(s->wi - frame.toWorld(sl->wi)), 1e-5f);
        EXPECT_TRUE(nearlyEqual(s->pdf, sl->pdf));
    }
    EXPECT_GT(nonZero, 400);
}

TEST(BsdfWorld, OpaqueSurfacesAreTwoSided) {
    Vec3f n(0, 0, 1);
    Bsdf bsdf(Frame::fromNormal(n), n, LambertLobe{Rgb(0.6f)});
    Vec3f wo = below(direction(30, 0.4f)), wi = below(direction(60, 2.0f));
    EXPECT_TRUE(nearlyEqual(bsdf.eval(wo, wi), Rgb(0.6f * kInvPi)));
    EXPECT_TRUE(nearlyEqual(bsdf.pdf(wo, wi), cosineHemispherePdf(-wi.z)));
    // No transmission through it from either side.
    EXPECT_EQ(bsdf.eval(wo, below(wi)), Rgb(0.0f));
    EXPECT_EQ(bsdf.eval(below(wo), wi), Rgb(0.0f));
    Rng rng(6, 6);
    for (int i = 0; i < 200; ++i) {
        auto s = bsdf.sample(wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()});
        ASSERT_TRUE(s);
        EXPECT_LT(s->wi.z, 0);
    }
}

TEST(BsdfWorld, DielectricKnowsInsideFromOutside) {
    Vec3f n(0, 0, 1);
    Bsdf bsdf(Frame::fromNormal(n), n, SmoothDielectricLobe{1.5f, Rgb(1.0f)});
    auto fromOutside = bsdf.sample(direction(30, 0.0f), 0.999f, {});
    auto fromInside = bsdf.sample(below(direction(30, 0.0f)), 0.999f, {});
    ASSERT_TRUE(fromOutside && fromInside);
    EXPECT_TRUE(fromOutside->isTransmission && fromInside->isTransmission);
    EXPECT_FLOAT_EQ(fromOutside->eta, 1.5f);
    EXPECT_FLOAT_EQ(fromInside->eta, 1 / 1.5f);
    EXPECT_LT(fromOutside->wi.z, 0);
    EXPECT_GT(fromInside->wi.z, 0);
}

TEST(BsdfWorld, ShadingNormalsDoNotLeakLight) {
    // Shading normal tilted 40 degrees from the geometric one.
    Vec3f ng(0, 0, 1);
    Vec3f ns = direction(40, 0.0f);
    Frame frame = Frame::fromNormal(ns);
    // wi below ng but above ns: a shading-only reflection that would leak through the surface.
    Vec3f wo = direction(10, 0.0f);
    Vec3f wiLeak = direction(100, 0.0f);
    ASSERT_GT(dot(wiLeak, ns), 0);
    ASSERT_LT(dot(wiLeak, ng), 0);
    std::vector<BsdfLobe> opaque = {
        LambertLobe{Rgb(0.5f)}, ConductorLobe{Rgb(1.0f), 0.5f},
        DiffuseConductorMixLobe{LambertLobe{Rgb(0.5f)}, ConductorLobe{Rgb(1.0f), 0.5f}, 0.5f}};
    for (const BsdfLobe& lobe : opaque) {
        Bsdf bsdf(frame, ng, lobe);
        EXPECT_EQ(bsdf.eval(wo, wiLeak), Rgb(0.0f)) << lobeName(lobe);
        EXPECT_EQ(bsdf.pdf(wo, wiLeak), 0.0f) << lobeName(lobe);
        // The local lobe itself does reflect there; only the guard stops it.
        EXPECT_GT(maxComponent(lobeEval(lobe, frame.toLocal(wo), frame.toLocal(wiLeak),
                                        TransportMode::Radiance)),
                  0)
            << lobeName(lobe);
        Rng rng(8, 8);
        int rejected = 0;
        for (int i = 0; i < 2000; ++i) {
            auto s = bsdf.sample(wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()});
            if (!s) {
                ++rejected;
                continue;
            }
            EXPECT_GT(dot(s->wi, ng), 0) << lobeName(lobe);
            EXPECT_TRUE(nearlyEqual(s->pdf, bsdf.pdf(wo, s->wi), 1e-3f)) << lobeName(lobe);
        }
        EXPECT_GT(rejected, 0) << lobeName(lobe);  // the guard was exercised
    }
    // A dielectric: transmission must cross ng, reflection must stay on wo's side of it.
    for (BsdfLobe lobe : {BsdfLobe(DielectricLobe{1.5f, 0.3f, Rgb(1.0f)}),
                          BsdfLobe(SmoothDielectricLobe{1.5f, Rgb(1.0f)})}) {
        Bsdf bsdf(frame, ng, lobe);
        Rng rng(9, 9);
        for (Vec3f w : {wo, direction(80, 3.1f), below(direction(20, 0.5f))}) {
            for (int i = 0; i < 2000; ++i) {
                auto s = bsdf.sample(w, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()});
                if (!s) continue;
                bool crossedNg = dot(w, ng) * dot(s->wi, ng) < 0;
                EXPECT_EQ(crossedNg, s->isTransmission) << lobeName(lobe);
            }
        }
    }
    // Exhaustively: for every lobe, wo on either side and wi on a grid, whenever the lobe's
    // shading-frame reflection/transmission disagrees with the geometric one and the local lobe
    // gives a non-zero value, the wrapper must give zero.
    std::vector<BsdfLobe> all = opaque;
    all.push_back(DielectricLobe{1.5f, 0.8f, Rgb(1.0f)});
    for (const BsdfLobe& lobe : all) {
        Bsdf bsdf(frame, ng, lobe);
        int leaks = 0;
        for (Vec3f w :
             {wo, direction(60, kPi), below(direction(20, 0)), below(direction(70, kPi))}) {
            for (int i = 1; i < 90; ++i)
                for (int j = 0; j < 36; ++j) {
                    Vec3f wi = direction(2.0f * i, 2 * kPi * j / 36);
                    bool shadingReflect = dot(w, ns) * dot(wi, ns) > 0;
                    bool geometricReflect = dot(w, ng) * dot(wi, ng) > 0;
                    if (shadingReflect == geometricReflect) continue;
                    // The local lobe as the wrapper would see it (mirrored for opaque lobes
                    // hit from the back).
                    Vec3f woL = frame.toLocal(w), wiL = frame.toLocal(wi);
                    if (!isTransmissiveLobe(lobe) && dot(w, ng) < 0) {
                        woL.z = -woL.z;
                        wiL.z = -wiL.z;
                    }
                    if (maxComponent(lobeEval(lobe, woL, wiL, TransportMode::Radiance)) <= 0)
                        continue;
                    ++leaks;
                    EXPECT_EQ(bsdf.eval(w, wi), Rgb(0.0f)) << lobeName(lobe);
                    EXPECT_EQ(bsdf.pdf(w, wi), 0.0f) << lobeName(lobe);
                }
        }
        EXPECT_GT(leaks, 0) << lobeName(lobe);  // the configuration does exercise the guard
    }
}

TEST(BsdfWorld, AlbedoSemantics) {
    Frame f;
    Vec3f ng(0, 0, 1);
    EXPECT_EQ(Bsdf(f, ng, LambertLobe{Rgb(0.1f, 0.2f, 0.3f)}).albedo(), Rgb(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(Bsdf(f, ng, ConductorLobe{Rgb(0.4f), 0.1f}).albedo(), Rgb(0.4f));
    EXPECT_EQ(Bsdf(f, ng, MirrorLobe{Rgb(0.5f)}).albedo(), Rgb(0.5f));
    EXPECT_EQ(Bsdf(f, ng, SmoothDielectricLobe{1.5f, Rgb(0.6f)}).albedo(), Rgb(0.6f));
    EXPECT_EQ(Bsdf(f, ng, DielectricLobe{1.5f, 0.1f, Rgb(0.7f)}).albedo(), Rgb(0.7f));
    Bsdf mix(
        f, ng,
        DiffuseConductorMixLobe{LambertLobe{Rgb(0.2f)}, ConductorLobe{Rgb(1.0f), 0.1f}, 0.25f});
    EXPECT_TRUE(nearlyEqual(mix.albedo(), Rgb(0.75f * 0.2f + 0.25f)));
    EXPECT_TRUE(Bsdf(f, ng, MirrorLobe{}).isDelta());
    EXPECT_TRUE(Bsdf(f, ng, SmoothDielectricLobe{}).isDelta());
    EXPECT_FALSE(Bsdf(f, ng, DielectricLobe{}).isDelta());
    EXPECT_FALSE(Bsdf(f, ng, mix.lobe()).isDelta());
}

// =============================================================================================
// glTF material -> BSDF mapping (rules in material_mapping.h)

namespace {

SurfacePoint flatPoint() {
    SurfacePoint sp;
    sp.ng = Vec3f(0, 0, 1);
    sp.ns = normalize(Vec3f(0.1f, 0, 1));
    sp.uv = {Vec2f(0.25f, 0.25f), Vec2f(0.75f, 0.75f)};
    sp.hasUv[0] = true;
    sp.hasUv[1] = true;
    return sp;
}

// A 2x2 texture with nearest filtering: texel (x, y) has rgb = (x, y, 0.5) style values given.
Texture checker(Rgb t00, Rgb t10, Rgb t01, Rgb t11) {
    Texture t;
    t.width = 2;
    t.height = 2;
    t.filter = TextureFilter::Nearest;
    t.rgba = {t00.x, t00.y, t00.z, 1, t10.x, t10.y, t10.z, 1,
              t01.x, t01.y, t01.z, 1, t11.x, t11.y, t11.z, 1};
    return t;
}

Material dielectricBase() {
    Material m;
    m.baseColor = Rgb(0.8f, 0.6f, 0.4f);
    m.metallic = 0;
    m.roughness = 1;
    return m;
}

template <class L>
L lobeAs(const Bsdf& b) {
    EXPECT_TRUE(std::holds_alternative<L>(b.lobe())) << "got " << lobeName(b.lobe());
    const L* l = std::get_if<L>(&b.lobe());
    return l ? *l : L{};
}

}  // namespace

TEST(MaterialMapping, TransmissionRule) {
    std::vector<Texture> none;
    Material m = dielectricBase();
    m.transmission = 1;
    m.ior = 1.45f;
    m.roughness = 0.0f;
    auto smooth = lobeAs<SmoothDielectricLobe>(makeBsdf(m, none, flatPoint()));
    EXPECT_EQ(smooth.eta, 1.45f);
    EXPECT_EQ(smooth.tint, m.baseColor);
    m.roughness = kSmooth * 0.99f;
    lobeAs<SmoothDielectricLobe>(makeBsdf(m, none, flatPoint()));
    m.roughness = kSmooth;  // the threshold itself is rough
    lobeAs<DielectricLobe>(makeBsdf(m, none, flatPoint()));
    m.roughness = 0.5f;
    auto rough = lobeAs<DielectricLobe>(makeBsdf(m, none, flatPoint()));
    EXPECT_EQ(rough.eta, 1.45f);
    EXPECT_FLOAT_EQ(rough.alpha, 0.25f);
    EXPECT_EQ(rough.tint, m.baseColor);
    // Index-matched: a Dirac pass-through at any roughness.
    m.ior = 1.0f;
    EXPECT_EQ(lobeAs<SmoothDielectricLobe>(makeBsdf(m, none, flatPoint())).eta, 1.0f);
    // glTF weights transmission by (1 - metallic): metals do not transmit.
    m.ior = 1.5f;
    m.metallic = 1;
    lobeAs<ConductorLobe>(makeBsdf(m, none, flatPoint()));
    m.metallic = 0.4f;  // (1 - 0.4) * 1 >= 0.5: still glass
    lobeAs<DielectricLobe>(makeBsdf(m, none, flatPoint()));
    m.metallic = 0;
    m.transmission = 0.49f;  // below one half: opaque
    lobeAs<LambertLobe>(makeBsdf(m, none, flatPoint()));
}

TEST(MaterialMapping, DielectricBaseIsLambert) {
    std::vector<Texture> none;
    Material m = dielectricBase();
    for (float roughness : {0.0f, 0.01f, 0.5f, 1.0f}) {
        m.roughness = roughness;
        EXPECT_EQ(lobeAs<LambertLobe>(makeBsdf(m, none, flatPoint())).reflectance, m.baseColor);
    }
}

TEST(MaterialMapping, SmoothMetalIsMirror) {
    std::vector<Texture> none;
    Material m = dielectricBase();
    m.metallic = 1;
    m.roughness = 0;
    Bsdf b = makeBsdf(m, none, flatPoint());
    EXPECT_TRUE(b.isDelta());
    EXPECT_EQ(lobeAs<MirrorLobe>(b).tint, m.baseColor);
    // Mostly metallic: the mirror keeps its glTF weight.
    m.metallic = 0.7f;
    m.roughness = 0.015f;
    EXPECT_TRUE(
        nearlyEqual(lobeAs<MirrorLobe>(makeBsdf(m, none, flatPoint())).tint, m.baseColor * 0.7f));
    // Mostly dielectric and smooth: the diffuse part keeps its weight, never a Dirac+D mix.
    m.metallic = 0.3f;
    EXPECT_TRUE(nearlyEqual(lobeAs<LambertLobe>(makeBsdf(m, none, flatPoint())).reflectance,
                            m.baseColor * 0.7f));
}

TEST(MaterialMapping, RoughMetalIsConductorAndPartialMetalIsMix) {
    std::vector<Texture> none;
    Material m = dielectricBase();
    m.metallic = 1;
    m.roughness = 0.5f;
    auto c = lobeAs<ConductorLobe>(makeBsdf(m, none, flatPoint()));
    EXPECT_EQ(c.f0, m.baseColor);
    EXPECT_FLOAT_EQ(c.alpha, 0.25f);
    m.metallic = 0.4f;
    Bsdf b = makeBsdf(m, none, flatPoint());
    EXPECT_FALSE(b.isDelta());
    auto mix = lobeAs<DiffuseConductorMixLobe>(b);
    EXPECT_FLOAT_EQ(mix.metallic, 0.4f);
    EXPECT_EQ(mix.diffuse.reflectance, m.baseColor);
    EXPECT_EQ(mix.conductor.f0, m.baseColor);
    EXPECT_FLOAT_EQ(mix.conductor.alpha, 0.25f);
}

TEST(MaterialMapping, FrameAndNormalsComeFromSurfacePoint) {
    std::vector<Texture> none;
    SurfacePoint sp = flatPoint();
    Bsdf b = makeBsdf(dielectricBase(), none, sp);
    EXPECT_LT(length(b.frame().n - sp.ns), 1e-6f);
    EXPECT_EQ(b.geometricNormal(), sp.ng);
}

TEST(MaterialMapping, BaseColorTextureWithTransformAndTexCoord) {
    Rgb c00(1, 0, 0), c10(0, 1, 0), c01(0, 0, 1), c11(1, 1, 0);
    std::vector<Texture> tex = {checker(c00, c10, c01, c11)};
    Material m = dielectricBase();
    m.baseColor = Rgb(0.5f);
    m.baseColorTexture.texture = 0;
    SurfacePoint sp = flatPoint();  // uv0 = (0.25, 0.25) -> texel (0, 0); uv1 -> texel (1, 1)
    auto reflectance = [&](const SurfacePoint& p) {
        return lobeAs<LambertLobe>(makeBsdf(m, tex, p)).reflectance;
    };
    EXPECT_EQ(reflectance(sp), c00 * 0.5f);
    // TEXCOORD_1.
    m.baseColorTexture.texCoord = 1;
    EXPECT_EQ(reflectance(sp), c11 * 0.5f);
    // Named set absent on the mesh: fall back to TEXCOORD_0.
    SurfacePoint noUv1 = sp;
    noUv1.hasUv[1] = false;
    EXPECT_EQ(reflectance(noUv1), c00 * 0.5f);
    // KHR_texture_transform: offset moves (0.25, 0.25) to (0.75, 0.25) -> texel (1, 0).
    m.baseColorTexture.texCoord = 0;
    m.baseColorTexture.hasTransform = true;
    m.baseColorTexture.offset = Vec2f(0.5f, 0);
    EXPECT_EQ(reflectance(sp), c10 * 0.5f);
    // Rotation by 90 degrees: (x, y) -> (y, -x) + offset (0, 1): (0.25, 0.25) -> (0.25, 0.75),
    // texel (0, 1). Scale 3 on uv1 with texCoord 1: (0.75, 0.75) * 3 = (2.25, 2.25) -> repeat ->
    // texel (0, 0).
    m.baseColorTexture.offset = Vec2f(0, 1);
    m.baseColorTexture.rotation = kPi / 2;
    EXPECT_EQ(reflectance(sp), c01 * 0.5f);
    m.baseColorTexture.rotation = 0;
    m.baseColorTexture.offset = Vec2f(0, 0);
    m.baseColorTexture.scale = Vec2f(3, 3);
    m.baseColorTexture.texCoord = 1;
    EXPECT_EQ(reflectance(sp), c00 * 0.5f);
}

TEST(MaterialMapping, MetallicRoughnessAndTransmissionTextures) {
    // G = roughness, B = metallic; R of the transmission texture.
    std::vector<Texture> tex = {
        checker(Rgb(0.9f, 0.5f, 1.0f), Rgb(0.9f, 0.5f, 0.0f), Rgb(0, 0.01f, 1), Rgb(0, 1, 0.5f)),
        checker(Rgb(1, 0, 0), Rgb(0, 1, 1), Rgb(0, 0, 0), Rgb(1, 1, 1))};
    Material m = dielectricBase();
    m.metallic = 1;
    m.roughness = 0.6f;
    m.metallicRoughnessTexture.texture = 0;
    SurfacePoint sp = flatPoint();
    auto at = [&](Vec2f uv) {
        SurfacePoint p = sp;
        p.uv[0] = uv;
        return makeBsdf(m, tex, p);
    };
    // texel (0,0): roughness 0.6 * 0.5 = 0.3, metallic 1 -> Conductor alpha 0.09.
    EXPECT_FLOAT_EQ(lobeAs<ConductorLobe>(at({0.25f, 0.25f})).alpha, 0.09f);
    // texel (1,0): metallic 0 -> Lambert.
    lobeAs<LambertLobe>(at({0.75f, 0.25f}));
    // texel (0,1): roughness 0.006 < kSmooth, metallic 1 -> Mirror.
    lobeAs<MirrorLobe>(at({0.25f, 0.75f}));
    // texel (1,1): roughness 0.6, metallic 0.5 -> mix with m = 0.5.
    EXPECT_FLOAT_EQ(lobeAs<DiffuseConductorMixLobe>(at({0.75f, 0.75f})).metallic, 0.5f);
    // Transmission from texture 1's red channel, on TEXCOORD_1.
    m = dielectricBase();
    m.transmission = 1;
    m.transmissionTexture.texture = 1;
    m.transmissionTexture.texCoord = 1;
    auto atUv1 = [&](Vec2f uv1) {
        SurfacePoint p = sp;
        p.uv[1] = uv1;
        return makeBsdf(m, tex, p);
    };
    lobeAs<DielectricLobe>(atUv1({0.25f, 0.25f}));  // R = 1
    lobeAs<LambertLobe>(atUv1({0.75f, 0.25f}));     // R = 0
}

TEST(MaterialMapping, EmissionIsFactorTimesTextureTimesStrength) {
    std::vector<Texture> tex = {checker(Rgb(1, 0.5f, 0.25f), Rgb(0.0f), Rgb(0.0f), Rgb(0.5f))};
    Material m;
    EXPECT_EQ(evalEmission(m, tex, {Vec2f(0.25f, 0.25f), Vec2f(0.25f, 0.25f)}), Rgb(0.0f));
    m.emissiveFactor = Rgb(1.0f, 0.8f, 0.6f);
    m.emissiveStrength = 10;
    EXPECT_TRUE(nearlyEqual(evalEmission(m, tex, {Vec2f(0.25f, 0.25f), Vec2f(0, 0)}),
                            Rgb(10.0f, 8.0f, 6.0f)));
    m.emissiveTexture.texture = 0;
    EXPECT_TRUE(nearlyEqual(evalEmission(m, tex, {Vec2f(0.25f, 0.25f), Vec2f(0.75f, 0.75f)}),
                            Rgb(10.0f, 4.0f, 1.5f)));
    m.emissiveTexture.texCoord = 1;
    EXPECT_TRUE(nearlyEqual(evalEmission(m, tex, {Vec2f(0.25f, 0.25f), Vec2f(0.75f, 0.75f)}),
                            Rgb(5.0f, 4.0f, 3.0f)));
}
