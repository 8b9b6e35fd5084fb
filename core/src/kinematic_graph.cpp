#include "fabkit/core/kinematic_graph.h"

#include <algorithm>
#include <cassert>
#include <numeric>

namespace fabkit {

PartId KinematicGraph::add_root() {
  nodes_.push_back({});
  return PartId{part_count() - 1};
}

PartId KinematicGraph::add_child(PartId parent, ConnectionId via) {
  assert(parent.valid() && parent.value < part_count());
  assert(via.valid() && via.value < edge_count());
  nodes_.push_back({via, parent});
  return PartId{part_count() - 1};
}

ConnectionId KinematicGraph::add_edge(PartId a, PartId b, bool closes_cycle) {
  edges_.push_back({a, b, closes_cycle});
  return ConnectionId{edge_count() - 1};
}

PartId KinematicGraph::root_of(PartId p) const {
  while (!is_root(p)) p = parent(p);
  return p;
}

std::vector<PartId> KinematicGraph::path_to_root(PartId p) const {
  std::vector<PartId> path{p};
  while (!is_root(path.back())) path.push_back(parent(path.back()));
  return path;
}

std::vector<ConnectionId> KinematicGraph::cycle_edges() const {
  std::vector<ConnectionId> out;
  for (int i = 0; i < edge_count(); ++i) {
    if (edges_[static_cast<std::size_t>(i)].closes_cycle) out.push_back(ConnectionId{i});
  }
  return out;
}

std::vector<ConnectionId> KinematicGraph::edges_of(PartId p) const {
  std::vector<ConnectionId> out;
  for (int i = 0; i < edge_count(); ++i) {
    const Edge& e = edges_[static_cast<std::size_t>(i)];
    if (e.a == p || e.b == p) out.push_back(ConnectionId{i});
  }
  return out;
}

std::vector<std::vector<PartId>> KinematicGraph::below_all() const {
  std::vector<std::vector<PartId>> out(edges_.size());
  // Parents come before children: each part is below every tree edge on its root path.
  for (int q = 0; q < part_count(); ++q) {
    PartId p{q};
    while (!is_root(p)) {
      out[parent_edge(p).index()].push_back(PartId{q});
      p = parent(p);
    }
  }
  return out;
}

std::vector<PartId> KinematicGraph::below(ConnectionId tree_edge) const {
  std::vector<PartId> out;
  for (int q = 0; q < part_count(); ++q) {
    for (PartId p{q}; !is_root(p); p = parent(p)) {
      if (parent_edge(p) == tree_edge) {
        out.push_back(PartId{q});
        break;
      }
    }
  }
  return out;
}

KinematicGraph::CyclePath KinematicGraph::cycle_path(ConnectionId closing) const {
  CyclePath out;
  out.first_side = path_to_root(edge_first(closing));
  out.second_side = path_to_root(edge_second(closing));
  std::vector<PartId>& a = out.first_side;
  std::vector<PartId>& b = out.second_side;
  // Drop the shared part above the lowest common ancestor.
  while (a.size() > 1 && b.size() > 1 && a.back() == b.back() &&
         a[a.size() - 2] == b[b.size() - 2]) {
    a.pop_back();
    b.pop_back();
  }
  out.common_ancestor = a.back() == b.back();
  return out;
}

std::vector<int> KinematicGraph::movable_groups(int* group_count) const {
  std::vector<int> up(nodes_.size());
  std::iota(up.begin(), up.end(), 0);
  auto find = [&](int x) {
    while (up[static_cast<std::size_t>(x)] != x) {
      up[static_cast<std::size_t>(x)] = up[up[static_cast<std::size_t>(x)]];
      x = up[static_cast<std::size_t>(x)];
    }
    return x;
  };
  for (const Edge& e : edges_) {
    if (is_root(e.a) || is_root(e.b)) continue;
    up[static_cast<std::size_t>(find(e.a.value))] = find(e.b.value);
  }
  std::vector<int> group(nodes_.size(), -1);
  std::vector<int> label(nodes_.size(), -1);
  int count = 0;
  for (int q = 0; q < part_count(); ++q) {
    if (is_root(PartId{q})) continue;
    const int r = find(q);
    if (label[static_cast<std::size_t>(r)] < 0) label[static_cast<std::size_t>(r)] = count++;
    group[static_cast<std::size_t>(q)] = label[static_cast<std::size_t>(r)];
  }
  if (group_count) *group_count = count;
  return group;
}

}  // namespace fabkit
