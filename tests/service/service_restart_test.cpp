// Jobs are never lost: SIGTERM re-queues the running job and exits 0; after SIGKILL the running
// job is re-queued at the next start; finished results stay fetchable and queued jobs run.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "in_process.h"
#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

const fs::path kScenes = PARTITA_SCENES_DIR;

/// A job of a few seconds here, deterministic (a sample budget): signals land while it renders.
pb::JobSpec restartJob() { return sceneSpec("cornell", 128, 96, 128, 9); }

void interruptAndResume(int signal) {
    TempDir store;
    std::string id;
    {
        Daemon first(store.path());
        ASSERT_TRUE(first.running());
        auto stub = first.stub();
        Submitted job = submit(*stub, restartJob());
        ASSERT_TRUE(job.status.ok());
        id = job.id;
        ASSERT_TRUE(waitForState(*stub, id, pb::JOB_STATE_RENDERING));
        std::this_thread::sleep_for(100ms);
        int code = first.stop(signal);
        if (signal == SIGTERM) {
            EXPECT_EQ(code, 0) << first.log();
            EXPECT_NE(first.log().find("re-queued"), std::string::npos) << first.log();
        } else {
            EXPECT_EQ(code, 128 + SIGKILL);
        }
    }
    Daemon second(store.path());
    ASSERT_TRUE(second.running());
    auto stub = second.stub();
    pb::Job end = waitForEnd(*stub, id);
    ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error() << "\n" << second.log();
    EXPECT_EQ(end.stats().at("requeued"), 1.0);
    if (signal == SIGKILL) {
        EXPECT_NE(second.log().find("re-queued after restart"), std::string::npos) << second.log();
    }
    // The re-queue is a note, never an error; the record keeps it after the job ran again.
    EXPECT_TRUE(end.error().empty()) << end.error();
    const std::string why = signal == SIGKILL
                                ? "re-queued after restart: partitad stopped while the job was "
                                : "re-queued: partitad stopped while the job was ";
    EXPECT_EQ(end.note().rfind(why, 0), 0u) << end.note();
    Fetched exr = fetch(*stub, id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok());
    LayeredImage result = readExrBytes(exr.bytes);
    EXPECT_EQ(result.combined.width, 128);
    if (signal == SIGKILL) {
        // It rendered again from scratch: the same image as in-process.
        EXPECT_EQ(compareImages(result, renderInProcess(kScenes / "cornell" / "cornell.gltf", 128,
                                                        96, 128, 9)),
                  "");
    }
}

TEST(ServiceRestart, SigtermRequeuesTheRunningJobWhichCompletesAfterRestart) {
    interruptAndResume(SIGTERM);
}

TEST(ServiceRestart, SigkillMidJobThenRestartRequeuesAndCompletesIt) {
    interruptAndResume(SIGKILL);
}

