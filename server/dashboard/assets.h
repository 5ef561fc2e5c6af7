// The dashboard's pages, scripts and styles (server/dashboard/www), compiled into partitad by
// embed_assets.cmake: the daemon serves them from memory, never from the file system, so no
// request path can name a file.
#pragma once

#include <string_view>

namespace partita::server::dashboard {

struct Asset {
    std::string_view name;  // file name under www/, e.g. "job.js"
    std::string_view contentType;
    std::string_view body;
};

/// The asset of that file name, or null.
const Asset* findAsset(std::string_view name);

}  // namespace partita::server::dashboard
