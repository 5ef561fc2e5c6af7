// partitad with the tests' own algorithm "test-constant" registered first: the same daemon in
// every other respect (server/partitad_main.h).
#include "partitad_main.h"
#include "throwaway/throwaway_algorithm.h"

int main(int argc, char** argv) {
    partita::test::registerThrowawayAlgorithm();
    return partita::server::partitadMain(argc, argv);
}
