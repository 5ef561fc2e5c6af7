// The store's size as the store limit counts it (store_usage.h): a staged upload and the jobs
// that link it hold its bytes once on disk, so they count once.
#include "store_usage.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "temp_dir.h"

namespace partita::server {
namespace {

namespace fs = std::filesystem;

void writeBytes(const fs::path& path, size_t bytes) {
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << std::string(bytes, 'x');
}

TEST(StoreUsage, FilesCountByTheirBytesAndHardLinksCountOnce) {
    partita::test::TempDir store;
    writeBytes(store.path() / "uploads" / "u" / "upload.pb", 1000);
    writeBytes(store.path() / "jobs" / "a" / "result.exr", 300);
    EXPECT_EQ(folderBytes(store.path()), 1300u);
    for (const char* job : {"b", "c"}) {
        fs::create_directories(store.path() / "jobs" / job);
        fs::create_hard_link(store.path() / "uploads" / "u" / "upload.pb",
                             store.path() / "jobs" / job / "scene.upload");
    }
    EXPECT_EQ(folderBytes(store.path()), 1300u);
    fs::remove_all(store.path() / "uploads");  // the staged upload expires; its jobs keep it
    EXPECT_EQ(folderBytes(store.path()), 1300u);
    writeBytes(store.path() / "jobs" / "d" / "scene.upload", 50);
    EXPECT_EQ(folderBytes(store.path()), 1350u);
}

}  // namespace
}  // namespace partita::server
