#include "mcmc/chain_error_monitor.h"

#include <algorithm>

#include "mcmc/chain_runner.h"
#include "progress_reporter.h"

namespace partita {

ChainErrorMonitor::ChainErrorMonitor(const RenderSettings& settings, double targetError,
                                     Estimator estimator)
    : targetError_(targetError),
      everyRound_(targetError > 0 && settings.budgetKind != BudgetKind::Seconds),
      minMutations_(kMinMutationsPerPixel * double(settings.width) * double(settings.height)),
      estimator_(std::move(estimator)) {}

void ChainErrorMonitor::Estimate::publish(ProgressReporter& progress) const {
    std::map<std::string, double> values = parts;
    if (combined >= 0) values["error_estimate"] = combined;
    if (!values.empty()) progress.mergeValues(values);
}

bool ChainErrorMonitor::due() const {
    // Every round until the first estimate (the halves need mutations in both).
    if (everyRound_ || latest_.combined < 0) return true;
    return schedule_.due();
}

void ChainErrorMonitor::estimateNow() {
    auto begin = Clock::now();
    latest_ = estimator_();
    schedule_.ran(begin);
}

void ChainErrorMonitor::afterRound(ChainRunner& runner, ProgressReporter& progress) {
    if (due()) {
        estimateNow();
        reachedTarget_ = targetError_ > 0 && latest_.forTarget() >= 0 &&
                         latest_.forTarget() <= targetError_ &&
                         double(runner.mutationsDone()) >= minMutations_;
        if (reachedTarget_) runner.requestStop();
    }
    // The runner replaces the phase's values every round: these go in again each time.
    if (latest_.combined < 0) return;
    latest_.publish(progress);
}

void ChainErrorMonitor::addStats(RenderStats& st) const {
    if (latest_.combined >= 0) {
        st.values["error_estimate"] = latest_.combined;
        for (const auto& [name, value] : latest_.parts) st.values[name] = value;
    }
    if (targetError_ > 0) st.values["reached_target_error"] = reachedTarget_ ? 1 : 0;
}

}  // namespace partita
