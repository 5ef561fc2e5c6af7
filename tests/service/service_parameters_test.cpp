// Declared parameters through the service (issue #21): every parameter of every algorithm the
// server lists travels by name, is stored with the job as it ran (defaults filled in) and so
// survives a restart unchanged, and lands in the metadata; older clients' typed fields reach
// the same parameters.
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <map>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

/// A cheap value other than the default for each declared parameter (floats exact in float).
/// A parameter added to a declaration needs a line here: the test says so.
const std::map<std::string, std::string>& cheapValues() {
    static const std::map<std::string, std::string> values = {
        {"width", "8"},
        {"height", "6"},
        {"seed", "5"},
        {"max_depth", "3"},
        {"layers", "4"},
        {"preview_interval", "0.5"},
        {"camera", ""},
        {"environment", ""},  // need a named camera and an image file
        {"environment_color", "0.5,0.25,1"},
        {"environment_rotation", "45"},
        {"target_error", "0.5"},
        {"k", "2"},
        {"prepass", "pt"},
        {"bootstrap", "2000"},
        {"chains", "8"},
        {"startup_share", "0.5"},
        {"burn_in", "16"},
        {"partitions", "classes"},
        {"estimators", "per-pixel"},
        {"pixel_estimator", "pt"},
        {"allocation", "neyman"},
        {"pilot_share", "0.1"},
        {"direct", "chains"},
        {"direct_spp", "4"},
        {"large_step_rate", "0.25"},
        {"y", "16"},
        {"radius", "10"},
        {"epsilon", "0.5"},
        {"move", "lens"},
        {"through_specular", "true"},
    };
    return values;
}

pb::JobSpec specOf(const pb::AlgorithmInfo& a) {
    pb::JobSpec spec = sceneSpec("cornell", 8, 6, 1);
    spec.clear_width();
    spec.clear_height();
    spec.clear_seed();
    spec.set_algorithm(a.name());
    spec.mutable_budget()->set_kind(a.native_budget());
    return spec;
}

pb::Job getJob(pb::Partita::Stub& stub, const std::string& id) {
    pb::GetJobRequest request;
    request.set_job_id(id);
    pb::Job job;
    auto ctx = context(10s);
    EXPECT_TRUE(stub.GetJob(ctx.get(), request, &job).ok());
    return job;
}

bool sameParameters(const pb::JobSpec& a, const pb::JobSpec& b) {
    if (a.parameters_size() != b.parameters_size()) return false;
    for (const auto& [name, value] : a.parameters()) {
        auto it = b.parameters().find(name);
        if (it == b.parameters().end() ||
            !google::protobuf::util::MessageDifferencer::Equals(value, it->second))
            return false;
    }
    return true;
}

/// The value as the metadata JSON writes it.
nlohmann::json jsonOf(const pb::ParameterValue& v) {
    switch (v.value_case()) {
        case pb::ParameterValue::kBoolValue:
            return v.bool_value();
        case pb::ParameterValue::kIntValue:
            return v.int_value();
        case pb::ParameterValue::kUintValue:
            return v.uint_value();
        case pb::ParameterValue::kRealValue:
            return v.real_value();
        case pb::ParameterValue::kTextValue:
            return v.text_value();
        case pb::ParameterValue::kRgbValue:
            return {v.rgb_value().r(), v.rgb_value().g(), v.rgb_value().b()};
        default:
            return nullptr;
    }
}

