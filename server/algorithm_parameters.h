// Which job parameters change what an algorithm renders, in the CLI's spelling. GetServerInfo
// advertises them so that a client can refuse a sweep over a parameter that the algorithm
// ignores (a grid of identical images). The core's registry does not carry this, so the table
// lives here, next to the contract; an algorithm missing from it advertises nothing (no check).
#pragma once

#include <string>
#include <vector>

namespace partita::server {

std::vector<std::string> algorithmParameters(const std::string& algorithm);

}  // namespace partita::server
