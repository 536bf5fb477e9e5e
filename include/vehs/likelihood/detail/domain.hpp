#pragma once
// The catalogue's parameter domains for a maximum-likelihood result (refine.hpp): what a model
// file accepts (vehs/core/model.hpp: complete_effect, validate_model) is what refine returns.
//  * harmonic_forcing.amplitude < 0 is the same force as −amplitude with phase + π: the result
//    is mapped there (values, phases, the amplitude's covariance row and column change sign);
//  * any other estimate outside its domain (electromechanical_coupling.coupling < 0: a
//    positive feedback the catalogue's hidden state cannot be; a22(0, 0) < 0) is an error naming
//    the parameter, its estimate and standard error — the data do not support the effect as the
//    catalogue defines it, and a model file could not hold the result.
#include "vehs/likelihood/refine.hpp"

namespace vehs::likelihood::detail {

/// Maps or refuses (vehs::Error, one line) as described above.
void respect_domain(Result& result);

}  // namespace vehs::likelihood::detail