TEST(ServiceParameters, EveryParameterRoundTripsThroughTheWireTheStoreAndTheMetadata) {
    TempDir store;
    auto daemon = std::make_unique<Daemon>(store.path());
    ASSERT_TRUE(daemon->running());
    auto stub = daemon->stub();
    pb::ServerInfo info = serverInfo(*stub);
    ASSERT_GE(info.algorithms_size(), 5);

    std::map<std::string, pb::Job> submitted;  // by algorithm
    for (const pb::AlgorithmInfo& a : info.algorithms()) {
        pb::JobSpec spec = specOf(a);
        ASSERT_FALSE(a.parameter_info().empty()) << a.name();
        for (const pb::ParameterInfo& p : a.parameter_info()) {
            auto value = cheapValues().find(p.name());
            ASSERT_NE(value, cheapValues().end())
                << "give parameter '" << p.name() << "' a cheap value in this test";
            if (!value->second.empty())
                (*spec.mutable_parameters())[p.name()].set_text_value(value->second);
        }
        Submitted s = submit(*stub, spec);
        ASSERT_TRUE(s.status.ok()) << a.name() << ": " << s.status.error_message();
        submitted[a.name()] = getJob(*stub, s.id);
    }
    for (const auto& [algorithm, job] : submitted) {
        pb::Job end = waitForEnd(*stub, job.id(), 120s);
        EXPECT_EQ(end.state(), pb::JOB_STATE_DONE) << algorithm << ": " << end.error();
    }
    // Every declared parameter is stored, as given or as its default.
    for (const pb::AlgorithmInfo& a : info.algorithms()) {
        const pb::JobSpec& stored = submitted[a.name()].spec();
        for (const pb::ParameterInfo& p : a.parameter_info()) {
            bool hasDefault = p.has_default_value();
            bool given = !cheapValues().at(p.name()).empty();
            EXPECT_EQ(stored.parameters().count(p.name()), (given || hasDefault) ? 1u : 0u)
                << a.name() << " " << p.name();
        }
        EXPECT_EQ(stored.parameters().at("width").int_value(), 8) << a.name();
    }
    const pb::JobSpec& guided = submitted["guided"].spec();
    EXPECT_EQ(guided.parameters().at("radius").real_value(), 10.0);
    EXPECT_EQ(guided.parameters().at("epsilon").real_value(), 0.5);
    EXPECT_EQ(guided.parameters().at("y").int_value(), 16);
    EXPECT_EQ(guided.parameters().at("bootstrap").uint_value(), 2000u);
    EXPECT_EQ(guided.parameters().at("prepass").text_value(), "pt");
    EXPECT_EQ(guided.parameters().at("camera").text_value(), "") << "a default, filled in";

    // The metadata holds the same values.
    for (const auto& [algorithm, job] : submitted) {
        Fetched meta = fetch(*stub, job.id(), pb::RESULT_KIND_METADATA);
        ASSERT_TRUE(meta.status.ok()) << algorithm;
        auto params = nlohmann::json::parse(meta.bytes)["parameters"];
        for (const auto& [name, value] : job.spec().parameters())
            EXPECT_EQ(params[name], jsonOf(value)) << algorithm << " " << name;
    }

    // A restarted daemon reads the same values back from its store.
    ASSERT_EQ(daemon->stop(), 0);
    daemon = std::make_unique<Daemon>(store.path());
    ASSERT_TRUE(daemon->running());
    stub = daemon->stub();
    for (const auto& [algorithm, job] : submitted) {
        pb::Job again = getJob(*stub, job.id());
        EXPECT_TRUE(sameParameters(again.spec(), job.spec())) << algorithm;
    }
}

TEST(ServiceParameters, OlderClientsTypedFieldsReachTheSameParameters) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec typed = sceneSpec("cornell", 8, 6, 1, 5);
    typed.set_algorithm("guided");
    typed.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    typed.set_k(2);
    typed.set_y(16);
    typed.set_radius(10);
    typed.set_epsilon(0.5f);
    typed.set_prepass("pt");
    typed.set_bootstrap_samples(2000);
    typed.set_max_depth(3);
    typed.set_max_type_layers(4);
    pb::JobSpec named = sceneSpec("cornell", 8, 6, 1, 5);
    named.set_algorithm("guided");
    named.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    for (const auto& [name, value] : std::map<std::string, std::string>{{"k", "2"},
                                                                        {"y", "16"},
                                                                        {"radius", "10"},
                                                                        {"epsilon", "0.5"},
                                                                        {"prepass", "pt"},
                                                                        {"bootstrap", "2000"},
                                                                        {"max_depth", "3"},
                                                                        {"layers", "4"}})
        (*named.mutable_parameters())[name].set_text_value(value);
    Submitted a = submit(*stub, typed), b = submit(*stub, named);
    ASSERT_TRUE(a.status.ok()) << a.status.error_message();
    ASSERT_TRUE(b.status.ok()) << b.status.error_message();
    pb::Job ja = getJob(*stub, a.id), jb = getJob(*stub, b.id);
    EXPECT_TRUE(sameParameters(ja.spec(), jb.spec()));
    EXPECT_EQ(ja.spec().k(), 2) << "the typed fields are echoed as sent";
    EXPECT_EQ(waitForEnd(*stub, a.id, 120s).state(), pb::JOB_STATE_DONE);
    EXPECT_EQ(waitForEnd(*stub, b.id, 120s).state(), pb::JOB_STATE_DONE);
    Fetched ea = fetch(*stub, a.id, pb::RESULT_KIND_EXR),
            eb = fetch(*stub, b.id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(ea.status.ok() && eb.status.ok());
    auto pa = nlohmann::json::parse(fetch(*stub, a.id, pb::RESULT_KIND_METADATA).bytes);
    auto pb_ = nlohmann::json::parse(fetch(*stub, b.id, pb::RESULT_KIND_METADATA).bytes);
    EXPECT_EQ(pa["parameters"], pb_["parameters"]);
    EXPECT_EQ(pa["stats"]["guide_radius"], 10.0);
}

}  // namespace
}  // namespace partita::test
