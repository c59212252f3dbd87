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
  /// The type named `type_name`. @throws std::invalid_argument for an unknown name: "unknown block type 'x' (did you
  /// mean a, b?): `motionblocks blocks` lists them".
  const BlockType& Get(const std::string& type_name) const;

 private:
  std::map<std::string, BlockType> types_;
};

// ---- The block reference (`motionblocks blocks`, the diagram schema's descriptions) ------------------------------

/// A block type's ports, learned as DiagramDocument learns an element's (an instance built through the type's
/// factory), here without a diagram: with the type's default parameters and, when it requires a sampleTime, a
/// sample time of 1 ms (ports do not depend on it).
struct BlockTypePorts {
  bool known = false;  ///< false: a parameter has no default, or the type does not build with its defaults
  std::vector<PortSpec> inputs;   ///< in declared order (port numbers 0, 1, …)
  std::vector<PortSpec> outputs;
  /// When !known: "ports depend on parameters (no default for A, B)", or "ports not listed: the type does not build
  /// without a diagram (<the factory's message>)" (a HIL block without its board).
  std::string why_unknown;
};

/// The ports of `type` built with its defaults. Throws nothing (a factory's exception becomes `why_unknown`).
BlockTypePorts DefaultPorts(const BlockType& type);

/// The ports in one line: "inputs u [N, direct feedthrough]; outputs x [m], v [m/s]" (width as "[3]" after the name
/// when > 1, "any" for a port without unit); `why_unknown` when unknown.
std::string PortsSummary(const BlockTypePorts& ports);

/// A minimal diagram element of `type`: {"name": type, "type": type, "parameters": {…}, "sampleTime": 0.001 when
/// required}, the parameters being those without default, each with a placeholder of its type to replace (numbers:
/// 1 or the lower bound, vectors [1], strings the first choice or "FILE"/"TEXT", booleans false).
nlohmann::json ExampleElement(const BlockType& type);

/// The reference of `type` as `motionblocks blocks` prints it: name, description, ports of an instance built with the
/// default parameters (direction, number, name, width, unit, direct feedthrough; parameters such as a sum's signs
/// change them), parameters (type, unit, default or [required], description), the sampleTime rule and
/// ExampleElement, over several indented lines ending with a newline.
std::string BlockReference(const BlockType& type);

}  // namespace mb

/// Registers block type `type` (a BlockType expression) at static-initialisation time. Use once per block .cc.
#define MB_REGISTER_BLOCK(identifier, ...)                                         \
  namespace {                                                                      \
  [[maybe_unused]] const bool kRegistered_##identifier =                           \
      ::mb::BlockRegistry::Global().Add(__VA_ARGS__);                              \
  }
