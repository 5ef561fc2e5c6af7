// Each of Veach's mutations on its own (mcmc/): a chain that mixes the mutation under test with
// an exact independence proposal (mcmc/independence_mutation.h) must converge to the BDPT
// reference, per path type and image region. The independence proposal alone is ergodic and exact,
// so a wrong T ratio in the mutation under test shows up as bias. The chains' images are compared
// as fractions of their total (the normalising constant b is the bootstrap's business, tested with
// `mlt` itself), with tolerances from the spread over independent seeds on both sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include "camera.h"
#include "film.h"
#include "gltf/gltf_loader.h"
#include "guide/gbuffer.h"
#include "guide/guided_perturbation.h"
#include "guide/image_guide.h"
#include "guide/offsets.h"
#include "mcmc/bidirectional_mutation.h"
#include "mcmc/caustic_perturbation.h"
#include "mcmc/independence_mutation.h"
#include "mcmc/lens_perturbation.h"
#include "mcmc/markov_chain.h"
#include "mcmc/multi_chain_perturbation.h"
#include "mcmc/path_edits.h"
#include "render_helpers.h"
#include "renderer.h"
#include "scene_builders.h"
#include "splat_buffer.h"
#include "thread_pool.h"

namespace partita {
namespace {

constexpr int kWidth = 16, kHeight = 12, kMaxDepth = 6;
constexpr int kSeeds = 12;
constexpr int kBlocksX = 4, kBlocksY = 3;
/// The mutation under test takes this share of the steps: the more it moves the chain, the more
/// a wrong ratio shows.
constexpr double kMutationShare = 0.8;

struct SceneUnderTest {
    RenderScene scene;
    Camera camera;
    explicit SceneUnderTest(SceneData data)
        : scene(std::move(data)), camera(resolveCamera(scene.data(), ""), kWidth, kHeight) {}
};

SceneData shippedScene(const std::string& name) {
    return loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/" + name + "/" + name + ".gltf");
}

/// A diffuse floor seen at a grazing angle under an area light: the raster-to-area Jacobian of
/// camera rays varies by orders of magnitude over the image, so a lens perturbation that forgot
/// it would be visibly biased.
SceneData grazingFloorScene() {
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(0.8f)),
                   test::lambertMaterial(Rgb(0.0f), Rgb(4.0f), false)};
    s.meshes.push_back(test::quad({-2, 0, -6}, {0, 0, 8}, {4, 0, 0}, 0));  // faces up
    s.meshes.push_back(test::quad({-1, 2, -4}, {2, 0, 0}, {0, 0, 4}, 1));  // faces down
    s.cameras.push_back(test::lookAtCamera({0, 0.4f, 1.8f}, {0, 0, -3}, 0.9f));
    return s;
}

/// The statistics compared: for each of the given types, its share of the image's luminance
/// in the whole image and in each of kBlocksX x kBlocksY blocks; then the share of every other
/// type.
std::vector<double> shares(const LayeredImage& image, const std::vector<std::string>& types) {
    double total = luminance(image.combined.mean()) * kWidth * kHeight;
    std::vector<double> out;
    double listed = 0;
    for (const std::string& name : types) {
        const Image* layer = image.layer(name);
        std::vector<double> blocks(kBlocksX * kBlocksY, 0.0);
        for (int y = 0; y < kHeight && layer; ++y)
            for (int x = 0; x < kWidth; ++x)
                blocks[size_t((y * kBlocksY / kHeight) * kBlocksX + x * kBlocksX / kWidth)] +=
                    luminance(layer->at(x, y));
        double whole = 0;
        for (double b : blocks) whole += b;
        listed += whole;
        out.push_back(whole / total);
        for (double b : blocks) out.push_back(b / total);
    }
    out.push_back(1 - listed / total);
    return out;
}

