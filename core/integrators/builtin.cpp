#include <mutex>

#include "algorithm.h"
#include "integrators/bdpt/bdpt_integrator.h"
#include "integrators/guided/guided_integrator.h"
#include "integrators/mlt/mlt_integrator.h"
#include "integrators/partitioned/partitioned_integrator.h"
#include "integrators/pt/pt_integrator.h"

namespace partita {

void registerBuiltinAlgorithms() {
    static std::once_flag once;
    std::call_once(once, [] {
        registerPathTracer();
        registerBdpt();
        registerMlt();
        registerPartitioned();
        registerGuided();
    });
}

}  // namespace partita
