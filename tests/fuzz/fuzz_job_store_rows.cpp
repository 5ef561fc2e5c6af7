// libFuzzer target for the job store's rows (server/stored_job.h): a row read back at start-up
// from a jobs.db that may be damaged becomes a job (fromStored), its stored spec is checked
// again (settingsFromSpec) and its memory estimated, as JobManager::recover does; the job is
// then stored again (toStored). None of it may throw or crash, whatever the row holds.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>

#include "job_memory.h"
#include "quiet_logs.h"
#include "stored_job.h"
#include "validation.h"

namespace ps = partita::server;

namespace {

ps::StoredJob rowFrom(FuzzedDataProvider& in) {
    ps::StoredJob row;
    row.id = in.ConsumeRandomLengthString(64);
    row.sequence = in.ConsumeIntegral<int64_t>();
    row.state = in.ConsumeIntegral<int>();
    row.priority = in.ConsumeIntegral<int>();
    row.label = in.ConsumeRandomLengthString(256);
    row.error = in.ConsumeRandomLengthString(256);
    row.note = in.ConsumeRandomLengthString(256);
    row.createdMs = in.ConsumeIntegral<int64_t>();
    row.startedMs = in.ConsumeIntegral<int64_t>();
    row.finishedMs = in.ConsumeIntegral<int64_t>();
    row.stats = in.ConsumeRandomLengthString(512);
    row.spec = in.ConsumeRemainingBytesAsString();  // last: protobuf bytes, mutated as such
    return row;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    partita::fuzz::quietLogs();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    FuzzedDataProvider in(data, size);
    const ps::StoredJob row = rowFrom(in);
    const ps::pb::Job job = ps::fromStored(row);
    static const ps::ServiceLimits limits;
    ps::ValidatedSpec v;
    if (ps::settingsFromSpec(job.spec(), limits, v).ok())
        (void)partita::server::estimateJobMemory(v.algorithm, v.settings, 1 << 20, 2,
                                                 v.environment);
    (void)ps::toStored(job, row.sequence);
    return 0;
}