/// The reference: BDPT at independent seeds.
std::vector<std::vector<double>> bdptShares(const SceneUnderTest& s,
                                            const std::vector<std::string>& types) {
    std::vector<std::vector<double>> out;
    for (int seed = 0; seed < kSeeds; ++seed) {
        RenderSettings st;
        st.width = kWidth;
        st.height = kHeight;
        st.budget = 256;
        st.seed = 500 + uint64_t(seed);
        st.maxDepth = kMaxDepth;
        st.previewIntervalSeconds = 0;
        out.push_back(shares(test::renderWith(s.scene, "bdpt", st).image, types));
    }
    return out;
}

/// The image of `chains` chains mixing `mutation` with the independence proposal (`share` to the
/// mutation, the rest to the proposal; share 1: the mutation alone), each started from an
/// independent sample and burnt in, as unnormalised splats.
LayeredImage chainImage(const SceneUnderTest& s,
                        const std::function<std::unique_ptr<Mutation>()>& make, uint64_t seed,
                        std::map<std::string, MutationStats>& stats, double share) {
    const int chains = 16, burnIn = 200, steps = 3000;
    ThreadPool pool(2);
    std::vector<std::vector<std::tuple<Vec2f, PathType, Rgb>>> splats(chains);
    std::vector<std::vector<MutationStats>> chainStats(chains);
    std::vector<std::string> names;
    pool.parallelFor(chains, [&](size_t k) {
        IndependenceMutation independent(s.scene, s.camera, kMaxDepth);
        std::unique_ptr<Mutation> mutation = make();
        Rng rng(seed, 1000 + k);
        MarkovPath start;
        uint64_t rays = 0;
        while (!independent.sample(rng, start, rays)) {
        }
        MarkovChain chain({{mutation.get(), share}, {&independent, 1 - share}}, {}, start, rng);
        auto none = [](Vec2f, PathType, Rgb) {};
        for (int i = 0; i < burnIn; ++i) chain.step(none);
        auto keep = [&](Vec2f r, PathType t, Rgb v) { splats[k].emplace_back(r, t, v); };
        for (int i = 0; i < steps; ++i) chain.step(keep);
        chainStats[k] = chain.stats();
    });
    Film film(kWidth, kHeight);
    SplatBuffer buffer(kWidth, kHeight);
    for (const auto& chainSplats : splats) {
        for (const auto& [r, t, v] : chainSplats) buffer.addTent(r, t, v);
        buffer.flushInto(film);
    }
    std::string name = make()->name();
    for (const auto& st : chainStats) {
        stats[name].proposed += st[0].proposed;
        stats[name].accepted += st[0].accepted;
    }
    return film.resolve(1.0f, 64);
}

using MutationMaker = std::function<std::unique_ptr<Mutation>(const SceneUnderTest&)>;

/// The chain's shares against BDPT's, component by component: the largest ratio of a
/// difference to its tolerance (< 1: every component agrees), and where it is.
struct Comparison {
    double worst = 0;
    std::string where;
};

