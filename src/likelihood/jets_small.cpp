// Automatic derivatives of the likelihood for up to 12 parameters per record.
#include "vehs/likelihood/detail/jet_evaluation.hpp"

namespace vehs::likelihood::detail {
template bool evaluate_jets<4>(const Evaluator&, const double*, Derivatives&, bool, bool, EvaluationFailure*);
template bool evaluate_jets<6>(const Evaluator&, const double*, Derivatives&, bool, bool, EvaluationFailure*);
template bool evaluate_jets<8>(const Evaluator&, const double*, Derivatives&, bool, bool, EvaluationFailure*);
template bool evaluate_jets<10>(const Evaluator&, const double*, Derivatives&, bool, bool, EvaluationFailure*);
template bool evaluate_jets<12>(const Evaluator&, const double*, Derivatives&, bool, bool, EvaluationFailure*);
}  // namespace vehs::likelihood::detail
