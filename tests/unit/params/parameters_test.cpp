// The parameter table (params/): values read, written and checked by their declarations, the
// declarations bound to settings structs, and every declared parameter of every registered
// algorithm travelling unchanged through the text a CLI gives, the shard plan and the render's
// attributes.
#include <gtest/gtest.h>

#include <cmath>

#include "params/job_parameters.h"
#include "params/settings_table.h"
#include "renderer.h"
#include "shard/shard_files.h"

namespace partita {
namespace {

ParameterValue parsed(const ParameterSpec& spec, const std::string& text) {
    std::string error;
    std::optional<ParameterValue> v = parseParameter(spec, text, error);
    EXPECT_TRUE(v) << text << ": " << error;
    return v ? *v : ParameterValue{};
}

struct Toy {
    int count = 3;
    uint64_t seed = 7;
    float scale = 0.01f;
    double weight = 0.5;
    bool on = true;
    std::string mode = "fast";
    std::array<float, 3> tint{1, 0.5f, 0.25f};
};

const SettingsTable<Toy>& toyTable() {
    static const SettingsTable<Toy> t = [] {
        SettingsTable<Toy> table;
        table.add(ParameterSpec("count", "how many").within(0, 10), &Toy::count);
        table.add(ParameterSpec("seed", "a seed"), &Toy::seed);
        table.add(ParameterSpec("scale", "a float").above(0).atMost(1).withUnit("m"), &Toy::scale);
        table.add(ParameterSpec("weight", "a double").atLeast(0), &Toy::weight);
        table.add(ParameterSpec("on", "a switch"), &Toy::on);
        table.add(ParameterSpec("mode", "a choice").withChoices({"fast", "slow"}), &Toy::mode);
        table.add(ParameterSpec("tint", "a colour").within(0, 2), &Toy::tint);
        return table;
    }();
    return t;
}

TEST(Parameters, DeclarationsTakeTheirTypeAndDefaultFromTheField) {
    const auto& specs = toyTable().specs();
    ASSERT_EQ(specs.size(), 7u);
    EXPECT_EQ(specs[0].type, ParameterType::Int);
    EXPECT_EQ(std::get<int64_t>(specs[0].defaultValue), 3);
    EXPECT_EQ(specs[1].type, ParameterType::UInt);
    EXPECT_EQ(specs[2].type, ParameterType::Real);
    EXPECT_TRUE(specs[2].singlePrecision);
    EXPECT_EQ(formatParameter(specs[2], specs[2].defaultValue), "0.01") << "shortest float";
    EXPECT_FALSE(specs[3].singlePrecision);
    EXPECT_EQ(specs[4].type, ParameterType::Bool);
    EXPECT_EQ(specs[5].type, ParameterType::Choice);
    EXPECT_EQ(specs[6].type, ParameterType::Rgb);
    EXPECT_EQ(formatParameter(specs[6], specs[6].defaultValue), "1,0.5,0.25");
}

TEST(Parameters, TextReadsBackToTheSameValueForEveryType) {
    for (const auto& spec : toyTable().specs()) {
        ParameterValue v = spec.defaultValue;
        EXPECT_EQ(parsed(spec, formatParameter(spec, v)), v) << spec.name;
    }
    ParameterSpec seed = toyTable().specs()[1];
    EXPECT_EQ(parsed(seed, "18446744073709551615"),
              ParameterValue(uint64_t(18446744073709551615ull)));
    ParameterSpec weight = toyTable().specs()[3];
    double third = 1.0 / 3;
    EXPECT_EQ(parsed(weight, formatParameter(weight, third)), ParameterValue(third));
}

TEST(Parameters, ConversionsAreExactOrRefused) {
    const auto& s = toyTable().specs();
    std::string error;
    EXPECT_EQ(coerceParameter(s[0], 4.0, error), ParameterValue(int64_t(4)));
    EXPECT_FALSE(coerceParameter(s[0], 4.5, error));
    EXPECT_EQ(error, "count must be a whole number, got 4.5");
    EXPECT_FALSE(coerceParameter(s[1], int64_t(-1), error)) << "a negative seed";
    EXPECT_EQ(coerceParameter(s[3], int64_t(2), error), ParameterValue(2.0));
    EXPECT_EQ(coerceParameter(s[2], 0.1, error), ParameterValue(double(0.1f))) << "as the field";
    EXPECT_EQ(coerceParameter(s[0], std::string("5"), error), ParameterValue(int64_t(5)));
    EXPECT_FALSE(coerceParameter(s[4], int64_t(1), error)) << "a number is not a switch";
    EXPECT_FALSE(parseParameter(s[3], "nan", error));
    EXPECT_FALSE(parseParameter(s[3], " 1", error));
    EXPECT_FALSE(parseParameter(s[6], "1,2", error));
    EXPECT_FALSE(coerceParameter(s[2], 1e300, error));
}

TEST(Parameters, EachRuleHasOneMessage) {
    const auto& s = toyTable().specs();
    EXPECT_EQ(checkParameter(s[0], int64_t(11)), "count = 11 is outside [0, 10]");
    EXPECT_EQ(checkParameter(s[0], int64_t(10)), "");
    EXPECT_EQ(checkParameter(s[2], 0.0), "scale = 0 is outside (0, 1] m");
    EXPECT_EQ(checkParameter(s[3], -1.0), "weight = -1 must be >= 0");
    EXPECT_EQ(checkParameter(s[3], INFINITY), "weight must be a finite number");
    EXPECT_EQ(checkParameter(s[5], std::string("warp")), "mode 'warp' is not one of fast | slow");
    EXPECT_EQ(checkParameter(s[6], RgbValue{1, 3, 0}), "tint = 1,3,0 is outside [0, 2]");
    EXPECT_EQ(describeRange(s[1]), "any");
}

TEST(Parameters, ResolveAppliesGivenValuesOverTheDefaults) {
    ParameterValues given;
    given.set("count", 5).set("mode", "slow").set("tint", RgbValue{0, 0, 1});
    Toy t = toyTable().resolve(given);
    EXPECT_EQ(t.count, 5);
    EXPECT_EQ(t.mode, "slow");
    EXPECT_EQ(t.tint, (std::array<float, 3>{0, 0, 1}));
    EXPECT_EQ(t.scale, 0.01f) << "what is not given keeps its default";
    ASSERT_NE(toyTable().values(t).find("count"), nullptr);
    EXPECT_EQ(std::get<int64_t>(*toyTable().values(t).find("count")), 5);
    given.set("count", 11);
    try {
        toyTable().resolve(given);
        ADD_FAILURE() << "an out-of-range value resolves";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "count = 11 is outside [0, 10]");
    }
}

/// A valid value of `spec` other than its default (for an environment file, one with its
/// extension).
ParameterValue otherValue(const ParameterSpec& spec) {
    const ParameterValue& d = spec.defaultValue;
    switch (spec.type) {
        case ParameterType::Bool:
            return !std::get<bool>(d);
        case ParameterType::Int: {
            int64_t v = std::get<int64_t>(d) + 1;
            if (spec.max && double(v) > *spec.max) v -= 2;
            return v;
        }
        case ParameterType::UInt:
            return std::get<uint64_t>(d) > 1 ? std::get<uint64_t>(d) / 2 : uint64_t(12345);
        case ParameterType::Real: {
            double v = std::get<double>(d);
            double other = v != 0 ? v * 0.5 : 0.5;
            if (spec.singlePrecision) other = double(float(other));
            return other;
        }
        case ParameterType::Text:
            return spec.name == "environment" ? std::string("sky.exr") : std::string("top");
        case ParameterType::Choice:
            for (const auto& c : spec.choices)
                if (c != std::get<std::string>(d)) return c;
            return d;
        case ParameterType::Rgb:
            return RgbValue{0.5, 0.25, 1};
    }
    return d;
}

/// Settings of `algorithm` with every declared parameter at otherValue (an environment colour
/// rather than a file: not both).
RenderSettings everyParameterChanged(const AlgorithmRegistry::Entry& entry) {
    RenderSettings s;
    ParameterValues given;
    for (const ParameterSpec& spec : jobParameterSpecs(entry))
        if (spec.name != "environment") given.setValue(spec.name, otherValue(spec));
    EXPECT_EQ(applyJobParameters(entry, given, s), "") << entry.name;
    return s;
}

std::vector<std::pair<std::string, std::string>> asText(const AlgorithmRegistry::Entry& entry,
                                                        const RenderSettings& s) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const JobParameter& p : jobParameters(entry, s))
        out.emplace_back(p.spec->name, formatParameter(*p.spec, p.value));
    return out;
}

