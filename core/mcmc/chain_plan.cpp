#include "mcmc/chain_plan.h"

#include <stdexcept>

#include "byte_stream.h"

namespace partita {

namespace {

constexpr uint32_t kMagic = 0x50435450;  // "PTCP"
constexpr uint32_t kVersion = 3;         // 2: burn-in per chain; 3: type layers

}  // namespace

uint64_t ChainPlan::mutations(int group) const {
    uint64_t n = 0;
    for (const PlannedChain& c : chains)
        if (group < 0 || c.group == uint32_t(group)) n += c.mutations;
    return n;
}

std::vector<uint8_t> serializeChainPlan(const ChainPlan& plan) {
    ByteWriter w;
    w.putHeader(kMagic, kVersion);
    w.put(plan.seed);
    w.put(plan.bootstrapSamples);
    w.put(uint64_t(plan.groups.size()));
    for (const ChainGroup& g : plan.groups) {
        w.putString(g.label);
        w.put(g.b);
    }
    w.put(uint64_t(plan.chains.size()));
    for (const PlannedChain& c : plan.chains) {
        w.put(c.group);
        w.put(c.stream);
        w.put(c.mutations);
        w.put(c.burnIn);
        w.putBytes(c.start);
    }
    plan.layers.serialize(w);
    return w.bytes;
}

ChainPlan deserializeChainPlan(std::span<const uint8_t> bytes) {
    ByteReader r(bytes, "chain plan");
    r.expectHeader(kMagic, kVersion, "chain plan");
    ChainPlan plan;
    plan.seed = r.get<uint64_t>();
    plan.bootstrapSamples = r.get<uint64_t>();
    uint64_t groups = r.get<uint64_t>();
    for (uint64_t i = 0; i < groups; ++i) {
        std::string label = r.getString();
        plan.groups.push_back({std::move(label), r.get<double>()});
    }
    uint64_t chains = r.get<uint64_t>();
    for (uint64_t i = 0; i < chains; ++i) {
        PlannedChain c;
        c.group = r.get<uint32_t>();
        c.stream = r.get<uint64_t>();
        c.mutations = r.get<uint64_t>();
        c.burnIn = r.get<uint64_t>();
        c.start = r.getBytes();
        if (c.group >= plan.groups.size()) r.fail("bad group");
        plan.chains.push_back(std::move(c));
    }
    plan.layers = TypeLayers::deserialize(r);
    if (!r.atEnd()) r.fail("trailing bytes");
    return plan;
}

}  // namespace partita
