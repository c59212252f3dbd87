#pragma once
// clock: y = t, the simulation time — Simulink's Clock. The source of a force that changes in time in proportion to
// it (a third factor of the diagnosis' grammar: an amplitude that drifts over a record, models/diagnosis/
// amplitude_factor.h).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = t [s]. Port: out "y". No parameters. Continuous (its output changes between major steps).
class Clock final : public Block {
 public:
  explicit Clock(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
};

}  // namespace mb
