#include "job_store.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "file_io.h"

namespace partita::server {

namespace fs = std::filesystem;

namespace {

/// One prepared statement, finalized on scope exit.
class Statement {
  public:
    Statement(sqlite3* db, const char* sql) : db_(db) {
        if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK)
            throw std::runtime_error(std::string("job store: ") + sqlite3_errmsg(db));
    }
    ~Statement() { sqlite3_finalize(stmt_); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;

    void bind(int i, const std::string& v) {
        sqlite3_bind_blob(stmt_, i, v.data(), int(v.size()), SQLITE_TRANSIENT);
    }
    void bindText(int i, const std::string& v) {
        sqlite3_bind_text(stmt_, i, v.data(), int(v.size()), SQLITE_TRANSIENT);
    }
    void bind(int i, int64_t v) { sqlite3_bind_int64(stmt_, i, v); }
    /// true while there is a row.
    bool step() {
        int rc = sqlite3_step(stmt_);
        if (rc == SQLITE_ROW) return true;
        if (rc == SQLITE_DONE) return false;
        throw std::runtime_error(std::string("job store: ") + sqlite3_errmsg(db_));
    }
    int64_t integer(int col) const { return sqlite3_column_int64(stmt_, col); }
    std::string blob(int col) const {
        const void* p = sqlite3_column_blob(stmt_, col);
        int n = sqlite3_column_bytes(stmt_, col);
        return p ? std::string(static_cast<const char*>(p), size_t(n)) : std::string();
    }

  private:
    sqlite3* db_;
    sqlite3_stmt* stmt_ = nullptr;
};

}  // namespace

bool isJobId(std::string_view id) {
    return id.size() == 12 && std::all_of(id.begin(), id.end(), [](char c) {
               return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
           });
}

fs::path JobStore::jobDir(const std::string& id) const {
    if (!isJobId(id)) throw std::invalid_argument("job store: '" + id + "' is not a job id");
    return dir_ / "jobs" / id;
}

namespace {

void bindJob(Statement& s, const StoredJob& j) {
    s.bindText(1, j.id);
    s.bind(2, j.sequence);
    s.bind(3, int64_t(j.state));
    s.bind(4, int64_t(j.priority));
    s.bindText(5, j.label);
    s.bind(6, j.spec);
    s.bindText(7, j.error);
    s.bind(8, j.createdMs);
    s.bind(9, j.startedMs);
    s.bind(10, j.finishedMs);
    s.bindText(11, j.stats);
    s.bindText(12, j.note);
}

/// The schema version this code writes (PRAGMA user_version). 1: the first; 2: jobs.note.
constexpr int64_t kSchemaVersion = 2;

int64_t nowMs() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace

JobStore::JobStore(const fs::path& dir) : dir_(dir) {
    std::error_code ec;
    fs::create_directories(dir_ / "jobs", ec);
    if (ec)
        throw std::runtime_error("cannot create job store '" + dir_.string() +
                                 "': " + ec.message());
    lockFd_ = ::open((dir_ / "lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lockFd_ < 0)
        throw std::runtime_error("cannot open '" + (dir_ / "lock").string() +
                                 "': " + std::strerror(errno));
    if (::flock(lockFd_, LOCK_EX | LOCK_NB) != 0) {
        ::close(lockFd_);
        throw std::runtime_error("job store '" + dir_.string() + "' is in use by another partitad");
    }
    fs::path dbPath = dir_ / "jobs.db";
    if (sqlite3_open_v2(dbPath.c_str(), &db_,
                        SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                        nullptr) != SQLITE_OK) {
        std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
        sqlite3_close(db_);
        ::close(lockFd_);
        throw std::runtime_error("cannot open job database '" + dbPath.string() + "': " + msg);
    }
    try {
        sqlite3_busy_timeout(db_, 5000);
        exec("PRAGMA journal_mode=WAL");
        // FULL: a committed transition survives a power cut too, not only a crash of partitad.
        exec("PRAGMA synchronous=FULL");
        exec("PRAGMA foreign_keys=ON");
        exec(R"sql(
            CREATE TABLE IF NOT EXISTS jobs(
              id TEXT PRIMARY KEY,
              seq INTEGER NOT NULL,
              state INTEGER NOT NULL,
              priority INTEGER NOT NULL DEFAULT 0,
              label TEXT NOT NULL DEFAULT '',
              spec BLOB NOT NULL,
              error TEXT NOT NULL DEFAULT '',
              created_ms INTEGER NOT NULL,
              started_ms INTEGER NOT NULL DEFAULT 0,
              finished_ms INTEGER NOT NULL DEFAULT 0,
              stats TEXT NOT NULL DEFAULT '{}',
              note TEXT NOT NULL DEFAULT '');
            CREATE TABLE IF NOT EXISTS transitions(
              id INTEGER PRIMARY KEY AUTOINCREMENT,
              job_id TEXT NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
              state INTEGER NOT NULL,
              at_ms INTEGER NOT NULL,
              error TEXT NOT NULL DEFAULT '',
              note TEXT NOT NULL DEFAULT '');
            CREATE INDEX IF NOT EXISTS transitions_job ON transitions(job_id);)sql");
        migrate();
        Statement s(db_, "SELECT COALESCE(MAX(seq), 0) FROM jobs");
        if (s.step()) nextSequence_ = s.integer(0) + 1;
    } catch (...) {
        sqlite3_close(db_);
        ::close(lockFd_);
        throw;
    }
}

JobStore::~JobStore() {
    sqlite3_close(db_);
    if (lockFd_ >= 0) ::close(lockFd_);
}

void JobStore::migrate() {
    int64_t version = 0;
    {
        Statement s(db_, "PRAGMA user_version");
        if (s.step()) version = s.integer(0);
    }
    // A newer schema only adds columns (with defaults); every statement here names its columns.
    if (version >= kSchemaVersion) return;
    // A store of an older partitad (or a new one, created above with every column): add what is
    // missing, in one transaction with the new version number.
    exec("BEGIN IMMEDIATE");
    try {
        bool hasNote = false;
        {
            Statement s(db_, "SELECT name FROM pragma_table_info('jobs')");
            while (s.step())
                if (s.blob(0) == "note") hasNote = true;
        }
        if (!hasNote) {
            exec("ALTER TABLE jobs ADD COLUMN note TEXT NOT NULL DEFAULT ''");
            spdlog::info("job store '{}': schema upgraded from version {} to {} (jobs.note)",
                         dir_.string(), version, kSchemaVersion);
        }
        exec(("PRAGMA user_version=" + std::to_string(kSchemaVersion)).c_str());
        exec("COMMIT");
    } catch (...) {
        sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
        throw;
    }
}

void JobStore::exec(const char* sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
        std::string msg = err ? err : "unknown error";
        sqlite3_free(err);
        throw std::runtime_error("job store: " + msg);
    }
}

std::vector<StoredJob> JobStore::loadAll() {
    std::lock_guard lock(mutex_);
    Statement s(db_,
                "SELECT id, seq, state, priority, label, spec, error, created_ms, started_ms, "
                "finished_ms, stats, note "
                "FROM jobs ORDER BY seq");
    std::vector<StoredJob> jobs;
    while (s.step()) {
        StoredJob j;
        j.id = s.blob(0);
        if (!isJobId(j.id)) {
            spdlog::error(
                "job store: skipping a row of jobs.db whose id is not a job id ({} bytes)",
                j.id.size());
            continue;
        }
        j.sequence = s.integer(1);
        j.state = int(s.integer(2));
        j.priority = int(s.integer(3));
        j.label = s.blob(4);
        j.spec = s.blob(5);
        j.error = s.blob(6);
        j.createdMs = s.integer(7);
        j.startedMs = s.integer(8);
        j.finishedMs = s.integer(9);
        j.stats = s.blob(10);
        j.note = s.blob(11);
        jobs.push_back(std::move(j));
    }
    return jobs;
}

int64_t JobStore::nextSequence() {
    std::lock_guard lock(mutex_);
    return nextSequence_++;
}

void JobStore::writeTransition(const StoredJob& j, const std::string& note) {
    Statement t(
        db_,
        "INSERT INTO transitions(job_id, state, at_ms, error, note) VALUES(?1, ?2, ?3, ?4, ?5)");
    t.bindText(1, j.id);
    t.bind(2, int64_t(j.state));
    t.bind(3, nowMs());
    t.bindText(4, j.error);
    t.bindText(5, note);
    t.step();
}

void JobStore::insert(const StoredJob& j, const std::string& note) {
    if (!isJobId(j.id)) throw std::invalid_argument("job store: '" + j.id + "' is not a job id");
    std::lock_guard lock(mutex_);
    exec("BEGIN IMMEDIATE");
    try {
        Statement s(db_,
                    "INSERT INTO jobs(id, seq, state, priority, label, spec, error, created_ms, "
                    "started_ms, finished_ms, stats, note) "
                    "VALUES(?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)");
        bindJob(s, j);
        s.step();
        writeTransition(j, note);
        exec("COMMIT");
    } catch (...) {
        sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
        throw;
    }
}

void JobStore::update(const StoredJob& j, const std::string& note) {
    std::lock_guard lock(mutex_);
    exec("BEGIN IMMEDIATE");
    try {
        Statement s(db_,
                    "UPDATE jobs SET seq=?2, state=?3, priority=?4, label=?5, spec=?6, error=?7, "
                    "created_ms=?8, started_ms=?9, finished_ms=?10, stats=?11, note=?12 "
                    "WHERE id=?1");
        bindJob(s, j);
        s.step();
        if (sqlite3_changes(db_) != 1) throw std::runtime_error("job store: no job " + j.id);
        writeTransition(j, note);
        exec("COMMIT");
    } catch (...) {
        sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
        throw;
    }
}

void JobStore::remove(const std::string& id) {
    {
        std::lock_guard lock(mutex_);
        Statement s(db_, "DELETE FROM jobs WHERE id=?1");
        s.bindText(1, id);
        s.step();
    }
    std::error_code ec;
    fs::remove_all(jobDir(id), ec);
    if (ec) spdlog::warn("[job {}] could not remove its folder: {}", id, ec.message());
}

std::vector<std::string> JobStore::transitions(const std::string& id) {
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT state, note FROM transitions WHERE job_id=?1 ORDER BY id");
    s.bindText(1, id);
    std::vector<std::string> out;
    while (s.step()) out.push_back(std::to_string(s.integer(0)) + " " + s.blob(1));
    return out;
}

void JobStore::removeOrphanFolders() {
    std::set<std::string> known;
    for (const auto& j : loadAll()) known.insert(j.id);
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir_ / "jobs", ec)) {
        std::string name = entry.path().filename().string();
        if (known.count(name)) continue;
        spdlog::info("job store: removing '{}', which belongs to no job", entry.path().string());
        std::error_code rec;
        fs::remove_all(entry.path(), rec);
    }
}

void JobStore::checkpoint() {
    std::lock_guard lock(mutex_);
    sqlite3_wal_checkpoint_v2(db_, nullptr, SQLITE_CHECKPOINT_TRUNCATE, nullptr, nullptr);
}

void JobStore::writeFileAtomic(const fs::path& path, std::string_view bytes) {
    partita::writeFileAtomic(path, {reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()});
}

}  // namespace partita::server