Comparison compareWithBdpt(SceneData data, const MutationMaker& make, uint64_t minimumAccepted,
                           double share = kMutationShare) {
    SceneUnderTest s(std::move(data));
    // The types compared: the six brightest of a BDPT image.
    RenderSettings st;
    st.width = kWidth;
    st.height = kHeight;
    st.budget = 256;
    st.maxDepth = kMaxDepth;
    st.previewIntervalSeconds = 0;
    LayeredImage probe = test::renderWith(s.scene, "bdpt", st).image;
    std::vector<std::string> types;
    for (const auto& layer : probe.layers)
        if (layer.name != Film::kOtherLayer && types.size() < 6) types.push_back(layer.name);
    std::vector<std::vector<double>> reference = bdptShares(s, types);
    std::vector<std::vector<double>> chains;
    std::map<std::string, MutationStats> stats;
    for (int seed = 0; seed < kSeeds; ++seed)
        chains.push_back(shares(chainImage(
                                    s, [&] { return make(s); }, 900 + uint64_t(seed), stats, share),
                                types));
    size_t components = reference[0].size();
    Comparison result;
    for (size_t c = 0; c < components; ++c) {
        std::vector<double> a, b;
        for (const auto& v : chains) a.push_back(v[c]);
        for (const auto& v : reference) b.push_back(v[c]);
        auto ma = test::meanAndError(a), mb = test::meanAndError(b);
        std::string what = c + 1 == components ? "other types"
                                               : types[c / (1 + kBlocksX * kBlocksY)] + " region " +
                                                     std::to_string(c % (1 + kBlocksX * kBlocksY));
        double ratio =
            std::abs(ma.mean - mb.mean) / test::twoSampleTolerance(ma, mb, int(components));
        if (ratio > result.worst) {
            std::ostringstream o;
            o << what << ": chain " << ma.mean << " +- " << ma.standardError << ", bdpt " << mb.mean
              << " +- " << mb.standardError << " (difference / tolerance " << ratio << ")";
            result = {ratio, o.str()};
        }
    }
    for (const auto& [name, m] : stats) {
        EXPECT_GE(m.accepted, minimumAccepted)
            << name << " was hardly used: the test proves nothing";
        std::printf("[ info     ] %s: %llu proposed, %llu accepted\n", name.c_str(),
                    (unsigned long long)m.proposed, (unsigned long long)m.accepted);
    }
    std::printf("[ info     ] worst component: %s\n", result.where.c_str());
    return result;
}

void expectConvergesToBdpt(const std::string& sceneName, const MutationMaker& make,
                           uint64_t minimumAccepted, double share = kMutationShare) {
    Comparison c = compareWithBdpt(shippedScene(sceneName), make, minimumAccepted, share);
    EXPECT_LT(c.worst, 1.0) << sceneName << ", worst component " << c.where;
}

/// The lens perturbation with T(y->x) / T(x->y) taken as 1 (the raster Jacobian forgotten).
class LensWithoutJacobian : public LensPerturbation {
  public:
    using LensPerturbation::LensPerturbation;
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& ratio,
                 uint64_t& rays) override {
        bool ok = LensPerturbation::propose(x, rng, y, ratio, rays);
        ratio = 1;
        return ok;
    }
};

TEST(Mutations, LensPerturbationConvergesOnAGrazingFloor) {
    Comparison c = compareWithBdpt(
        grazingFloorScene(),
        [](const SceneUnderTest& s) {
            return std::make_unique<LensPerturbation>(s.scene, s.camera,
                                                      PerturbationRange{0.1f, 1.6f});
        },
        10000);
    EXPECT_LT(c.worst, 1.0) << c.where;
}

/// The comparison is sensitive: the same chain with a wrong T ratio is caught.
TEST(Mutations, AWrongTRatioShowsAsBias) {
    Comparison c = compareWithBdpt(
        grazingFloorScene(),
        [](const SceneUnderTest& s) {
            return std::make_unique<LensWithoutJacobian>(s.scene, s.camera,
                                                         PerturbationRange{0.1f, 1.6f});
        },
        10000);
    EXPECT_GT(c.worst, 1.0) << "a lens perturbation without its Jacobian went unnoticed: "
                            << c.where;
}

TEST(Mutations, BidirectionalConvergesToBdptPerType) {
    expectConvergesToBdpt(
        "cornell-glass",
        [](const SceneUnderTest& s) {
            return std::make_unique<BidirectionalMutation>(s.scene, s.camera, kMaxDepth);
        },
        10000);
}

TEST(Mutations, LensPerturbationConvergesToBdptPerType) {
    expectConvergesToBdpt(
        "cornell-glass",
        [](const SceneUnderTest& s) {
            return std::make_unique<LensPerturbation>(s.scene, s.camera,
                                                      PerturbationRange{0.1f, 1.6f});
        },
        10000);
}

