// libprotobuf prints its own errors ("[libprotobuf ERROR ...] String field ... contains invalid
// UTF-8 data") straight to stderr, untimed and unlike every other line of the daemon's log. This
// routes them through spdlog.
#pragma once

namespace partita::server {

void routeProtobufLogToSpdlog();

}  // namespace partita::server
