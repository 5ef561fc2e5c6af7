// partita [--server HOST:PORT] jobs [--label L]
// A table of the server's jobs: id, state, algorithm, scene, label, progress.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/job_format.h"
#include "cli/table.h"

namespace partita::cli {

namespace {

std::string sceneText(const partita::v1::JobSpec& spec) {
    switch (spec.scene().source_case()) {
        case partita::v1::SceneSource::kSceneName:
            return spec.scene().scene_name();
        case partita::v1::SceneSource::kGlb:
        case partita::v1::SceneSource::kGltf:
            return spec.scene_file().empty() ? "upload" : spec.scene_file();
        default:
            return "-";
    }
}

int runJobs(const GlobalOptions& global, const std::string& label) {
    Session session(global);
    partita::v1::ListJobsRequest request;
    request.set_label(label);
    partita::v1::ListJobsResponse response =
        session.connection().call(&Connection::Stub::ListJobs, request, "list jobs");
    Table table({"ID", "STATE", "ALGORITHM", "SCENE", "LABEL", "PROGRESS"});
    for (const auto& job : response.jobs())
        table.addRow({job.id(), stateName(job.state()), job.spec().algorithm(),
                      sceneText(job.spec()), job.spec().label(), progressText(job)});
    table.print(stdout);
    return 0;
}

}  // namespace

Command addJobsCommand(CLI::App& app, const GlobalOptions& global) {
    auto label = std::make_shared<std::string>();
    CLI::App* sub = app.add_subcommand("jobs", "list the server's jobs");
    sub->add_option("--label", *label, "only jobs with this label");
    return {sub, [&global, label] { return runJobs(global, *label); }};
}

}  // namespace partita::cli
