#include "render_settings.h"

#include <spdlog/fmt/fmt.h>
#include <algorithm>
#include <cmath>
#include <filesystem>

namespace partita {

namespace {

std::string environmentExtension(const ParameterValue& v) {
    const std::string& file = std::get<std::string>(v);
    if (file.empty()) return "";
    std::string ext = std::filesystem::path(file).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext == ".exr" || ext == ".hdr" ? "" : "environment must be an .exr or .hdr image";
}

SettingsTable<RenderSettings> makeSharedParameters() {
    using S = RenderSettings;
    SettingsTable<S> t;
    t.add(ParameterSpec("width", "image width").withUnit("pixels").atLeast(1), &S::width);
    t.add(ParameterSpec("height", "image height").withUnit("pixels").atLeast(1), &S::height);
    t.add(
        ParameterSpec("camera", "camera name (empty: the scene's first camera)").withMaxLength(256),
        &S::cameraName);
    t.add(ParameterSpec("seed", "random seed"), &S::seed);
    t.add(ParameterSpec("max_depth", "maximum scattering vertices per path")
              .withUnit("vertices")
              .atLeast(1),
          &S::maxDepth);
    t.add(ParameterSpec("layers",
                        "path types kept as layers of their own (the largest, chosen before the "
                        "render); the rest sum into 'other'")
              .within(0, 1024),
          &S::maxTypeLayers);
    t.add(ParameterSpec(
              "preview_interval",
              "seconds between preview frames (0: none); at least ten times what a frame costs")
              .withUnit("seconds")
              .atLeast(0),
          &S::previewIntervalSeconds);
    t.add(
        ParameterSpec("environment",
                      "equirectangular EXR/HDR lighting the scene from afar (+Y up, centre at -Z)")
            .withCheck(environmentExtension)
            .ofType(ParameterType::Text),
        [](const S& s) -> ParameterValue { return s.environment.file; },
        [](S& s, const ParameterValue& v) { s.environment.file = std::get<std::string>(v); });
    t.add(
        ParameterSpec("environment_color", "uniform environment radiance R,G,B")
            .within(0, 1e6)
            .ofType(ParameterType::Rgb, /*single=*/true),
        [](const S& s) -> ParameterValue {
            if (!s.environment.hasColor) return std::monostate{};
            const auto& c = s.environment.color;
            return RgbValue{c[0], c[1], c[2]};
        },
        [](S& s, const ParameterValue& v) {
            s.environment.hasColor = std::holds_alternative<RgbValue>(v);
            if (!s.environment.hasColor) return;
            const RgbValue& c = std::get<RgbValue>(v);
            s.environment.color = {float(c[0]), float(c[1]), float(c[2])};
        });
    t.add(
        ParameterSpec("environment_rotation", "turn the environment about +Y")
            .withUnit("degrees")
            .within(-360000, 360000)
            .ofType(ParameterType::Real, /*single=*/true),
        [](const S& s) -> ParameterValue { return double(s.environment.rotationDegrees); },
        [](S& s, const ParameterValue& v) {
            s.environment.rotationDegrees = float(std::get<double>(v));
        });
    return t;
}

/// The budget's rules; numbers as the shortest decimal that reads back ("2000000", not "2e+06").
std::string checkBudget(const RenderSettings& s, const RenderLimits& limits) {
    auto num = [](double v) { return fmt::format("{}", v); };
    if (!std::isfinite(s.budget) || s.budget <= 0)
        return "budget must be a positive number, got " + num(s.budget);
    if (s.budgetKind == BudgetKind::Seconds && s.budget > limits.maxSeconds)
        return "time budget " + num(s.budget) + " s exceeds the limit of " +
               num(limits.maxSeconds) + " s";
    if (s.budgetKind != BudgetKind::Seconds && s.budget > limits.maxSamplesPerPixel)
        return "budget " + num(s.budget) + " per pixel exceeds the limit of " +
               num(limits.maxSamplesPerPixel);
    if (s.budgetKind != BudgetKind::Seconds && s.budget != std::floor(s.budget))
        return "samples/mutations per pixel must be a whole number, got " + num(s.budget);
    return "";
}

}  // namespace

const char* budgetKindName(BudgetKind kind) {
    switch (kind) {
        case BudgetKind::SamplesPerPixel:
            return "spp";
        case BudgetKind::MutationsPerPixel:
            return "mpp";
        case BudgetKind::Seconds:
            return "seconds";
    }
    return "?";
}

const SettingsTable<RenderSettings>& sharedParameters() {
    static const SettingsTable<RenderSettings> table = makeSharedParameters();
    return table;
}

std::string validateSettings(const RenderSettings& s, const RenderLimits& limits) {
    for (const auto& e : sharedParameters().entries())
        if (std::string why = checkParameter(e.spec, e.get(s)); !why.empty()) return why;
    if (s.width > limits.maxWidth || s.height > limits.maxHeight)
        return "resolution " + std::to_string(s.width) + "x" + std::to_string(s.height) +
               " exceeds the limit of " + std::to_string(limits.maxWidth) + "x" +
               std::to_string(limits.maxHeight);
    if (s.maxDepth > limits.maxDepth)
        return "max_depth = " + std::to_string(s.maxDepth) + " exceeds the limit of " +
               std::to_string(limits.maxDepth);
    if (std::string why = checkBudget(s, limits); !why.empty()) return why;
    if (!s.environment.file.empty() && s.environment.hasColor)
        return "give an environment file or an environment colour, not both";
    return "";
}

}  // namespace partita
