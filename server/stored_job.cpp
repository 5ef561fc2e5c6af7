#include "stored_job.h"

#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include "text.h"

namespace partita::server {

StoredJob toStored(const pb::Job& j, int64_t sequence) {
    StoredJob s;
    s.id = j.id();
    s.sequence = sequence;
    s.state = int(j.state());
    s.priority = j.spec().priority();
    s.label = j.spec().label();
    s.spec = j.spec().SerializeAsString();
    s.error = j.error();
    s.note = j.note();
    s.createdMs = j.created_unix_ms();
    s.startedMs = j.started_unix_ms();
    s.finishedMs = j.finished_unix_ms();
    nlohmann::json stats = nlohmann::json::object();
    for (const auto& [k, v] : j.stats()) stats[k] = v;
    s.stats = stats.dump();
    return s;
}

pb::Job fromStored(const StoredJob& s) {
    pb::Job j;
    j.set_id(s.id);
    if (!j.mutable_spec()->ParseFromString(s.spec))
        spdlog::error("[job {}] its stored spec is damaged; it will fail if it runs", s.id);
    j.set_state(pb::JobState_IsValid(s.state) ? pb::JobState(s.state) : pb::JOB_STATE_FAILED);
    // A store written before errors were made valid UTF-8 may hold raw bytes: escape them.
    j.set_error(toValidUtf8(s.error));
    j.set_note(toValidUtf8(s.note));
    j.set_created_unix_ms(s.createdMs);
    j.set_started_unix_ms(s.startedMs);
    j.set_finished_unix_ms(s.finishedMs);
    try {
        auto stats = nlohmann::json::parse(s.stats);
        for (const auto& [k, v] : stats.items())
            if (v.is_number()) (*j.mutable_stats())[k] = v.get<double>();
    } catch (const std::exception&) {
    }
    return j;
}

}  // namespace partita::server
