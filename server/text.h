// Text that reaches a protobuf `string` field or a log line. proto3 strings must be valid UTF-8
// (a receiver refuses to parse the whole message otherwise), and anything quoted from a request
// may be hostile: huge, binary, full of control characters.
#pragma once

#include <string>
#include <string_view>

namespace partita::server {

/// True when `s` is well-formed UTF-8 (no overlong forms, no surrogates, at most U+10FFFF).
bool isValidUtf8(std::string_view s);

/// `s` with every byte that is not part of a well-formed UTF-8 sequence written as "\xNN".
/// Valid UTF-8 comes back unchanged.
std::string toValidUtf8(std::string_view s);

/// Input for a message: valid UTF-8, control characters as "\xNN", at most `maxChars` bytes of
/// it followed by "... (N bytes)" when longer. Never quotes more than a short prefix.
std::string quoteInput(std::string_view s, size_t maxChars = 64);

}  // namespace partita::server
