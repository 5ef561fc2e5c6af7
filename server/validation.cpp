#include "validation.h"

#include <google/protobuf/field_mask.pb.h>
#include <google/protobuf/util/field_mask_util.h>

#include <spdlog/fmt/fmt.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "algorithm.h"
#include "gltf/resource_resolver.h"
#include "parameter_wire.h"
#include "params/job_parameters.h"
#include "scene_environment.h"
#include "scene_source.h"
#include "text.h"

namespace partita::server {

namespace fs = std::filesystem;

namespace {

grpc::Status invalid(const std::string& message) {
    return {grpc::StatusCode::INVALID_ARGUMENT, message};
}
grpc::Status exhausted(const std::string& message) {
    return {grpc::StatusCode::RESOURCE_EXHAUSTED, message};
}

/// The shortest decimal that reads back as v: "65536", "1048576", "0.5" (never "1.04858e+06").
std::string num(double v) { return fmt::format("{}", v); }

std::string algorithmList() {
    std::string names;
    for (const auto& n : AlgorithmRegistry::instance().names())
        names += (names.empty() ? "" : ", ") + n;
    return names;
}

const char* budgetUnit(BudgetKind k) {
    switch (k) {
        case BudgetKind::SamplesPerPixel:
            return "samples per pixel";
        case BudgetKind::MutationsPerPixel:
            return "mutations per pixel";
        case BudgetKind::Seconds:
            return "seconds";
    }
    return "?";
}

grpc::Status checkScene(const pb::SceneSource& scene, const ServiceLimits& limits) {
    switch (scene.source_case()) {
        case pb::SceneSource::SOURCE_NOT_SET:
            return invalid(
                "the job names no scene: set scene.scene_name, scene.upload_id, scene.glb or "
                "scene.gltf");
        case pb::SceneSource::kSceneName:
            if (std::string why = SceneSource::checkName(scene.scene_name()); !why.empty())
                return invalid("invalid scene name: " + why);
            return grpc::Status::OK;
        case pb::SceneSource::kUploadId:
            return grpc::Status::OK;  // found, or NOT_FOUND, by the caller (upload_staging.h)
        case pb::SceneSource::kGlb:
            if (scene.glb().empty()) return invalid("the uploaded GLB is empty");
            break;
        case pb::SceneSource::kGltf: {
            if (scene.gltf().gltf().empty()) return invalid("the uploaded glTF is empty");
            std::set<std::string> seen;
            for (const auto& r : scene.gltf().resources())
                if (grpc::Status st = checkUploadedUri(r.uri(), seen); !st.ok()) return st;
            break;
        }
    }
    return checkUploadSize(SceneSource::uploadBytes(scene), limits);
}

}  // namespace

grpc::Status checkUploadedUri(const std::string& uri, std::set<std::string>& seen) {
    // A stored upload is a SceneSource, whose uri is a proto3 string: UTF-8 or unreadable.
    if (!isValidUtf8(uri))
        return invalid("uploaded resource '" + quoteInput(uri, 64) +
                       "' refused: its uri is not valid UTF-8");
    if (std::string why = checkRelativeUri(uri); !why.empty())
        return invalid("uploaded resource '" + printableUri(uri) + "' refused: " + why);
    if (!seen.insert(uri).second)
        return invalid("resource '" + printableUri(uri) + "' is uploaded twice");
    return grpc::Status::OK;
}

grpc::Status checkUploadSize(uint64_t bytes, const ServiceLimits& limits) {
    if (bytes <= uint64_t(limits.maxUploadBytes)) return grpc::Status::OK;
    return exhausted("the uploaded scene has " + std::to_string(bytes) +
                     " bytes, over this server's limit of " +
                     std::to_string(limits.maxUploadBytes) + " (--max-upload-mb)");
}

grpc::Status validateJobSpec(const pb::JobSpec& spec, const ServiceLimits& limits,
                             ValidatedSpec& out) {
    if (grpc::Status s = checkScene(spec.scene(), limits); !s.ok()) return s;
    return settingsFromSpec(spec, limits, out);
}

namespace {

/// The budget of `spec`: the algorithm's native unit with 16 per pixel when unset.
grpc::Status budgetFromSpec(const pb::JobSpec& spec, const AlgorithmRegistry::Entry& entry,
                            const ServiceLimits& limits, RenderSettings& s) {
    bool budgetSet = spec.has_budget() && !(spec.budget().kind() == pb::BUDGET_KIND_UNSPECIFIED &&
                                            spec.budget().amount() == 0);
    if (!budgetSet) {
        s.budgetKind = entry.nativeBudget;
        s.budget = 16;
        return grpc::Status::OK;
    }
    int kind = spec.budget().kind();
    if (!pb::BudgetKind_IsValid(kind))
        return invalid("unknown budget kind " + std::to_string(kind));
    switch (kind) {
        case pb::BUDGET_KIND_SAMPLES_PER_PIXEL:
            s.budgetKind = BudgetKind::SamplesPerPixel;
            break;
        case pb::BUDGET_KIND_MUTATIONS_PER_PIXEL:
            s.budgetKind = BudgetKind::MutationsPerPixel;
            break;
        case pb::BUDGET_KIND_SECONDS:
            s.budgetKind = BudgetKind::Seconds;
            break;
        default:
            return invalid(
                "budget kind is unspecified: set samples per pixel, mutations per pixel or "
                "seconds");
    }
    s.budget = spec.budget().amount();
    if (s.budgetKind != BudgetKind::Seconds && s.budgetKind != entry.nativeBudget)
        return invalid("algorithm '" + entry.name + "' takes its budget in " +
                       budgetUnit(entry.nativeBudget) + " or seconds, not " +
                       budgetUnit(s.budgetKind));
    if (!std::isfinite(s.budget) || s.budget <= 0)
        return invalid("the budget must be a positive number, got " + num(s.budget));
    if (s.budgetKind == BudgetKind::Seconds && s.budget > limits.maxSeconds)
        return exhausted("time budget " + num(s.budget) + " s exceeds this server's limit of " +
                         num(limits.maxSeconds) + " s");
    if (s.budgetKind != BudgetKind::Seconds && s.budget > limits.maxSamplesPerPixel)
        return exhausted("budget " + num(s.budget) + " " + budgetUnit(s.budgetKind) +
                         " exceeds this server's limit of " + num(limits.maxSamplesPerPixel));
    return grpc::Status::OK;
}

/// What this server refuses as too much (RESOURCE_EXHAUSTED) or as its own rule, once the
/// parameters are known to be well formed.
grpc::Status checkServerLimits(const pb::JobSpec& spec, const RenderSettings& s,
                               const ServiceLimits& limits) {
    if (s.width > limits.maxWidth || s.height > limits.maxHeight)
        return exhausted("resolution " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                         " exceeds this server's limit of " + std::to_string(limits.maxWidth) +
                         "x" + std::to_string(limits.maxHeight));
    if (s.maxDepth > limits.maxDepth)
        return exhausted("max_depth = " + std::to_string(s.maxDepth) +
                         " exceeds this server's limit of " + std::to_string(limits.maxDepth));
    if (const auto* b = s.parameters.find("bootstrap"))
        if (const auto* samples = std::get_if<uint64_t>(b);
            samples && *samples > limits.maxBootstrapSamples)
            return exhausted("bootstrap = " + std::to_string(*samples) +
                             " samples exceeds this server's limit of " +
                             std::to_string(limits.maxBootstrapSamples));
    double p = s.previewIntervalSeconds;
    if (p > 0 && p < 0.05)
        return invalid("preview_interval must be 0 (no previews) or at least 0.05 s, got " +
                       num(p));
    if (!s.environment.file.empty() && spec.scene().has_glb())
        return invalid(
            "an environment image goes with a .gltf upload (as one of its "
            "resources) or a named scene, not with a .glb");
    return grpc::Status::OK;
}

}  // namespace

grpc::Status settingsFromSpec(const pb::JobSpec& spec, const ServiceLimits& limits,
                              ValidatedSpec& out) {
    registerBuiltinAlgorithms();

    out.algorithm = spec.algorithm().empty() ? "pt" : spec.algorithm();
    const auto* entry = AlgorithmRegistry::instance().find(out.algorithm);
    if (!entry)
        return invalid("unknown algorithm '" + quoteInput(out.algorithm) +
                       "' (this server has: " + algorithmList() + ")");
    if (spec.label().size() > 1024) return invalid("the label is longer than 1024 characters");
    if (spec.scene_file().size() > 255)
        return invalid("the scene file name is longer than 255 characters");

    RenderSettings& s = out.settings;
    s = RenderSettings{};
    if (grpc::Status st = budgetFromSpec(spec, *entry, limits, s); !st.ok()) return st;
    ParameterValues given;
    if (std::string why = givenParameters(*entry, spec, given); !why.empty()) return invalid(why);
    if (std::string why = applyJobParameters(*entry, given, s); !why.empty()) return invalid(why);
    fillAlgorithmDefaults(*entry, s);
    if (grpc::Status st = checkServerLimits(spec, s, limits); !st.ok()) return st;
    if (std::string why = validateJob(*entry, s, limits.renderLimits()); !why.empty())
        return invalid(why);
    return grpc::Status::OK;
}

grpc::Status checkEnvironmentImage(const pb::JobSpec& spec, const SceneSource& scenes,
                                   const ServiceLimits& limits, ValidatedSpec& v) {
    return checkEnvironmentImage(
        [&](const std::string& file) {
            return spec.scene().has_scene_name()
                       ? scenes.readNamedResource(spec.scene().scene_name(), file,
                                                  uint64_t(limits.maxUploadBytes))
                       : SceneSource::readUploadedResource(spec.scene(), file);
        },
        v);
}

grpc::Status checkEnvironmentImage(
    const std::function<std::vector<uint8_t>(const std::string&)>& readResource, ValidatedSpec& v) {
    const std::string& file = v.settings.environment.file;
    if (file.empty()) return grpc::Status::OK;
    try {
        v.environment = readImageHeader(readResource(file), file);
    } catch (const std::exception&) {
        return grpc::Status::OK;  // the job fails when it runs, saying why
    }
    if (v.environment.pixels() > size_t(kMaxEnvironmentPixels))
        return invalid("the environment image '" + quoteInput(file) + "' is " +
                       std::to_string(v.environment.width) + " x " +
                       std::to_string(v.environment.height) +
                       " pixels, more than the 16384 x 8192 allowed");
    return grpc::Status::OK;
}

std::string sceneLabel(const pb::JobSpec& spec) {
    if (spec.scene().has_scene_name()) return spec.scene().scene_name();
    return spec.scene_file().empty() ? "upload" : spec.scene_file();
}

pb::JobSpec withoutSceneBytes(const pb::JobSpec& spec) {
    // Every field but the scene, without copying the scene's bytes (uploads can be large).
    static const google::protobuf::FieldMask allButScene = [] {
        google::protobuf::FieldMask mask;
        const auto* descriptor = pb::JobSpec::descriptor();
        for (int i = 0; i < descriptor->field_count(); ++i)
            if (descriptor->field(i)->number() != pb::JobSpec::kSceneFieldNumber)
                mask.add_paths(descriptor->field(i)->name());
        return mask;
    }();
    pb::JobSpec out;
    google::protobuf::util::FieldMaskUtil::MergeMessageTo(spec, allButScene, {}, &out);
    const pb::SceneSource& scene = spec.scene();
    pb::SceneSource* echo = out.mutable_scene();
    switch (scene.source_case()) {
        case pb::SceneSource::kSceneName:
            echo->set_scene_name(scene.scene_name());
            break;
        case pb::SceneSource::kGlb:
            echo->set_glb("");
            break;
        case pb::SceneSource::kGltf:
            for (const auto& r : scene.gltf().resources())
                echo->mutable_gltf()->add_resources()->set_uri(r.uri());
            echo->mutable_gltf();
            break;
        default:
            out.clear_scene();
            break;
    }
    return out;
}

}  // namespace partita::server
