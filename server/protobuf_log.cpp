#include "protobuf_log.h"

#include <google/protobuf/stubs/logging.h>
#include <spdlog/spdlog.h>

#include "text.h"

namespace partita::server {

namespace {

void handler(google::protobuf::LogLevel level, const char* file, int line,
             const std::string& message) {
    // The messages may quote request bytes: keep the log line valid UTF-8 and short.
    std::string text = quoteInput(message, 500);
    switch (level) {
        case google::protobuf::LOGLEVEL_INFO:
            spdlog::debug("libprotobuf {}:{}: {}", file, line, text);
            break;
        case google::protobuf::LOGLEVEL_WARNING:
            spdlog::warn("libprotobuf {}:{}: {}", file, line, text);
            break;
        default:
            spdlog::error("libprotobuf {}:{}: {}", file, line, text);
            break;
    }
}

}  // namespace

void routeProtobufLogToSpdlog() { google::protobuf::SetLogHandler(&handler); }

}  // namespace partita::server
