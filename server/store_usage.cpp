#include "store_usage.h"

namespace partita::server {

namespace fs = std::filesystem;

uint64_t folderBytes(const fs::path& dir) {
    uint64_t total = 0;
    std::error_code ec;
    auto it =
        fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
    for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        std::error_code fileEc;
        if (it->is_regular_file(fileEc)) {
            uintmax_t size = it->file_size(fileEc);
            if (!fileEc) total += size;
        }
    }
    return total;
}

uint64_t defaultStoreLimit(const fs::path& path) {
    std::error_code ec;
    fs::path p = fs::absolute(path, ec);
    while (!p.empty() && !fs::exists(p, ec) && p != p.parent_path()) p = p.parent_path();
    fs::space_info space = fs::space(p, ec);
    return ec ? 0 : uint64_t(space.capacity / 2);
}

}  // namespace partita::server
