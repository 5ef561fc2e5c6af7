#include "mcmc/veach_mutations.h"

#include <algorithm>

#include "camera.h"
#include "mcmc/caustic_perturbation.h"
#include "mcmc/independence_mutation.h"
#include "mcmc/lens_perturbation.h"
#include "mcmc/multi_chain_perturbation.h"

namespace partita {

PerturbationRange lensPixelRange(const Camera& camera, const VeachMutationSettings& s) {
    float largest = s.lensLargestFraction * float(std::max(camera.width(), camera.height()));
    return {s.lensSmallestPixels, std::max(largest, 2 * s.lensSmallestPixels)};
}

MutationSet makeVeachMutations(const RenderScene& scene, const Camera& camera, int maxDepth,
                               const VeachMutationSettings& s, std::unique_ptr<Mutation> lens) {
    PerturbationRange pixels = lensPixelRange(camera, s);
    if (!lens) lens = std::make_unique<LensPerturbation>(scene, camera, pixels);
    MutationSet set;
    set.add(std::make_unique<BidirectionalMutation>(scene, camera, maxDepth, s.bidirectional),
            s.bidirectionalWeight);
    set.add(std::move(lens), s.lensWeight);
    set.add(std::make_unique<CausticPerturbation>(scene, camera, s.causticAngles), s.causticWeight);
    set.add(std::make_unique<MultiChainPerturbation>(scene, camera, pixels, s.multiChainAngles),
            s.multiChainWeight);
    // Only when used: with a rate of 0 the chains are those from before it existed, bit for bit.
    if (s.largeStepRate > 0)
        set.add(std::make_unique<IndependenceMutation>(scene, camera, maxDepth,
                                                       s.independenceVertexCounts),
                s.largeStepRate, /*fixedRate=*/true);
    return set;
}

}  // namespace partita