TEST(Mutations, CausticPerturbationConvergesToBdptPerType) {
    expectConvergesToBdpt(
        "cornell-glass",
        [](const SceneUnderTest& s) {
            return std::make_unique<CausticPerturbation>(s.scene, s.camera,
                                                         PerturbationRange{1e-4f, 0.1f});
        },
        1000);
}

TEST(Mutations, MultiChainPerturbationConvergesToBdptPerType) {
    expectConvergesToBdpt(
        "cornell-glass",
        [](const SceneUnderTest& s) {
            return std::make_unique<MultiChainPerturbation>(
                s.scene, s.camera, PerturbationRange{0.1f, 1.6f}, PerturbationRange{1e-4f, 0.1f});
        },
        1000);
}

/// The guided image perturbation with guides of its own: the scene's G-buffer and a V' that
/// is 1 on a checkerboard of 2 x 2 pixel cells and epsilon = 0.05 elsewhere, so that S' varies
/// twentyfold between neighbours and a wrong ratio would show. `forgetSums` drops Eq. 16's
/// ratio of candidate sums (the negative control).
class GuidedWithOwnGuides : public Mutation {
  public:
    GuidedWithOwnGuides(const SceneUnderTest& s, int candidates, float radius, bool forgetSums,
                        bool throughSpecular = true)
        : gbuffer_(gbufferOf(s)),
          masks_({checkerboard()}, kWidth, kHeight, 0.05f),
          guide_(gbuffer_, masks_, 0),
          delta_(guideOffsets(candidates, radius)),
          guided_(s.scene, s.camera, guide_, delta_, PerturbationRange{0.1f, 1.6f},
                  throughSpecular),
          forgetSums_(forgetSums) {}
    std::string name() const override { return "guided"; }
    bool appliesTo(const MarkovPath& x) const override { return guided_.appliesTo(x); }
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& ratio,
                 uint64_t& rays) override {
        bool ok = guided_.propose(x, rng, y, ratio, rays);
        if (ok && forgetSums_) ratio *= guided_.lastSumRatio();
        return ok;
    }

  private:
    static GBuffer gbufferOf(const SceneUnderTest& s) {
        RenderSettings st;
        st.width = kWidth;
        st.height = kHeight;
        st.maxDepth = kMaxDepth;
        ThreadPool pool(1);
        std::atomic<bool> cancel{false};
        RenderObserver observer;
        RenderContext ctx{s.scene, s.camera, st, pool, cancel, observer};
        return buildGBuffer(ctx);
    }
    static std::vector<float> checkerboard() {
        std::vector<float> d(size_t(kWidth * kHeight), 0.0f);
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                d[size_t(y * kWidth + x)] = ((x / 2 + y / 2) % 2) ? 1.0f : 0.0f;
        return d;
    }
    GBuffer gbuffer_;
    SupportMasks masks_;
    ImageGuide guide_;
    std::vector<PixelOffset> delta_;
    GuidedPerturbation guided_;
    bool forgetSums_;
};

TEST(Mutations, GuidedPerturbationConvergesToBdptPerType) {
    expectConvergesToBdpt(
        "cornell-glass",
        [](const SceneUnderTest& s) {
            return std::make_unique<GuidedWithOwnGuides>(s, 33, 5, false);
        },
        10000);
}

TEST(Mutations, GuidedPerturbationConvergesOnAGrazingFloor) {
    Comparison c = compareWithBdpt(
        grazingFloorScene(),
        [](const SceneUnderTest& s) {
            return std::make_unique<GuidedWithOwnGuides>(s, 128, 10, false);
        },
        10000);
    EXPECT_LT(c.worst, 1.0) << c.where;
}

