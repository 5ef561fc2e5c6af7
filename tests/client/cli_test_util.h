// Helpers shared by the CLI tests.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "process.h"

namespace partita::test {

inline const std::string kCornell = std::string(PARTITA_SCENES_DIR) + "/cornell/cornell.gltf";
/// The tiny render every test uses: 32x24, 2 spp.
inline const std::vector<std::string> kTiny = {"--width", "32", "--height", "24", "--spp", "2"};

/// Runs the real partita binary.
inline RunResult partita(std::vector<std::string> args,
                         const std::map<std::string, std::string>& env = {}) {
    args.insert(args.begin(), PARTITA_CLI_PATH);
    return runProgram(args, env);
}

inline std::vector<std::string> concat(std::vector<std::string> a,
                                       const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

inline std::string readText(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline void writeText(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

inline std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
        if (!line.empty()) out.push_back(line);
    return out;
}

inline std::vector<std::string> words(const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    std::string w;
    while (in >> w) out.push_back(w);
    return out;
}

/// A failure: non-zero exit, exactly one line on stderr, "partita: error: ..." containing
/// `needle`.
inline void expectOneLineError(const RunResult& r, const std::string& needle) {
    EXPECT_NE(r.exitCode, 0) << r.describe();
    auto errLines = r.errLines();
    ASSERT_EQ(errLines.size(), 1u) << r.describe();
    EXPECT_EQ(errLines[0].rfind("partita: error: ", 0), 0u) << r.describe();
    EXPECT_NE(errLines[0].find(needle), std::string::npos) << "expected '" << needle << "'\n"
                                                           << r.describe();
}

}  // namespace partita::test
