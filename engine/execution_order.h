#pragma once
// Sorting blocks for evaluation and detecting algebraic loops, on a Boost.Graph directed graph whose vertices
// are blocks and whose edges are direct-feedthrough dependencies (source block → block whose input feeds
// through). Source: Simulink's "sorted order" and "algebraic loops" (MathWorks documentation).

#include <stdexcept>
#include <string>
#include <vector>

namespace mb {

/// A dependency edge: block `to` reads an output of block `from` through input port `to_port`, which has
/// direct feedthrough. The names are for messages.
struct FeedthroughEdge {
  int from = 0;
  int to = 0;
  std::string description;  ///< e.g. "sum.y → gain.u"
};

/// Thrown when the feedthrough graph has a cycle. `cycle()` lists the block indices of one cycle in order.
class AlgebraicLoopError : public std::runtime_error {
 public:
  AlgebraicLoopError(const std::string& what, std::vector<int> cycle)
      : std::runtime_error(what), cycle_(std::move(cycle)) {}
  const std::vector<int>& cycle() const { return cycle_; }

 private:
  std::vector<int> cycle_;
};

/// Returns an order of the `num_blocks` blocks in which every edge goes forward (a topological sort; ties keep
/// the declaration order). @throws AlgebraicLoopError naming every block and port of one cycle and how to break
/// it (insert a unit_delay or another block without direct feedthrough).
std::vector<int> SortBlocks(int num_blocks, const std::vector<FeedthroughEdge>& edges,
                            const std::vector<std::string>& block_names);

}  // namespace mb
