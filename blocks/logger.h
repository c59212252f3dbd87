#pragma once
// logger: a named sink for signal logging (Simulink's To Workspace / Scope role). y = u.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = u. Ports: in "u", out "y" (width n). Parameter width n. Inherits its sample time.
/// Why a block at all: the diagram's "log" list records output ports ("block.port"), so a logger gives a
/// signal a user-chosen name in the log: list "<logger name>.y" (or "<logger name>") in "log". The engine
/// logs nothing automatically; a logger that is not listed in "log" records nothing. Nothing need be
/// connected to its output.
class Logger final : public Block {
 public:
  explicit Logger(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
};

}  // namespace mb
