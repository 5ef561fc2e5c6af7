// partitad: the Partita render daemon (server/README.md).
#include "partitad_main.h"

int main(int argc, char** argv) { return partita::server::partitadMain(argc, argv); }
