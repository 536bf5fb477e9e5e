#pragma once
// The one failure of the likelihood that says nothing against the model's structure: the filter's
// moment equations left the model's domain at some parameter value (a stiff spot, a non-smooth
// force in nearly deterministic motion). Callers that can fall back (identify's refinement,
// diagnose's refits) catch it by type; every other caller sees a vehs::Error.
#include <string>

#include "vehs/core/error.hpp"

namespace vehs::likelihood {

class FilterDiverged : public Error {
 public:
  explicit FilterDiverged(const std::string& message) : Error(message) {}
};

}  // namespace vehs::likelihood
