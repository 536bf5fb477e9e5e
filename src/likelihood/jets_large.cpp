// Automatic derivatives of the likelihood for 13 to 32 parameters per record.
#include "vehs/likelihood/detail/jet_evaluation.hpp"

namespace vehs::likelihood::detail {
template bool evaluate_jets<16>(const Evaluator&, const double*, Derivatives&, bool, bool, EvaluationFailure*);
template bool evaluate_jets<24>(const Evaluator&, const double*, Derivatives&, bool, bool, EvaluationFailure*);
template bool evaluate_jets<32>(const Evaluator&, const double*, Derivatives&, bool, bool, EvaluationFailure*);
}  // namespace vehs::likelihood::detail