TEST(Mutations, GuidedPerturbationLeavesPathsSeenThroughSpecularToTheLensPerturbation) {
    // throughSpecular false: a path E S+ D ... gets exactly the lens perturbation's proposal
    // (the same random numbers give the same path and ratio), a path E D ... the guided one
    // (never the lens's path: where either move proposes one, they differ).
    // Both moves keep s, so the per-path choice is the same from either end of a move, and each
    // class's kernel is exact on its own (the lens's and the guided's convergence tests).
    SceneUnderTest s(shippedScene("cornell-glass"));
    GuidedWithOwnGuides guided(s, 33, 5, false, /*throughSpecular=*/false);
    LensPerturbation lens(s.scene, s.camera, PerturbationRange{0.1f, 1.6f});
    IndependenceMutation independent(s.scene, s.camera, kMaxDepth);
    Rng pathRng(5, 1);
    int throughSpecular = 0, direct = 0;
    for (uint64_t i = 0; i < 20000 && (throughSpecular < 50 || direct < 50); ++i) {
        MarkovPath x;
        uint64_t rays = 0;
        if (!independent.sample(pathRng, x, rays) || !lens.appliesTo(x)) continue;
        const int first = firstNonDirac(x, 1);
        if (first == x.size() - 1) continue;  // E S* L: the lens perturbation either way
        Rng a(9, i), b(9, i);
        MarkovPath yGuided, yLens;
        double ratioGuided = 0, ratioLens = 0;
        const bool guidedOk = guided.propose(x, a, yGuided, ratioGuided, rays);
        const bool lensOk = lens.propose(x, b, yLens, ratioLens, rays);
        const bool same = guidedOk == lensOk && (!guidedOk || (yGuided.raster.x == yLens.raster.x &&
                                                               yGuided.raster.y == yLens.raster.y &&
                                                               ratioGuided == ratioLens));
        if (first > 1) {
            ++throughSpecular;
            EXPECT_TRUE(same) << "path " << i << ": s = " << first;
        } else if (guidedOk || lensOk) {  // both refused: nothing to compare
            ++direct;
            EXPECT_FALSE(same) << "path " << i << ": s = 1 got the lens perturbation's proposal";
        }
    }
    EXPECT_GE(throughSpecular, 50);
    EXPECT_GE(direct, 50);
}

/// The comparison catches a guided perturbation without Eq. 16's candidate sums.
TEST(Mutations, GuidedPerturbationWithoutTheCandidateSumsShowsAsBias) {
    Comparison c = compareWithBdpt(
        grazingFloorScene(),
        [](const SceneUnderTest& s) {
            return std::make_unique<GuidedWithOwnGuides>(s, 33, 5, true);
        },
        10000);
    EXPECT_GT(c.worst, 1.0) << "a guided perturbation without its candidate sums went unnoticed: "
                            << c.where;
}

/// The independence (large-step) mutation alone, mixed with nothing else (share 1): its fresh
/// paths and its ratio p(x) / p(y) alone must give BDPT's image per type and region.
TEST(Mutations, IndependenceMutationAloneConvergesToBdptPerType) {
    expectConvergesToBdpt(
        "cornell-glass",
        [](const SceneUnderTest& s) {
            return std::make_unique<IndependenceMutation>(s.scene, s.camera, kMaxDepth);
        },
        10000, /*share=*/1.0);
}

/// The independence mutation with the ratio p(x) / p(y) left out (T ratio 1): the chain then
/// samples f* p instead of f*, which the comparison catches.
class IndependenceWithoutDensityRatio : public IndependenceMutation {
  public:
    using IndependenceMutation::IndependenceMutation;
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& ratio,
                 uint64_t& rays) override {
        bool ok = IndependenceMutation::propose(x, rng, y, ratio, rays);
        ratio = 1;
        return ok;
    }
};

TEST(Mutations, IndependenceMutationWithoutItsDensityRatioShowsAsBias) {
    Comparison c = compareWithBdpt(
        shippedScene("cornell-glass"),
        [](const SceneUnderTest& s) {
            return std::make_unique<IndependenceWithoutDensityRatio>(s.scene, s.camera, kMaxDepth);
        },
        1000, /*share=*/1.0);
    EXPECT_GT(c.worst, 1.0) << "an independence mutation without p(x) / p(y) went unnoticed: "
                            << c.where;
}

