#pragma once
// The verdict of a diagnosis: inadequate when a component's p-value is below
// alpha / (number of components) (Bonferroni, family-wise alpha; diagnose.hpp).
#include "vehs/core/enum_names.hpp"

namespace vehs::diagnose {

enum class Verdict { Adequate, Inadequate };
inline constexpr EnumNames<Verdict, 2> kVerdictNames{{{Verdict::Adequate, "adequate"}, {Verdict::Inadequate, "inadequate"}}};

}  // namespace vehs::diagnose
