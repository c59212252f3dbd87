#pragma once
// `compare --suggest`: the diagram amended with the block of a diagnosed missing effect, its parameters set
// from the diagnosis, its coefficients added to the diagram's free parameters so that the next compare refits
// them jointly with the base model (DIAGNOSIS.md step 1).

#include <string>

#include <nlohmann/json.hpp>

#include "models/diagnosis/diagnosis.h"

namespace mb {

/// Effects for which the block library has a block that SuggestAmendedDiagram can insert.
bool HasEffectBlock(const std::string& effect);

/// Returns the diagram with an element for `effect` added: its input wired from the diagram input connector
/// whose unit matches the effect's abscissa (position: "m"; velocity: "m/s"), its output added to the source of
/// output connector `output` through a new sum element. @throws std::invalid_argument if the effect has no block
/// or the diagram lacks the needed input connector (the message says which to add).
nlohmann::json SuggestAmendedDiagram(const nlohmann::json& diagram, const DiagnosedEffect& effect,
                                     const std::string& output);

}  // namespace mb