TEST(MarkovChain, DeferredSplatsAddUpToTheSameSumsWithFewerSplats) {
    // Two chains of one start and RNG stream, one splatting every step (step) and one holding
    // the current state's weight back until it moves, an accepted proposal's weight joining it
    // (stepDeferred, then flush): they visit the same states, and per (raster position, type)
    // their splats sum to the same value, only rounded differently; the deferred chain splats
    // fewer times. A flush that lost a weight (or one splat too many) would show in the sums.
    SceneUnderTest s(shippedScene("cornell-glass"));
    BidirectionalMutation bidirectional(s.scene, s.camera, kMaxDepth);
    LensPerturbation lens(s.scene, s.camera, PerturbationRange{0.1f, 1.6f});
    IndependenceMutation independent(s.scene, s.camera, kMaxDepth);
    Rng startRng(77, 1);
    MarkovPath start;
    uint64_t rays = 0;
    while (!independent.sample(startRng, start, rays)) {
    }
    auto chainOf = [&] {
        return MarkovChain({{&bidirectional, 0.5}, {&lens, 0.5}, {&independent, 0.1, true}}, {},
                           start, Rng(77, 2));
    };
    using Key = std::tuple<float, float, uint64_t, int>;
    auto keyOf = [](Vec2f r, PathType t) {
        return Key{r.x, r.y, t.specularMask(), t.scatteringVertices()};
    };
    // Per key and channel: the sum of the splats, then the sum of their absolute values (the
    // scale of their float rounding).
    std::map<Key, std::array<double, 6>> every, deferred;
    size_t everyCount = 0, deferredCount = 0;
    auto into = [&](std::map<Key, std::array<double, 6>>& sums, size_t& count) {
        return [&sums, &count, &keyOf](Vec2f r, PathType t, Rgb v) {
            auto& sum = sums[keyOf(r, t)];
            for (size_t k = 0; k < 3; ++k) {
                sum[k] += double(v[int(k)]);
                sum[k + 3] += std::fabs(double(v[int(k)]));
            }
            ++count;
        };
    };
    MarkovChain a = chainOf(), b = chainOf();
    const int steps = 4000;
    int moves = 0;
    for (int i = 0; i < steps; ++i) {
        bool movedA = a.step(into(every, everyCount));
        bool movedB = b.stepDeferred(into(deferred, deferredCount));
        ASSERT_EQ(movedA, movedB) << "step " << i;
        moves += movedA;
        if (i == steps / 2) b.flush(into(deferred, deferredCount));  // a round's end
    }
    b.flush(into(deferred, deferredCount));
    EXPECT_EQ(a.state().raster.x, b.state().raster.x);
    EXPECT_EQ(a.state().raster.y, b.state().raster.y);
    EXPECT_GT(moves, steps / 10);
    // Step splats every proposal with a > 0 and the current state at every step that did not
    // accept for sure (at least every rejection); the deferred chain splats the rejected
    // proposals, and the current state once per move (and flush).
    EXPECT_LE(deferredCount, everyCount - size_t(steps - moves) + 2);
    EXPECT_LT(deferredCount, everyCount) << "the current state's weights were not held back";
    ASSERT_EQ(every.size(), deferred.size());
    // The two differ only in float rounding: each splat is f * float(weight / f*), two float
    // roundings of at most FLT_EPSILON / 2 each, so the sums of one key differ by at most
    // FLT_EPSILON times the absolute splats of both (a lost or doubled weight is a whole splat).
    for (const auto& [key, sum] : every) {
        const auto& other = deferred.at(key);
        for (size_t k = 0; k < 3; ++k)
            EXPECT_NEAR(other[k], sum[k], FLT_EPSILON * (sum[k + 3] + other[k + 3]));
    }
}

}  // namespace
}  // namespace partita
