// The parameters of the chains' mutations that mlt, partitioned and guided all take, declared
// once: "large_step_rate", the independence mutation's rate (independence_mutation.h).
#pragma once

#include "mcmc/veach_mutations.h"
#include "params/settings_table.h"

namespace partita {

/// Declares "large_step_rate" on a settings struct S with a VeachMutationSettings `mutations`.
template <class S>
void addMutationParameters(SettingsTable<S>& t) {
    ParameterSpec spec = ParameterSpec("large_step_rate",
                                       "share of mutations that propose a fresh path (the "
                                       "independence mutation; 0: none)")
                             .within(0, 1);
    spec.type = detail::parameterTypeOf<double>();
    t.add(
        std::move(spec), [](const S& s) { return detail::valueOf(s.mutations.largeStepRate); },
        [](S& s, const ParameterValue& v) { detail::assign(s.mutations.largeStepRate, v); });
}

}  // namespace partita
