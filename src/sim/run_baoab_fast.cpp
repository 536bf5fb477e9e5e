// Instantiates the engine's fast path for one scheme (one translation unit each keeps builds
// parallel and each unit small).
#include "engine.hpp"

namespace vehs::sim::detail {
template void run_fast<BaoabStepper>(RunContext&);
}  // namespace vehs::sim::detail