TEST(Parameters, EveryParameterOfEveryAlgorithmRoundTripsUnchanged) {
    registerBuiltinAlgorithms();
    for (const auto& name : AlgorithmRegistry::instance().names()) {
        const AlgorithmRegistry::Entry& entry = registeredAlgorithm(name);
        RenderSettings s = everyParameterChanged(entry);
        auto expected = asText(entry, s);
        // Every value differs from its default (else the round trip would prove nothing).
        for (const JobParameter& p : jobParameters(entry, s)) {
            if (p.spec->name == "environment") continue;
            EXPECT_NE(p.value, p.spec->defaultValue) << name << " " << p.spec->name;
        }

        // Through the text a command line gives.
        ParameterValues text;
        for (const auto& [param, value] : expected) text.set(param, value);
        RenderSettings fromText;
        ASSERT_EQ(applyJobParameters(entry, text, fromText), "") << name;
        EXPECT_EQ(asText(entry, fromText), expected) << name;

        // Through a shard plan.
        ShardPlan plan;
        plan.algorithm = name;
        plan.scene = "scene.gltf";
        plan.settings = s;
        ShardPlan back = deserializeShardPlan(serializeShardPlan(plan));
        EXPECT_EQ(asText(entry, back.settings), expected) << name;

        // Into the EXR attributes (partita:NAME).
        auto attributes = describeRender(name, s, {});
        for (const auto& [param, value] : expected)
            EXPECT_EQ(attributes["partita:" + param], value) << name << " " << param;
    }
}

