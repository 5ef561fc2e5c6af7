#include "shard/chain_shards.h"

#include "mcmc/chain_runner.h"

namespace partita {

ChainPlan chainShardPlan(const ChainPlan& plan, uint32_t shard, uint32_t shards) {
    ChainPlan part;
    part.seed = plan.seed;
    part.bootstrapSamples = plan.bootstrapSamples;
    part.groups = plan.groups;
    const ShareRange range = shareRange(plan.chains.size(), shards, shard);
    part.chains.assign(plan.chains.begin() + long(range.first),
                       plan.chains.begin() + long(range.end));
    return part;
}

ShardWork chainShardWork(const ChainRunner& runner, const ChainPlan& plan) {
    ShardWork work;
    for (uint32_t g = 0; g < plan.groups.size(); ++g) {
        const Film& film = runner.film(g);
        work.films.emplace_back(film.width(), film.height());
        work.films.back().merge(film);
        work.counts.push_back(runner.mutationsDone(int(g)));
    }
    work.sums["rays"] = double(runner.rays());
    for (const auto& [name, m] : runner.mutationStats()) {
        work.sums["proposed_" + name] = double(m.proposed);
        work.sums["accepted_" + name] = double(m.accepted);
    }
    return work;
}

void addMergedChainStats(RenderStats& st, const ShardWork& merged, const ChainPlan& plan,
                         double pixels) {
    double done = 0;
    for (uint64_t n : merged.counts) done += double(n);
    st.values["chains"] = double(plan.chains.size());
    st.values["mutations"] = done;
    st.values["mpp"] = done / pixels;
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
