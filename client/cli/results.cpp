#include "cli/results.h"

#include "file_io.h"

#include <system_error>

#include "cli/file_util.h"

namespace partita::cli {

namespace fs = std::filesystem;

std::string fetchResult(Connection& connection, const std::string& jobId,
                        partita::v1::ResultKind kind) {
    const char* what = kind == partita::v1::RESULT_KIND_EXR   ? "EXR"
                       : kind == partita::v1::RESULT_KIND_PNG ? "PNG"
                                                              : "metadata";
    grpc::ClientContext context;
    connection.prepare(context);
    partita::v1::FetchResultRequest request;
    request.set_job_id(jobId);
    request.set_kind(kind);
    auto reader = connection.stub().FetchResult(&context, request);
    std::string data;
    uint64_t total = 0;
    partita::v1::ResultChunk chunk;
    while (reader->Read(&chunk)) {
        total = chunk.total_size();
        if (chunk.offset() + chunk.data().size() > data.size())
            data.resize(chunk.offset() + chunk.data().size());
        data.replace(chunk.offset(), chunk.data().size(), chunk.data());
    }
    grpc::Status status = reader->Finish();
    if (!status.ok())
        connection.fail(status, std::string("fetch the ") + what + " of job " + jobId);
    if (total != 0 && data.size() != total)
        throw CliError(std::string("fetch the ") + what + " of job " + jobId + ": got " +
                       std::to_string(data.size()) + " of " + std::to_string(total) + " bytes");
    return data;
}

ResultFiles downloadResults(Connection& connection, const std::string& jobId,
                            const fs::path& exrPath) {
    ResultFiles files{exrPath, withExtension(exrPath, ".png"), withExtension(exrPath, ".json")};
    requireOutputFolder(files.exr);
    writeFileAtomically(files.exr, fetchResult(connection, jobId, partita::v1::RESULT_KIND_EXR));
    writeFileAtomically(files.png, fetchResult(connection, jobId, partita::v1::RESULT_KIND_PNG));
    writeFileAtomically(files.json,
                        fetchResult(connection, jobId, partita::v1::RESULT_KIND_METADATA));
    return files;
}

void requireOutputFolder(const fs::path& path) {
    try {
        partita::requireOutputFolder(path);
    } catch (const std::runtime_error& e) {
        throw CliError(e.what());
    }
}

}  // namespace partita::cli
