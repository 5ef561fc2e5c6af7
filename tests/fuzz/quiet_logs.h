// What the server's fuzz targets share at start-up: no logging. spdlog would print every refusal,
// and protobuf logs every invalid UTF-8 string it parses, which is expected here, and slow.
#pragma once

#include <google/protobuf/stubs/logging.h>
#include <spdlog/spdlog.h>

#include <string>

namespace partita::fuzz {

inline void quietLogs() {
    spdlog::set_level(spdlog::level::off);
    google::protobuf::SetLogHandler(
        [](google::protobuf::LogLevel, const char*, int, const std::string&) {});
}

}  // namespace partita::fuzz
