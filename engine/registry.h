#pragma once
// Block types register themselves by type name; the engine creates blocks through this registry and knows
// none of them by name.

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/block.h"
#include "engine/parameters.h"
#include "engine/sample_time.h"

namespace mb {

/// Whether a block type takes a `sampleTime` in the diagram.
enum class SampleTimeRule {
  kNone,      ///< continuous or inherited by nature; a `sampleTime` in the diagram is an error
  kRequired,  ///< a discrete block: `sampleTime: [Ts, offset]` (or Ts) must be given
  kOptional,  ///< discrete when a `sampleTime` is given, continuous/inherited otherwise
};

/// What a factory gets to build one block instance.
struct BlockConfig {
  std::string name;                        ///< instance name, unique in the diagram
  Parameters parameters;                   ///< validated, defaults filled in
  std::optional<SampleTime> sample_time;   ///< from the diagram (discrete) if given
  std::filesystem::path base_directory;    ///< the diagram file's folder, for relative file parameters
};

/// One registered block type: its name, documentation, parameters and factory.
struct BlockType {
  std::string type_name;
  std::string description;  ///< the equation and ports, one paragraph (shown by `motionblocks blocks`)
  std::vector<ParamSpec> parameters;
  SampleTimeRule sample_time_rule = SampleTimeRule::kNone;
  std::function<std::unique_ptr<Block>(const BlockConfig&)> factory;
  /// Set by the one type that adds signals: the parameters that make an instance the sum of two inputs,
  /// y = u_0 + u_1 (its input ports in declared order, its output port 0). DiagramDocument::SumInto splices such
  /// an element into a signal path; nobody outside the block's own file names its type or ports.
  std::optional<nlohmann::json> sum_of_two = std::nullopt;
  /// Set by the same type: the parameters that make an instance the difference y = u_0 − u_1 (what the log holds
  /// beyond what a command-path block passes on: compare --suggest, BlockPlacement::kOnCommand).
  std::optional<nlohmann::json> difference_of_two = std::nullopt;
};

class BlockRegistry {
 public:
  /// The process-wide registry that library blocks add themselves to during static initialisation.
  static BlockRegistry& Global();

  /// Adds a type. @throws std::logic_error if the name is taken. Returns true (for static registration).
  bool Add(BlockType type);
  /// nullptr if unknown.
  const BlockType* Find(const std::string& type_name) const;
  std::vector<std::string> TypeNames() const;
  /// The type that declares `sum_of_two`. @throws std::logic_error if none is registered (link mb_blocks).
  const BlockType& SumOfTwo() const;
  /// The type that declares `difference_of_two`. @throws std::logic_error if none is registered (link mb_blocks).
  const BlockType& DifferenceOfTwo() const;
  /// The registered names closest to `type_name` (edit distance), for "did you mean" messages.
  std::vector<std::string> Suggest(const std::string& type_name, std::size_t max_suggestions = 3) const;

 private:
  std::map<std::string, BlockType> types_;
};

}  // namespace mb

/// Registers block type `type` (a BlockType expression) at static-initialisation time. Use once per block .cc.
#define MB_REGISTER_BLOCK(identifier, ...)                                         \
  namespace {                                                                      \
  [[maybe_unused]] const bool kRegistered_##identifier =                           \
      ::mb::BlockRegistry::Global().Add(__VA_ARGS__);                              \
  }