TEST(ServiceRestart, FinishedResultsStayAndQueuedJobsRunAfterRestart) {
    TempDir store;
    std::string done, running, queued, uploaded, cancelled;
    std::string doneExr;
    {
        Daemon first(store.path(), {"--max-jobs", "1"});
        ASSERT_TRUE(first.running());
        auto stub = first.stub();
        Submitted a = submit(*stub, sceneSpec("cornell", 24, 16, 2, 1));
        ASSERT_TRUE(a.status.ok());
        ASSERT_EQ(waitForEnd(*stub, a.id).state(), pb::JOB_STATE_DONE);
        done = a.id;
        doneExr = fetch(*stub, done, pb::RESULT_KIND_EXR).bytes;
        ASSERT_FALSE(doneExr.empty());

        Submitted b = submit(*stub, restartJob());
        ASSERT_TRUE(b.status.ok());
        running = b.id;
        ASSERT_TRUE(waitForState(*stub, running, pb::JOB_STATE_RENDERING));
        // Queued behind it: a named scene, an upload (its bytes must survive too), a cancelled one.
        Submitted c = submit(*stub, sceneSpec("cornell-glass", 24, 16, 2, 1));
        pb::JobSpec upload;
        upload.mutable_scene()->set_glb(makeGridGlb(16));
        upload.set_width(16);
        upload.set_height(16);
        Submitted d = submit(*stub, upload);
        Submitted e = submit(*stub, sceneSpec("cornell", 16, 16, 1, 1));
        ASSERT_TRUE(c.status.ok() && d.status.ok() && e.status.ok());
        queued = c.id;
        uploaded = d.id;
        cancelled = e.id;
        pb::CancelJobRequest cancel;
        cancel.set_job_id(cancelled);
        pb::Job ignored;
        auto ctx = context();
        ASSERT_TRUE(stub->CancelJob(ctx.get(), cancel, &ignored).ok());
        EXPECT_EQ(first.stop(SIGTERM), 0) << first.log();
    }
    Daemon second(store.path(), {"--max-jobs", "1"});
    ASSERT_TRUE(second.running());
    auto stub = second.stub();
    // The finished job: same state, same bytes, and a late watcher still gets its final frame.
    Fetched again = fetch(*stub, done, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(again.status.ok()) << again.status.error_message() << second.log();
    EXPECT_EQ(again.bytes, doneExr);
    WatchLog log = watch(*stub, done, true, true);
    ASSERT_TRUE(log.status.ok());
    ASSERT_EQ(log.frames().size(), 1u);
    EXPECT_TRUE(log.frames()[0]->final());
    EXPECT_EQ(compareImages(frameImage(*log.frames()[0]), readExrBytes(doneExr)), "");
    for (const auto& id : {running, queued, uploaded}) {
        pb::Job end = waitForEnd(*stub, id);
        EXPECT_EQ(end.state(), pb::JOB_STATE_DONE) << id << ": " << end.error();
    }
    EXPECT_EQ(waitForEnd(*stub, cancelled).state(), pb::JOB_STATE_CANCELLED);
}

std::string hex(const std::string& bytes) {
    std::string out;
    char buf[3];
    for (unsigned char c : bytes) {
        std::snprintf(buf, sizeof buf, "%02x", c);
        out += buf;
    }
    return out;
}

/// A store written by a partitad of schema version 1 (no jobs.note column), holding two jobs
/// that were RENDERING when it stopped: the store opens, its schema is upgraded, and both jobs
/// are re-queued with the note in `note` (seen while QUEUED: one waits behind the other) and run.
TEST(ServiceRestart, StoreOfAnOlderSchemaOpensAndRequeuesWithANote) {
    const char* python = "/usr/bin/python3";
    if (!fs::exists(python)) GTEST_SKIP() << "needs " << python << " (sqlite3 module)";
    TempDir store;
    fs::create_directories(store.path() / "jobs");
    pb::JobSpec first = restartJob();  // a few seconds: the second waits in the queue meanwhile
    first.set_priority(10);
    pb::JobSpec second = sceneSpec("cornell", 24, 16, 2, 1);
    std::ostringstream script;
    script << "import sqlite3\n"
           << "db = sqlite3.connect(r'''" << (store.path() / "jobs.db").string() << "''')\n"
           << R"py(db.executescript('''
CREATE TABLE jobs(id TEXT PRIMARY KEY, seq INTEGER NOT NULL, state INTEGER NOT NULL,
  priority INTEGER NOT NULL DEFAULT 0, label TEXT NOT NULL DEFAULT '', spec BLOB NOT NULL,
  error TEXT NOT NULL DEFAULT '', created_ms INTEGER NOT NULL,
  started_ms INTEGER NOT NULL DEFAULT 0, finished_ms INTEGER NOT NULL DEFAULT 0,
  stats TEXT NOT NULL DEFAULT '{}');
CREATE TABLE transitions(id INTEGER PRIMARY KEY AUTOINCREMENT,
  job_id TEXT NOT NULL REFERENCES jobs(id) ON DELETE CASCADE, state INTEGER NOT NULL,
  at_ms INTEGER NOT NULL, error TEXT NOT NULL DEFAULT '', note TEXT NOT NULL DEFAULT '');
CREATE INDEX transitions_job ON transitions(job_id);
PRAGMA user_version=1;''')
)py"
           << "rows = [('0000000000a1', 1, 10, bytes.fromhex('" << hex(first.SerializeAsString())
           << "')), ('0000000000b2', 2, 0, bytes.fromhex('" << hex(second.SerializeAsString())
           << R"py(')),]
for id, seq, prio, spec in rows:
    db.execute("INSERT INTO jobs(id, seq, state, priority, spec, created_ms, started_ms, stats) "
               "VALUES(?, ?, 4, ?, ?, 1000, 2000, '{}')", (id, seq, prio, spec))
db.commit()
db.close()
)py";
    writeFile(store.path() / "make_store.py", script.str());
    const std::string command =
        std::string(python) + " '" + (store.path() / "make_store.py").string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;

    Daemon daemon(store.path(), {"--max-jobs", "1"});
    ASSERT_TRUE(daemon.running()) << daemon.log();
    auto stub = daemon.stub();
    const std::string note =
        "re-queued after restart: partitad stopped while the job was RENDERING";
    {
        pb::GetJobRequest request;
        request.set_job_id("0000000000b2");
        pb::Job waiting;
        auto ctx = context();
        ASSERT_TRUE(stub->GetJob(ctx.get(), request, &waiting).ok());
        EXPECT_EQ(waiting.state(), pb::JOB_STATE_QUEUED);
        EXPECT_EQ(waiting.note(), note);
        EXPECT_TRUE(waiting.error().empty()) << waiting.error();
    }
    for (const std::string id : {"0000000000a1", "0000000000b2"}) {
        pb::Job end = waitForEnd(*stub, id);
        EXPECT_EQ(end.state(), pb::JOB_STATE_DONE) << id << ": " << end.error() << "\n"
                                                   << daemon.log();
        EXPECT_EQ(end.note(), note);
        EXPECT_TRUE(end.error().empty()) << end.error();
        EXPECT_EQ(end.stats().at("requeued"), 1.0);
    }
    EXPECT_NE(daemon.log().find("schema upgraded from version 1 to 2"), std::string::npos)
        << daemon.log();
    // Stopped and opened again: the upgraded store opens as it is, the notes kept.
    EXPECT_EQ(daemon.stop(SIGTERM), 0) << daemon.log();
    Daemon again(store.path());
    ASSERT_TRUE(again.running());
    auto stub2 = again.stub();
    EXPECT_EQ(waitForEnd(*stub2, "0000000000a1").note(), note);
    EXPECT_EQ(again.log().find("schema upgraded"), std::string::npos) << again.log();
}

/// A jobs.db row whose id is not a job id (a damaged or forged store: "..", "../../victim")
/// never names a path: the daemon skips the row with a log line, so deleting or fetching by
/// such an id is NOT_FOUND and neither the store itself nor a folder beside it is removed.
TEST(ServiceRestart, AStoredRowWhoseIdIsAPathIsSkippedAndNothingOutsideItsFolderIsTouched) {
    const char* python = "/usr/bin/python3";
    if (!fs::exists(python)) GTEST_SKIP() << "needs " << python << " (sqlite3 module)";
    TempDir root;
    const fs::path store = root.path() / "store", victim = root.path() / "victim" / "keep.txt";
    fs::create_directories(victim.parent_path());
    writeFile(victim, "not the store's");
    std::string id;
    {
        Daemon first(store);
        ASSERT_TRUE(first.running()) << first.log();
        auto stub = first.stub();
        Submitted job = submit(*stub, sceneSpec("cornell", 16, 12, 1, 1));
        ASSERT_TRUE(job.status.ok());
        id = job.id;
        ASSERT_EQ(waitForEnd(*stub, id).state(), pb::JOB_STATE_DONE);
        ASSERT_EQ(first.stop(SIGTERM), 0) << first.log();
    }
    // Copies of the finished job's row under ids that are paths.
    std::ostringstream script;
    script << "import sqlite3\n"
           << "db = sqlite3.connect(r'''" << (store / "jobs.db").string() << "''')\n"
           << "for n, bad in enumerate(['..', '../../victim']):\n"
           << "    db.execute('INSERT INTO jobs(id, seq, state, priority, label, spec, error, "
              "created_ms, started_ms, finished_ms, stats, note) SELECT ?, seq + 1 + ?, state, "
              "priority, label, spec, error, created_ms, started_ms, finished_ms, stats, note "
              "FROM jobs WHERE id = ?', (bad, n, '"
           << id << "'))\n"
           << "db.commit()\n";
    writeFile(root.path() / "forge.py", script.str());
    const std::string command =
        std::string(python) + " '" + (root.path() / "forge.py").string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;

    Daemon second(store);
    ASSERT_TRUE(second.running()) << second.log();
    auto stub = second.stub();
    pb::ListJobsResponse listed;
    {
        auto ctx = context();
        ASSERT_TRUE(stub->ListJobs(ctx.get(), pb::ListJobsRequest(), &listed).ok());
    }
    EXPECT_EQ(listed.jobs_size(), 1);
    EXPECT_EQ(listed.jobs(listed.jobs_size() - 1).id(), id);
    for (const std::string bad : {"..", "../../victim"}) {
        pb::DeleteJobRequest del;
        del.set_job_id(bad);
        pb::DeleteJobResponse deleted;
        auto ctx = context();
        EXPECT_EQ(stub->DeleteJob(ctx.get(), del, &deleted).error_code(),
                  grpc::StatusCode::NOT_FOUND)
            << bad;
        EXPECT_EQ(fetch(*stub, bad, pb::RESULT_KIND_EXR).status.error_code(),
                  grpc::StatusCode::NOT_FOUND)
            << bad;
    }
    EXPECT_TRUE(fs::exists(victim));
    EXPECT_TRUE(fs::exists(store / "jobs.db"));
    EXPECT_EQ(fetch(*stub, id, pb::RESULT_KIND_EXR).status.error_code(), grpc::StatusCode::OK);
    EXPECT_NE(second.log().find("whose id is not a job id"), std::string::npos) << second.log();
}

TEST(ServiceRestart, SigintAlsoStopsCleanlyAndRemovesThePortFile) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    EXPECT_EQ(daemon.stop(SIGINT), 0) << daemon.log();
    EXPECT_NE(daemon.log().find("stopped"), std::string::npos);
    // The same store opens again at once (the lock is released).
    Daemon again(store.path());
    EXPECT_TRUE(again.running());
}

TEST(ServiceRestart, SecondDaemonOnTheSameStoreIsRefused) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto [code, log] = runPartitad({"--listen", "127.0.0.1:0", "--store", store.path().string()});
    EXPECT_NE(code, 0);
    EXPECT_NE(log.find("in use by another partitad"), std::string::npos) << log;
}

}  // namespace
}  // namespace partita::test
