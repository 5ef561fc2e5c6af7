// An algorithm that exists only in the tests: "test-constant" renders every pixel at its one
// parameter, "strength". Registering it touches no file outside the tests, and the parameter
// must still reach the CLI's flags and help, the daemon's validation, the metadata, the EXR,
// the reference key, the shard plan and a sweep (cli_parameters_test.cpp).
#pragma once

namespace partita::test {

/// Adds "test-constant" to the registry (idempotent).
void registerThrowawayAlgorithm();

}  // namespace partita::test
