#include "shard/chain_shards.h"

#include <stdexcept>

#include "mcmc/chain_runner.h"
#include "progress_reporter.h"

namespace partita {

namespace {

/// A finished runner's work (its films moved out).
ShardWork chainShardWork(ChainRunner& runner, const ChainPlan& plan) {
    ShardWork work;
    for (uint32_t g = 0; g < plan.groups.size(); ++g) {
        work.films.push_back(runner.takeFilm(g));  // film g: see the runner's FilmLayout
        work.counts.push_back(runner.mutationsDone(int(g)));
    }
    work.sums["rays"] = double(runner.rays());
    work.sums["burn_in_steps"] = double(runner.burnInSteps());
    work.sums["stuck_chains"] = double(runner.stuckChains());
    work.sums["type_bound_chains"] = double(runner.typeBoundChains());
    for (const auto& [name, m] : runner.mutationStats()) {
        work.sums["proposed_" + name] = double(m.proposed);
        work.sums["accepted_" + name] = double(m.accepted);
    }
    return work;
}

}  // namespace

ChainPlan chainShardPlan(const ChainPlan& plan, uint32_t shard, uint32_t shards) {
    ChainPlan part;
    part.seed = plan.seed;
    part.bootstrapSamples = plan.bootstrapSamples;
    part.groups = plan.groups;
    part.layers = plan.layers;
    const ShareRange range = shareRange(plan.chains.size(), shards, shard);
    part.chains.assign(plan.chains.begin() + long(range.first),
                       plan.chains.begin() + long(range.end));
    return part;
}

void requireMutationBudget(const RenderContext& ctx, const std::string& algorithm) {
    if (ctx.settings.budgetKind != BudgetKind::MutationsPerPixel)
        throw std::invalid_argument("a sharded " + algorithm +
                                    " job needs a mutations-per-pixel budget (--mpp): a time "
                                    "budget is not reproducible across machines");
}

ShardWork runChainShard(const RenderContext& ctx, const ChainPlan& plan, uint32_t shard,
                        uint32_t shards, const ChainRunner::MutationFactory& mutations,
                        const ChainRunner::RestrictionFactory& restrictions,
                        uint64_t roundMutations, ChainRunner::FilmLayout layout) {
    const ChainPlan part = chainShardPlan(plan, shard, shards);
    ChainRunner runner(ctx, part, mutations, restrictions, roundMutations, layout);
    ProgressReporter progress(ctx.observer, "render", "mutations", double(part.mutations()));
    runner.run(progress, 0);
    progress.flush();
    ShardWork work = chainShardWork(runner, part);
    for (size_t g = 0; g < part.groups.size(); ++g)
        for (const auto& [name, m] : runner.mutationStats(int(g))) {
            const std::string key = "group_" + std::to_string(g) + "_";
            work.sums[key + "proposed"] += double(m.proposed);
            work.sums[key + "accepted"] += double(m.accepted);
        }
    for (size_t g = 0; g < part.groups.size(); ++g)
        work.sums["group_" + std::to_string(g) + "_stuck_chains"] =
            double(runner.stuckChains(int(g)));
    return work;
}

void addMergedChainStats(RenderStats& st, const ShardWork& merged, const ChainPlan& plan,
                         double pixels) {
    double done = 0;  // the groups' films (a film after them holds other work: samples)
    for (size_t g = 0; g < plan.groups.size() && g < merged.counts.size(); ++g)
        done += double(merged.counts[g]);
    st.values["chains"] = double(plan.chains.size());
    st.values["mutations"] = done;
    st.values["mpp"] = done / pixels;
    const auto burnIn = merged.sums.find("burn_in_steps");
    if (burnIn != merged.sums.end() && !plan.chains.empty())
        st.values["burn_in"] = burnIn->second / double(plan.chains.size());
    for (const auto& [name, value] : merged.sums) {
        st.values[name] = value;
        if (name.rfind("proposed_", 0) != 0) continue;
        const std::string mutation = name.substr(9);
        auto accepted = merged.sums.find("accepted_" + mutation);
        if (accepted != merged.sums.end())
            st.values["acceptance_" + mutation] = value > 0 ? accepted->second / value : 0;
    }
}

}  // namespace partita
