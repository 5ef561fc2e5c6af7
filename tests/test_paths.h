// Where the tests find the repository and the programs they start. The paths are compiled into
// one small generated file per test executable (tests/test_paths.cmake) and this header is
// force-included into every test source, instead of -D definitions on every test's command line:
// ccache keys on the command line, so with absolute paths there no test object of one clone
// (this one) could be reused in another (CI's clean clone), and every test was compiled again.
// The macros keep the names the tests have always used; each is a call that returns the path.
#pragma once

namespace partita::test_paths {
const char* scenes();             // <repository>/scenes
const char* source();             // <repository>
const char* partitaLocal();       // the partita-local binary
const char* partitad();           // the partitad binary
const char* partitadThrowaway();  // partitad with the tests' own algorithm (tests/client)
const char* cli();                // the partita CLI
const char* probe();              // partita-health-probe
const char* slurmCluster();       // tests/slurm/slurm_cluster.sh
}  // namespace partita::test_paths

#define PARTITA_SCENES_DIR (::partita::test_paths::scenes())
#define PARTITA_SOURCE_DIR (::partita::test_paths::source())
#define PARTITA_LOCAL_BIN (::partita::test_paths::partitaLocal())
#define PARTITA_LOCAL_PATH (::partita::test_paths::partitaLocal())
#define PARTITAD_PATH (::partita::test_paths::partitad())
#define PARTITAD_THROWAWAY_PATH (::partita::test_paths::partitadThrowaway())
#define PARTITA_CLI_PATH (::partita::test_paths::cli())
#define PARTITA_PROBE_PATH (::partita::test_paths::probe())
#define PARTITA_SLURM_CLUSTER (::partita::test_paths::slurmCluster())
