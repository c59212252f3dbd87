#pragma once
// What a block type can be in a larger structure, declared in the block's own file (beside MB_REGISTER_BLOCK) so
// that nobody else names the type (STYLE.md, "no type name compared as a string outside its own file"):
//  - loop roles: the parts of a motion control loop the type can be ("plant", "dob", "pd", "pd_proportional_gain",
//    "pd_derivative_gain", "pd_derivative_filter", "gp_velocity_filter", "gp_filter", "gp", "feedforward",
//    "adaptive_feedforward"), by which
//    tools/workflow/loop_from_diagram.h finds the loop, and against which a diagram's "roles" map is checked;
//  - I/O channels: for a hardware I/O block, which way its board channel goes and the parameter that scales it
//    (hw/virtual_stage.h reads an I/O subsystem's channels by this).

#include <map>
#include <string>
#include <vector>

namespace mb {

/// A hardware I/O block's board channel.
struct IoChannelTrait {
  /// true: the board measures (an encoder; the block's output feeds an output connector of the I/O subsystem);
  /// false: the board actuates (an analog output; an input connector feeds the block).
  bool measures = true;
  std::string scale_parameter;  ///< the parameter scaling the channel, e.g. "counts_per_metre" [counts/m]
  /// An actuating channel's output clamp, e.g. "limit" [V]: the board never sends more than ±limit ("" = none).
  std::string limit_parameter;
};

class BlockRoleRegistry {
 public:
  /// The process-wide registry the block files add to during static initialisation.
  static BlockRoleRegistry& Global();

  /// Declares the loop roles of `type`. Returns true (for static registration).
  bool AddLoopRoles(const std::string& type, const std::vector<std::string>& roles);
  /// Declares `type` a hardware I/O block. Returns true (for static registration).
  bool AddIoChannel(const std::string& type, IoChannelTrait trait);

  /// The block types that can be `role`, sorted by name (empty if none; link mb_blocks).
  std::vector<std::string> TypesWithLoopRole(const std::string& role) const;
  /// The I/O channel of `type`; nullptr if it is not a hardware I/O block.
  const IoChannelTrait* IoChannelOf(const std::string& type) const;

 private:
  std::map<std::string, std::vector<std::string>> loop_roles_;  // type → roles
  std::map<std::string, IoChannelTrait> io_channels_;
};

}  // namespace mb

/// Declares the loop roles of block type `type` (a string) at static-initialisation time: MB_REGISTER_LOOP_ROLES(
/// Dob, "dob", {"dob"}). Use in the block's own .cc.
#define MB_REGISTER_LOOP_ROLES(identifier, type, ...)                                 \
  namespace {                                                                         \
  [[maybe_unused]] const bool kLoopRoles_##identifier =                               \
      ::mb::BlockRoleRegistry::Global().AddLoopRoles(type, __VA_ARGS__);              \
  }

/// Declares block type `type` a hardware I/O block (an IoChannelTrait expression). Use in the block's own .cc.
#define MB_REGISTER_IO_CHANNEL(identifier, type, ...)                                 \
  namespace {                                                                         \
  [[maybe_unused]] const bool kIoChannel_##identifier =                               \
      ::mb::BlockRoleRegistry::Global().AddIoChannel(type, __VA_ARGS__);              \
  }
