#include "engine/execution_order.h"

#include <algorithm>
#include <functional>
#include <queue>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/strong_components.hpp>
#include <fmt/format.h>

namespace mb {

namespace {

using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS, boost::no_property,
                                    boost::property<boost::edge_index_t, std::size_t>>;

// Finds one cycle inside a strongly connected component (all of whose vertices are in `component`), as a
// list of edge indices, by walking forward until a vertex repeats.
std::vector<std::size_t> CycleInComponent(const std::vector<FeedthroughEdge>& edges, const std::vector<int>& comp,
                                          int start) {
  std::vector<std::size_t> path_edges;
  std::vector<int> visited_at(comp.size(), -1);
  auto comp_index = [&](int v) {
    return static_cast<std::size_t>(std::find(comp.begin(), comp.end(), v) - comp.begin());
  };
  int v = start;
  while (visited_at[comp_index(v)] < 0) {
    visited_at[comp_index(v)] = static_cast<int>(path_edges.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
      if (edges[e].from == v && std::find(comp.begin(), comp.end(), edges[e].to) != comp.end()) {
        path_edges.push_back(e);
        v = edges[e].to;
        break;
      }
    }
  }
  const auto first = static_cast<std::size_t>(visited_at[comp_index(v)]);
  return {path_edges.begin() + static_cast<std::ptrdiff_t>(first), path_edges.end()};
}

}  // namespace

std::vector<int> SortBlocks(int num_blocks, const std::vector<FeedthroughEdge>& edges,
                            const std::vector<std::string>& block_names) {
  const auto n = static_cast<std::size_t>(num_blocks);
  Graph graph(n);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    boost::add_edge(static_cast<std::size_t>(edges[e].from), static_cast<std::size_t>(edges[e].to), e, graph);
  }

  // Algebraic loops: strongly connected components with more than one block, or a block feeding itself.
  std::vector<int> component(n);
  const int num_components = boost::strong_components(
      graph, boost::make_iterator_property_map(component.begin(), boost::get(boost::vertex_index, graph)));
  std::vector<std::vector<int>> members(static_cast<std::size_t>(num_components));
  for (std::size_t v = 0; v < n; ++v) members[static_cast<std::size_t>(component[v])].push_back(static_cast<int>(v));
  std::vector<bool> feeds_itself(n, false);  // one pass over the edges (not one per block: 100k blocks)
  for (const auto& e : edges) {
    if (e.from == e.to) feeds_itself[static_cast<std::size_t>(e.from)] = true;
  }
  for (const auto& comp : members) {
    const bool self_loop = comp.size() == 1 && feeds_itself[static_cast<std::size_t>(comp[0])];
    if (comp.size() < 2 && !self_loop) continue;
    const auto cycle_edges = CycleInComponent(edges, comp, comp.front());
    std::vector<int> cycle;
    std::string path;
    for (auto e : cycle_edges) {
      cycle.push_back(edges[e].from);
      path += fmt::format("\n    {}", edges[e].description);
    }
    std::string names;
    for (int b : cycle) names += (names.empty() ? "" : ", ") + block_names[static_cast<std::size_t>(b)];
    throw AlgebraicLoopError(
        fmt::format("algebraic loop through blocks [{}]: every connection in the cycle feeds through directly:{}\n"
                    "  fix: break the cycle with a block without direct feedthrough (a unit_delay, an integrator, "
                    "a discrete block whose output does not depend on its current input), or move a "
                    "computation out of the cycle",
                    names, path),
        cycle);
  }

  // Kahn's algorithm with a min-queue keeps ties in declaration order (a stable, readable schedule).
  std::vector<int> indegree(n, 0);
  for (const auto& e : edges) ++indegree[static_cast<std::size_t>(e.to)];
  std::priority_queue<int, std::vector<int>, std::greater<>> ready;
  for (std::size_t v = 0; v < n; ++v) {
    if (indegree[v] == 0) ready.push(static_cast<int>(v));
  }
  std::vector<int> order;
  while (!ready.empty()) {
    const int v = ready.top();
    ready.pop();
    order.push_back(v);
    auto [it, end] = boost::out_edges(static_cast<std::size_t>(v), graph);
    for (; it != end; ++it) {
      const auto w = boost::target(*it, graph);
      if (--indegree[w] == 0) ready.push(static_cast<int>(w));
    }
  }
  return order;
}

}  // namespace mb
