#include "algorithm.h"

namespace partita {

AlgorithmRegistry& AlgorithmRegistry::instance() {
    static AlgorithmRegistry registry;
    return registry;
}

void AlgorithmRegistry::add(Entry entry) {
    std::string name = entry.name;
    entries_[name] = std::move(entry);
}

const AlgorithmRegistry::Entry* AlgorithmRegistry::find(const std::string& name) const {
    auto it = entries_.find(name);
    return it == entries_.end() ? nullptr : &it->second;
}

std::vector<std::string> AlgorithmRegistry::names() const {
    std::vector<std::string> out;
    for (const auto& [name, entry] : entries_) out.push_back(name);
    return out;
}

}  // namespace partita
