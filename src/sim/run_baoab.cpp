// Instantiates the engine for one scheme (one translation unit per scheme keeps builds parallel).
#include "engine.hpp"

namespace vehs::sim::detail {
template void run_all<BaoabStepper>(RunContext&);
}  // namespace vehs::sim::detail
