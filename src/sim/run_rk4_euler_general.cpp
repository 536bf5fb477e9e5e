// Instantiates the engine's general path for one scheme (one translation unit each keeps builds
// parallel and each unit small).
#include "engine.hpp"

namespace vehs::sim::detail {
template void run_general<Rk4EulerStepper>(RunContext&);
}  // namespace vehs::sim::detail
