// A job as the store keeps it (a StoredJob row) and back: the one place a row read from disk
// becomes a job again. A row comes from a file another process may have damaged, so reading
// one never throws: a spec that does not parse fails the job when it runs, an unknown state
// reads as FAILED, bad text is escaped to UTF-8 and stats that are not a JSON object of
// numbers are dropped (tests/fuzz/fuzz_job_store_rows.cpp feeds it arbitrary rows).
#pragma once

#include <cstdint>

#include "job_store.h"
#include "proto.h"

namespace partita::server {

/// The row of `job`, the `sequence`-th submission.
StoredJob toStored(const pb::Job& job, int64_t sequence);

/// The job a row holds (see above: never throws).
pb::Job fromStored(const StoredJob& row);

}  // namespace partita::server
