// The job store on disk:
//   <store>/jobs.db          SQLite (WAL): one row per job, plus a log of every state transition
//   <store>/jobs/<id>/       scene.upload (an uploaded scene, kept until the job is deleted),
//                            result.exr, preview.png, metadata.json (written when it finishes)
//   <store>/lock             held (flock) while a daemon uses the store
// Every state change is one transaction (job row + transition row); files are written to a
// temporary name in the same folder, flushed, then renamed, so a crash never leaves half a file
// under a final name. The store knows nothing of gRPC: specs are opaque serialized bytes.
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace partita::server {

/// Whether `id` has the form partitad gives job ids (12 lowercase hex digits): the only names
/// a job's folder may have. A row read back with any other id (a damaged or forged jobs.db:
/// "..", "../x") is skipped, so that no path is ever formed from it.
bool isJobId(std::string_view id);

struct StoredJob {
    std::string id;
    int64_t sequence = 0;
    int state = 0;  // partita.v1.JobState
    int priority = 0;
    std::string label;
    std::string spec;  // serialized partita.v1.JobSpec without scene bytes
    std::string error;
    std::string note;  // informational, e.g. why the job was re-queued (partita.v1.Job.note)
    int64_t createdMs = 0, startedMs = 0, finishedMs = 0;
    std::string stats;  // JSON object: name -> number
};

class JobStore {
  public:
    /// Opens (creating if needed) the store in `dir`. Throws std::runtime_error with one line
    /// when it cannot, or when another daemon holds it.
    explicit JobStore(const std::filesystem::path& dir);
    ~JobStore();
    JobStore(const JobStore&) = delete;
    JobStore& operator=(const JobStore&) = delete;

    const std::filesystem::path& dir() const { return dir_; }
    /// The job's folder. std::invalid_argument when `id` is not a job id (isJobId).
    std::filesystem::path jobDir(const std::string& id) const;

    /// Every job row, in submission order; rows whose id is not a job id are skipped (logged).
    std::vector<StoredJob> loadAll();
    /// The next submission sequence number (one more than any stored).
    int64_t nextSequence();

    void insert(const StoredJob& job, const std::string& note);
    /// Updates the job's row and logs the transition, in one transaction.
    void update(const StoredJob& job, const std::string& note);
    /// Deletes the job's rows and its folder.
    void remove(const std::string& id);
    /// The transitions logged for a job: "<state> <note>" lines, oldest first (for diagnostics).
    std::vector<std::string> transitions(const std::string& id);
    /// Removes job folders that have no row (a crash between writing files and inserting).
    void removeOrphanFolders();
    /// Folds the WAL into the database file (at shutdown).
    void checkpoint();

    /// Writes `bytes` to `path` atomically (temporary file, fsync, rename, fsync of the folder).
    static void writeFileAtomic(const std::filesystem::path& path, std::string_view bytes);

  private:
    void exec(const char* sql);
    /// Brings an existing store's schema up to this version (PRAGMA user_version): adds the
    /// columns an older partitad did not have.
    void migrate();
    void writeTransition(const StoredJob& job, const std::string& note);

    std::filesystem::path dir_;
    int lockFd_ = -1;
    sqlite3* db_ = nullptr;
    std::mutex mutex_;
    int64_t nextSequence_ = 1;
};

}  // namespace partita::server
