#include "store_usage.h"

#include <sys/stat.h>

#include <algorithm>
#include <set>
#include <utility>

namespace partita::server {

namespace fs = std::filesystem;

uint64_t folderBytes(const fs::path& dir) {
    uint64_t total = 0;
    std::set<std::pair<dev_t, ino_t>> linked;  // files with several names count once
    std::error_code ec;
    auto it =
        fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
    for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        std::error_code fileEc;
        if (!it->is_regular_file(fileEc)) continue;
        struct stat st {};
        if (::lstat(it->path().c_str(), &st) != 0) continue;
        if (st.st_nlink > 1 && !linked.insert({st.st_dev, st.st_ino}).second) continue;
        total += uint64_t(st.st_size);
    }
    return total;
}

uint64_t defaultStoreLimit(const fs::path& path) {
    std::error_code ec;
    fs::path p = fs::absolute(path, ec);
    while (!p.empty() && !fs::exists(p, ec) && p != p.parent_path()) p = p.parent_path();
    fs::space_info space = fs::space(p, ec);
    if (ec) return 0;
    // Half the file system, but never more than the store could grow to now: what is free plus
    // what the store already holds (issue #25 7: half the capacity can exceed the free space).
    uint64_t reachable = uint64_t(space.available) + folderBytes(path);
    return std::min(uint64_t(space.capacity / 2), reachable);
}

}  // namespace partita::server
