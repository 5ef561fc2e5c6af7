#include "mcmc/chain_plan.h"

#include <cstring>
#include <stdexcept>

namespace partita {

namespace {

constexpr uint32_t kMagic = 0x50435450;  // "PTCP"
constexpr uint32_t kVersion = 2;         // 2: burn-in per chain

class Writer {
  public:
    template <typename T>
    void put(T value) {
        const auto* p = reinterpret_cast<const uint8_t*>(&value);
        bytes.insert(bytes.end(), p, p + sizeof value);
    }
    void putBytes(std::span<const uint8_t> b) {
        put(uint64_t(b.size()));
        bytes.insert(bytes.end(), b.begin(), b.end());
    }
    std::vector<uint8_t> bytes;
};

class Reader {
  public:
    explicit Reader(std::span<const uint8_t> b) : bytes_(b) {}
    template <typename T>
    T get() {
        need(sizeof(T));
        T value;
        std::memcpy(&value, bytes_.data() + at_, sizeof value);
        at_ += sizeof value;
        return value;
    }
    std::vector<uint8_t> getBytes() {
        uint64_t n = get<uint64_t>();
        need(n);
        std::vector<uint8_t> out(bytes_.begin() + long(at_), bytes_.begin() + long(at_ + n));
        at_ += n;
        return out;
    }
    bool atEnd() const { return at_ == bytes_.size(); }

  private:
    void need(uint64_t n) const {
        if (n > bytes_.size() - at_) throw std::invalid_argument("chain plan: truncated");
    }
    std::span<const uint8_t> bytes_;
    size_t at_ = 0;
};

}  // namespace

uint64_t ChainPlan::mutations(int group) const {
    uint64_t n = 0;
    for (const PlannedChain& c : chains)
        if (group < 0 || c.group == uint32_t(group)) n += c.mutations;
    return n;
}

std::vector<uint8_t> serializeChainPlan(const ChainPlan& plan) {
    Writer w;
    w.put(kMagic);
    w.put(kVersion);
    w.put(plan.seed);
    w.put(plan.bootstrapSamples);
    w.put(uint64_t(plan.groups.size()));
    for (const ChainGroup& g : plan.groups) {
        w.putBytes({reinterpret_cast<const uint8_t*>(g.label.data()), g.label.size()});
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
    return w.bytes;
}

ChainPlan deserializeChainPlan(std::span<const uint8_t> bytes) {
    Reader r(bytes);
    if (r.get<uint32_t>() != kMagic) throw std::invalid_argument("not a chain plan");
    if (uint32_t v = r.get<uint32_t>(); v != kVersion)
        throw std::invalid_argument("chain plan version " + std::to_string(v) + ", expected " +
                                    std::to_string(kVersion));
    ChainPlan plan;
    plan.seed = r.get<uint64_t>();
    plan.bootstrapSamples = r.get<uint64_t>();
    uint64_t groups = r.get<uint64_t>();
    for (uint64_t i = 0; i < groups; ++i) {
        std::vector<uint8_t> label = r.getBytes();
        plan.groups.push_back({std::string(label.begin(), label.end()), r.get<double>()});
    }
    uint64_t chains = r.get<uint64_t>();
    for (uint64_t i = 0; i < chains; ++i) {
        PlannedChain c;
        c.group = r.get<uint32_t>();
        c.stream = r.get<uint64_t>();
        c.mutations = r.get<uint64_t>();
        c.burnIn = r.get<uint64_t>();
        c.start = r.getBytes();
        if (c.group >= plan.groups.size()) throw std::invalid_argument("chain plan: bad group");
        plan.chains.push_back(std::move(c));
    }
    if (!r.atEnd()) throw std::invalid_argument("chain plan: trailing bytes");
    return plan;
}

uint64_t chainShare(uint64_t total, uint64_t chains, uint64_t k) {
    return total / chains + (k < total % chains ? 1 : 0);
}

}  // namespace partita
