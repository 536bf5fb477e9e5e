#pragma once
// The effect catalogue as a Markdown page (docs/reference/effects.md), generated from the
// catalogue the code uses (vehs::effect_catalogue(), built from the effect types).
#include <string>

namespace vehs::tools {

std::string catalogue_markdown();

}  // namespace vehs::tools
