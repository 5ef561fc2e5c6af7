#include "throwaway/throwaway_algorithm.h"

#include <mutex>

#include "algorithm.h"
#include "params/settings_table.h"

namespace partita::test {

namespace {

struct ConstantSettings {
    double strength = 1;  // the radiance of every pixel
};

const SettingsTable<ConstantSettings>& constantParameters() {
    static const SettingsTable<ConstantSettings> table = [] {
        SettingsTable<ConstantSettings> t;
        t.add(ParameterSpec("strength", "radiance of every pixel").within(0, 10),
              &ConstantSettings::strength);
        return t;
    }();
    return table;
}

class ConstantAlgorithm : public Algorithm {
  public:
    explicit ConstantAlgorithm(ConstantSettings settings) : settings_(settings) {}
    RenderResult render(const RenderContext& ctx) override {
        RenderResult r;
        r.image.combined = Image(ctx.settings.width, ctx.settings.height);
        for (float& v : r.image.combined.rgb) v = float(settings_.strength);
        r.stats.values["strength"] = settings_.strength;
        return r;
    }

  private:
    ConstantSettings settings_;
};

}  // namespace

void registerThrowawayAlgorithm() {
    static std::once_flag once;
    std::call_once(once, [] {
        registerBuiltinAlgorithms();
        AlgorithmRegistry::instance().add(algorithmEntry<ConstantAlgorithm>(
            "test-constant", "every pixel at --strength (a test's own algorithm)",
            BudgetKind::SamplesPerPixel, constantParameters()));
    });
}

}  // namespace partita::test