TEST(Parameters, UnknownNamesAreRefusedNamingThemAndTheAlgorithmsParameters) {
    const AlgorithmRegistry::Entry& pt = registeredAlgorithm("pt");
    RenderSettings s;
    ParameterValues given;
    given.set("radius", 3);
    EXPECT_EQ(applyJobParameters(pt, given, s),
              "unknown parameter 'radius' for pt (its parameters: width, height, camera, seed, "
              "max_depth, layers, preview_interval, environment, environment_color, "
              "environment_rotation, target_error)");
    ParameterValues dashed;
    dashed.set("max-depth", "5");
    EXPECT_EQ(applyJobParameters(pt, dashed, s), "") << "'-' stands for '_'";
    EXPECT_EQ(s.maxDepth, 5);
    s.parameters.set("k", 3);
    EXPECT_NE(validateJob(pt, s).find("unknown parameter 'k' for pt"), std::string::npos);
    EXPECT_THROW(registeredAlgorithm("warp-drive"), std::invalid_argument);
}

TEST(Parameters, TheAlgorithmsSettingsResolveFromTheJobWithTheirDefaults) {
    // guided's K, |Y'| and R reach its settings through its one resolve function; what is not
    // given is the struct's default.
    const AlgorithmRegistry::Entry& guided = registeredAlgorithm("guided");
    ParameterValues given;
    given.set("k", 4).set("radius", "7.5");
    RenderSettings s;
    ASSERT_EQ(applyJobParameters(guided, given, s), "");
    std::unique_ptr<Algorithm> algorithm = guided.factory(s.parameters);
    ASSERT_TRUE(algorithm);
    RenderSettings complete = s;
    fillAlgorithmDefaults(guided, complete);
    EXPECT_EQ(std::get<int64_t>(*complete.parameters.find("k")), 4);
    EXPECT_EQ(std::get<double>(*complete.parameters.find("radius")), 7.5);
    EXPECT_EQ(std::get<int64_t>(*complete.parameters.find("y")), 128);
    EXPECT_EQ(std::get<uint64_t>(*complete.parameters.find("bootstrap")), 0u) << "by the rule";
    EXPECT_EQ(std::get<std::string>(*complete.parameters.find("prepass")), "bdpt");
}

}  // namespace
}  // namespace partita
