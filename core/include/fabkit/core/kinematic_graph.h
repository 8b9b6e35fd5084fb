#pragma once
/// The kinematic graph of an assembly: parts as nodes, connections as edges. Parts are added
/// in an order where every part's parent comes first; roots (fixed parts such as
/// environments) have no parent. A connection between a new part and one already in the graph
/// is a tree edge (the new part's parent); one between two parts already in it closes a
/// cycle. Reduced coordinates live on the tree edges; cycle edges become constraints.

#include <vector>

#include "fabkit/core/ids.h"

namespace fabkit {

class KinematicGraph {
 public:
  /// A fixed part (an environment): no parent.
  PartId add_root();
  /// A part brought in by tree edge `via` from `parent`.
  PartId add_child(PartId parent, ConnectionId via);
  /// Records that connection `id` (the next id) joins `a` and `b`; a tree edge must be
  /// recorded before add_child uses it.
  ConnectionId add_edge(PartId a, PartId b, bool closes_cycle);

  int part_count() const { return static_cast<int>(nodes_.size()); }
  int edge_count() const { return static_cast<int>(edges_.size()); }
  bool is_root(PartId p) const { return !nodes_[p.index()].parent_edge.valid(); }
  /// The tree edge above `p` (invalid for roots).
  ConnectionId parent_edge(PartId p) const { return nodes_[p.index()].parent_edge; }
  /// The part above `p` (invalid for roots).
  PartId parent(PartId p) const { return nodes_[p.index()].parent; }
  /// The part at the root of `p`'s tree.
  PartId root_of(PartId p) const;
  /// `p`, its parent, ..., its root.
  std::vector<PartId> path_to_root(PartId p) const;
  bool closes_cycle(ConnectionId c) const { return edges_[c.index()].closes_cycle; }
  PartId edge_first(ConnectionId c) const { return edges_[c.index()].a; }
  PartId edge_second(ConnectionId c) const { return edges_[c.index()].b; }
  /// Cycle-closing edges in the order they were added.
  std::vector<ConnectionId> cycle_edges() const;
  /// Edges touching part `p`.
  std::vector<ConnectionId> edges_of(PartId p) const;

  /// The parts a tree edge moves: the child below it and all its descendants (sorted).
  std::vector<PartId> below(ConnectionId tree_edge) const;
  /// below() for every edge at once (empty for cycle edges), in O(parts · depth).
  std::vector<std::vector<PartId>> below_all() const;

  /// The loop closed by a cycle edge as two tree paths, one from each end part up to the
  /// lowest common ancestor (shared as both paths' last element) or, when the ends hang from
  /// different roots, up to each root.
  struct CyclePath {
    std::vector<PartId> first_side;
    std::vector<PartId> second_side;
    bool common_ancestor = false;
  };
  CyclePath cycle_path(ConnectionId cycle_edge) const;

  /// Groups of non-root parts that move together: two parts are in one group when a
  /// connection (tree or cycle) joins them directly or through other non-root parts. Roots do
  /// not move, so what hangs from them in separate groups can be solved separately. Returns
  /// the group index of every part (-1 for roots).
  std::vector<int> movable_groups(int* group_count = nullptr) const;

 private:
  struct Node {
    ConnectionId parent_edge;
    PartId parent;
  };
  struct Edge {
    PartId a, b;
    bool closes_cycle = false;
  };
  std::vector<Node> nodes_;
  std::vector<Edge> edges_;
};

}  // namespace fabkit
