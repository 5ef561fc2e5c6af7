// Bidirectional path tracing as an Algorithm ("bdpt", Veach 1997 ch. 10): per pixel sample one
// camera subpath and one light subpath, every strategy (s, t) that joins them (s = 0 emitter
// hits, s = 1 next-event estimation, t = 1 light tracing onto the film), combined with MIS.
//
// Determinism: every pixel sample draws from its own RNG stream (as pt), so the camera film does
// not depend on threads or passes. Light-tracing splats land anywhere, so each tile records its
// splats in sample order and they are added after the pass in (sample, tile) order: the image
// is bit-identical for any thread count and any split of the budget into passes.
#pragma once

#include <memory>

#include "algorithm.h"
#include "integrators/bdpt/bdpt_settings.h"

namespace partita {

class BdptAlgorithm : public Algorithm {
  public:
    explicit BdptAlgorithm(BdptSettings settings = {});
    ~BdptAlgorithm() override;
    RenderResult render(const RenderContext& ctx) override;
    Shardable* shardable() override;

  private:
    BdptSettings settings_;
    std::unique_ptr<Shardable> shards_;
};

void registerBdpt();

}  // namespace partita
