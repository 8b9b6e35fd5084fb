#include "fabkit/templates/template.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "fabkit/templates/pattern.h"

namespace fabkit::templates {

std::string_view to_string(RelationKind k) {
  switch (k) {
    case RelationKind::kCoplanar:
      return "coplanar";
    case RelationKind::kConcentric:
      return "concentric";
    case RelationKind::kSymmetric:
      return "symmetric";
    case RelationKind::kOrder:
      return "order";
    case RelationKind::kFixedSize:
      return "fixed-size";
    case RelationKind::kMaxSize:
      return "max-size";
    case RelationKind::kMinSize:
      return "min-size";
    case RelationKind::kPlacement:
      return "placement";
  }
  return "coplanar";
}

double Relation::residual(const Eigen::VectorXd& q) const {
  double r = -rhs;
  for (const LinearTerm& t : terms) r += t.coefficient * q[t.index];
  return r;
}

double AffineExpr::value(const Eigen::VectorXd& q) const {
  double v = constant;
  for (const LinearTerm& t : terms) v += t.coefficient * q[t.index];
  return v;
}

AffineExpr AffineBox::plane(int axis, Side side) const {
  AffineExpr e = center[axis];
  const double half = 0.5 * static_cast<int>(side);
  if (half != 0) {
    for (const LinearTerm& t : size[axis].terms) e.terms.push_back({t.index, half * t.coefficient});
    e.constant += half * size[axis].constant;
  }
  return e;
}

Box AffineBox::value(const Eigen::VectorXd& q) const {
  Box b;
  for (int k = 0; k < 3; ++k) {
    b.center[k] = center[k].value(q);
    b.size[k] = size[k].value(q);
  }
  return b;
}

int Template::part_count() const {
  int n = 0;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const Element& e = elements[i];
    if (!e.pattern) {
      ++n;
      continue;
    }
    const PatternLayout l = layout_pattern(*e.pattern,
                                           box(ElementId(static_cast<int>(i))),
                                           e.role == PartRole::kConnecting,
                                           e.pattern->part_resizable);
    n += l.count[0] * (e.pattern->dims == 2 ? l.count[1] : 1);
  }
  return n;
}

std::string Template::path(NodeId n) const {
  std::vector<std::string_view> names;
  for (NodeId at = n; at.valid() && at != root(); at = node(at).parent) {
    names.push_back(node(at).name);
  }
  std::string out;
  for (auto it = names.rbegin(); it != names.rend(); ++it) {
    if (!out.empty()) out += '/';
    out += *it;
  }
  return out;
}

NodeId Template::find(std::string_view p) const {
  NodeId at = root();
  if (nodes.empty()) return NodeId();
  while (!p.empty()) {
    const std::size_t slash = p.find('/');
    const std::string_view name = p.substr(0, slash);
    p = slash == std::string_view::npos ? std::string_view() : p.substr(slash + 1);
    if (name.empty()) continue;
    NodeId next;
    for (NodeId c : node(at).children) {
      if (node(c).name == name) next = c;
    }
    if (!next.valid()) return NodeId();
    at = next;
  }
  return at;
}

NodeId Template::find_node_or_element(std::string_view name) const {
  if (name.find('/') != std::string_view::npos || name.empty()) return find(name);
  NodeId found, leaf;
  int hits = 0, leaves = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].name != name) continue;
    found = NodeId(static_cast<int>(i));
    ++hits;
    if (nodes[i].element) {
      leaf = found;
      ++leaves;
    }
  }
  if (hits == 1) return found;
  // "top" names both the group and the board in it: the part is meant.
  if (leaves == 1) return leaf;
  return find(name);
}

std::vector<ElementId> Template::elements_under(NodeId n) const {
  std::vector<ElementId> out;
  std::vector<NodeId> stack{n};
  while (!stack.empty()) {
    const NodeId at = stack.back();
    stack.pop_back();
    if (node(at).element) out.push_back(*node(at).element);
    for (auto it = node(at).children.rbegin(); it != node(at).children.rend(); ++it) {
      stack.push_back(*it);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool Template::is_ancestor(NodeId a, NodeId b) const {
  for (NodeId at = b; at.valid(); at = node(at).parent) {
    if (at == a) return true;
  }
  return false;
}

int Template::depth(NodeId n) const {
  int d = 0;
  for (NodeId at = n; at.valid() && at != root(); at = node(at).parent) ++d;
  return d;
}

NodeId Template::lowest_common_ancestor(NodeId a, NodeId b) const {
  int da = depth(a), db = depth(b);
  while (da > db) {
    a = node(a).parent;
    --da;
  }
  while (db > da) {
    b = node(b).parent;
    --db;
  }
  while (a != b) {
    a = node(a).parent;
    b = node(b).parent;
  }
  return a;
}

Box Template::box(ElementId e) const {
  return box(e, q);
}

Box Template::box(ElementId e, const Eigen::VectorXd& at) const {
  Box b;
  for (int k = 0; k < 3; ++k) {
    b.center[k] = at[center_index(e, k)];
    b.size[k] = at[size_index(e, k)];
  }
  return b;
}

Box Template::node_box(NodeId n) const {
  const std::vector<ElementId> es = elements_under(n);
  if (es.empty()) return Box{};
  Box b = box(es.front());
  for (ElementId e : es) b = b.united(box(e));
  return b;
}

AffineBox Template::affine_box(ElementId e) const {
  AffineBox b;
  for (int k = 0; k < 3; ++k) {
    b.center[k].terms = {{center_index(e, k), 1.0}};
    b.size[k].terms = {{size_index(e, k), 1.0}};
  }
  return b;
}

std::vector<PlacedPart> Template::placed_parts() const {
  std::vector<PlacedPart> out;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ElementId id(static_cast<int>(i));
    const Element& e = elements[i];
    const Box b = box(id);
    if (!e.pattern) {
      out.push_back({e.part_names.empty() ? e.name : e.part_names.front(), e.item, b, e.role, id});
      continue;
    }
    const std::vector<Box> boxes = pattern_part_boxes(
        *e.pattern, b, e.role == PartRole::kConnecting, e.pattern->part_resizable);
    for (std::size_t j = 0; j < boxes.size(); ++j) {
      // Names of the design's parts while the count is unchanged, numbered beyond.
      const std::string name = j < e.part_names.size() && boxes.size() == e.part_names.size()
                                   ? e.part_names[j]
                                   : e.name + "_" + std::to_string(j + 1);
      out.push_back({name, e.item, boxes[j], e.role, id});
    }
  }
  return out;
}

Template Template::subtree(NodeId n) const {
  Template t;
  t.name = n == root() ? name : name + "/" + path(n);
  t.title = n == root() ? title : node(n).name;
  t.category = category;
  // Nodes in pre-order, re-indexed.
  std::map<int, int> node_map;
  std::vector<NodeId> order;
  std::vector<NodeId> stack{n};
  while (!stack.empty()) {
    const NodeId at = stack.back();
    stack.pop_back();
    node_map[at.value] = static_cast<int>(order.size());
    order.push_back(at);
    for (auto it = node(at).children.rbegin(); it != node(at).children.rend(); ++it) {
      stack.push_back(*it);
    }
  }
  std::map<int, int> element_map;
  for (ElementId e : elements_under(n)) {
    element_map[e.value] = static_cast<int>(element_map.size());
  }
  std::map<int, int> relation_map, connection_map;
  for (std::size_t r = 0; r < relations.size(); ++r) {
    if (node_map.count(relations[r].node.value)) {
      relation_map[static_cast<int>(r)] = static_cast<int>(relation_map.size());
    }
  }
  for (std::size_t c = 0; c < connections.size(); ++c) {
    if (node_map.count(connections[c].node.value)) {
      connection_map[static_cast<int>(c)] = static_cast<int>(connection_map.size());
    }
  }
  auto map_element = [&](ElementId e) { return ElementId(element_map.at(e.value)); };
  auto map_index = [&](int index) {
    return element_map.at(index / kParamsPerElement) * kParamsPerElement +
           index % kParamsPerElement;
  };
  t.q.resize(static_cast<Eigen::Index>(element_map.size()) * kParamsPerElement);
  t.elements.resize(element_map.size());
  for (const auto& [from, to] : element_map) {
    t.elements[to] = elements[from];
    t.elements[to].node = NodeId(node_map.at(elements[from].node.value));
    t.q.segment<kParamsPerElement>(to * kParamsPerElement) =
        q.segment<kParamsPerElement>(from * kParamsPerElement);
  }
  for (NodeId at : order) {
    Node copy = node(at);
    copy.parent = at == n ? NodeId() : NodeId(node_map.at(node(at).parent.value));
    for (NodeId& c : copy.children) c = NodeId(node_map.at(c.value));
    if (copy.element) copy.element = map_element(*copy.element);
    std::vector<RelationId> rs;
    for (RelationId r : copy.relations) rs.push_back(RelationId(relation_map.at(r.value)));
    copy.relations = rs;
    std::vector<ConnectionId> cs;
    for (ConnectionId c : copy.connections) cs.push_back(ConnectionId(connection_map.at(c.value)));
    copy.connections = cs;
    t.nodes.push_back(std::move(copy));
  }
  if (n != root()) t.nodes[0].name = t.name.substr(t.name.rfind('/') + 1);
  t.relations.resize(relation_map.size());
  for (const auto& [from, to] : relation_map) {
    Relation r = relations[from];
    for (LinearTerm& term : r.terms) term.index = map_index(term.index);
    for (ElementId& e : r.elements) e = map_element(e);
    for (PlaneRef& p : r.planes) p.element = map_element(p.element);
    r.node = NodeId(node_map.at(r.node.value));
    if (r.connection.valid()) r.connection = ConnectionId(connection_map.at(r.connection.value));
    t.relations[to] = std::move(r);
  }
  t.connections.resize(connection_map.size());
  for (const auto& [from, to] : connection_map) {
    Connection c = connections[from];
    for (ElementId& e : c.principal) e = map_element(e);
    for (ElementId& e : c.connecting) e = map_element(e);
    for (RelationId& r : c.relations) r = RelationId(relation_map.at(r.value));
    for (RelationId& r : c.placement) r = RelationId(relation_map.at(r.value));
    c.node = NodeId(node_map.at(c.node.value));
    t.connections[to] = std::move(c);
  }
  for (const TemplateArticulation& a : articulations) {
    bool inside = element_map.count(a.pivot_element.value) > 0;
    for (ElementId e : a.moving) inside = inside && element_map.count(e.value) > 0;
    if (!inside) continue;
    TemplateArticulation copy = a;
    copy.pivot_element = map_element(a.pivot_element);
    for (ElementId& e : copy.moving) e = map_element(e);
    t.articulations.push_back(std::move(copy));
  }
  return t;
}

double Template::max_violation(const Eigen::VectorXd& at) const {
  double worst = 0;
  for (const Relation& r : relations) {
    if (r.soft) continue;
    const double v = r.residual(at);
    worst = std::max(worst, r.equality ? std::abs(v) : std::max(0.0, v));
  }
  return worst;
}

}  // namespace fabkit::templates

namespace fabkit::templates {

namespace {

AffineExpr scaled(const AffineExpr& e, double s) {
  AffineExpr out = e;
  for (LinearTerm& t : out.terms) t.coefficient *= s;
  out.constant *= s;
  return out;
}

AffineExpr sum(const AffineExpr& a, const AffineExpr& b) {
  AffineExpr out = a;
  out.terms.insert(out.terms.end(), b.terms.begin(), b.terms.end());
  out.constant += b.constant;
  return out;
}

}  // namespace

std::string rest_pose_name(const TemplateArticulation& a) {
  const double v = a.upper;
  const bool whole = std::abs(v - std::round(v)) < 1e-9;
  const std::string number =
      whole ? std::to_string(static_cast<long long>(std::round(v))) : std::to_string(v);
  return a.name + " at " + number + (a.type == JointType::kPrismatic ? " mm" : "°");
}

AffineBox rest_pose_box(const Template& t, const TemplateArticulation& a, ElementId e) {
  AffineBox b = t.affine_box(e);
  if (a.type == JointType::kPrismatic) {
    b.center[a.axis].constant += a.direction * (a.upper - a.lower);
    return b;
  }
  if (a.type != JointType::kHinge) return b;
  // Quarter turns only (the linear model keeps boxes axis-aligned).
  const int quarter = static_cast<int>(std::lround((a.upper - a.lower) / 90.0)) * a.direction;
  const int turns = ((quarter % 4) + 4) % 4;
  if (turns == 0) return b;
  const int u = (a.axis + 1) % 3, v = (a.axis + 2) % 3;
  // Pivot: the anchor element's min corner plus fraction ∘ size.
  const AffineBox anchor = t.affine_box(a.pivot_element);
  std::array<AffineExpr, 3> pivot;
  for (int k = 0; k < 3; ++k) {
    pivot[k] = sum(anchor.plane(k, Side::kMin), scaled(anchor.size[k], a.pivot_fraction[k]));
  }
  AffineBox out = b;
  // Rotate (c - P) in the (u, v) plane by turns × 90°.
  const AffineExpr du = sum(b.center[u], scaled(pivot[u], -1));
  const AffineExpr dv = sum(b.center[v], scaled(pivot[v], -1));
  AffineExpr ru = du, rv = dv;
  if (turns == 1) {
    ru = scaled(dv, -1);
    rv = du;
  } else if (turns == 2) {
    ru = scaled(du, -1);
    rv = scaled(dv, -1);
  } else if (turns == 3) {
    ru = dv;
    rv = scaled(du, -1);
  }
  out.center[u] = sum(pivot[u], ru);
  out.center[v] = sum(pivot[v], rv);
  if (turns % 2 == 1) std::swap(out.size[u], out.size[v]);
  return out;
}

}  // namespace fabkit::templates

namespace fabkit::templates {

NodeId Template::append(const Template& other, NodeId parent, const std::string& new_name) {
  const int node_offset = static_cast<int>(nodes.size());
  const int element_offset = static_cast<int>(elements.size());
  const int relation_offset = static_cast<int>(relations.size());
  const int connection_offset = static_cast<int>(connections.size());
  const int index_offset = element_offset * kParamsPerElement;
  auto node_of = [&](NodeId n) { return n.valid() ? NodeId(n.value + node_offset) : parent; };
  for (const Node& n : other.nodes) {
    Node copy = n;
    copy.parent = node_of(n.parent);
    for (NodeId& c : copy.children) c = NodeId(c.value + node_offset);
    if (copy.element) copy.element = ElementId(copy.element->value + element_offset);
    for (RelationId& r : copy.relations) r = RelationId(r.value + relation_offset);
    for (ConnectionId& c : copy.connections) c = ConnectionId(c.value + connection_offset);
    nodes.push_back(std::move(copy));
  }
  const NodeId root_copy(node_offset);
  nodes[root_copy.value].name = new_name;
  nodes[parent.value].children.push_back(root_copy);
  for (const Element& e : other.elements) {
    Element copy = e;
    copy.node = NodeId(e.node.value + node_offset);
    elements.push_back(std::move(copy));
  }
  for (const Relation& r : other.relations) {
    Relation copy = r;
    for (LinearTerm& t : copy.terms) t.index += index_offset;
    for (ElementId& e : copy.elements) e = ElementId(e.value + element_offset);
    for (PlaneRef& p : copy.planes) p.element = ElementId(p.element.value + element_offset);
    copy.node = NodeId(r.node.value + node_offset);
    if (copy.connection.valid())
      copy.connection = ConnectionId(r.connection.value + connection_offset);
    relations.push_back(std::move(copy));
  }
  for (const Connection& c : other.connections) {
    Connection copy = c;
    for (ElementId& e : copy.principal) e = ElementId(e.value + element_offset);
    for (ElementId& e : copy.connecting) e = ElementId(e.value + element_offset);
    for (RelationId& r : copy.relations) r = RelationId(r.value + relation_offset);
    for (RelationId& r : copy.placement) r = RelationId(r.value + relation_offset);
    copy.node = NodeId(c.node.value + node_offset);
    connections.push_back(std::move(copy));
  }
  for (const TemplateArticulation& a : other.articulations) {
    TemplateArticulation copy = a;
    for (ElementId& e : copy.moving) e = ElementId(e.value + element_offset);
    copy.pivot_element = ElementId(a.pivot_element.value + element_offset);
    articulations.push_back(std::move(copy));
  }
  Eigen::VectorXd grown(q.size() + other.q.size());
  grown << q, other.q;
  q = grown;
  return root_copy;
}

Template Template::without(NodeId n) const {
  std::vector<char> removed_element(elements.size(), 0);
  for (ElementId e : elements_under(n)) removed_element[e.value] = 1;
  // Connections touching a removed principal element go, with their connecting elements.
  std::vector<char> removed_connection(connections.size(), 0);
  for (std::size_t c = 0; c < connections.size(); ++c) {
    bool gone = false;
    for (ElementId e : connections[c].principal) gone = gone || removed_element[e.value];
    for (ElementId e : connections[c].connecting) gone = gone || removed_element[e.value];
    if (!gone) continue;
    removed_connection[c] = 1;
    for (ElementId e : connections[c].connecting) removed_element[e.value] = 1;
  }
  std::vector<char> removed_node(nodes.size(), 0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const NodeId id(static_cast<int>(i));
    if (is_ancestor(n, id)) removed_node[i] = 1;
    if (nodes[i].element && removed_element[nodes[i].element->value]) removed_node[i] = 1;
  }
  // Connection nodes left empty go too.
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (!nodes[i].connection_node || removed_node[i]) continue;
    bool any = false;
    for (NodeId c : nodes[i].children) any = any || !removed_node[c.value];
    if (!any) removed_node[i] = 1;
  }
  removed_node[0] = 0;
  std::vector<int> element_map(elements.size(), -1), node_map(nodes.size(), -1),
      connection_map(connections.size(), -1), relation_map(relations.size(), -1);
  int ne = 0, nn = 0, nc = 0, nr = 0;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (!removed_element[i]) element_map[i] = ne++;
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (!removed_node[i]) node_map[i] = nn++;
  }
  for (std::size_t i = 0; i < connections.size(); ++i) {
    if (!removed_connection[i]) connection_map[i] = nc++;
  }
  for (std::size_t i = 0; i < relations.size(); ++i) {
    bool keep = node_map[relations[i].node.value] >= 0;
    for (ElementId e : relations[i].elements) keep = keep && !removed_element[e.value];
    if (relations[i].connection.valid())
      keep = keep && !removed_connection[relations[i].connection.value];
    if (keep) relation_map[i] = nr++;
  }
  Template t;
  t.name = name;
  t.title = title;
  t.category = category;
  t.q.resize(ne * kParamsPerElement);
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (element_map[i] < 0) continue;
    Element e = elements[i];
    e.node = NodeId(node_map[e.node.value]);
    t.elements.push_back(std::move(e));
    t.q.segment<kParamsPerElement>(element_map[i] * kParamsPerElement) =
        q.segment<kParamsPerElement>(static_cast<Eigen::Index>(i) * kParamsPerElement);
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (node_map[i] < 0) continue;
    Node copy = nodes[i];
    copy.parent = copy.parent.valid() ? NodeId(node_map[copy.parent.value]) : NodeId();
    std::vector<NodeId> children;
    for (NodeId c : copy.children) {
      if (node_map[c.value] >= 0) children.push_back(NodeId(node_map[c.value]));
    }
    copy.children = children;
    if (copy.element) copy.element = ElementId(element_map[copy.element->value]);
    std::vector<RelationId> rs;
    for (RelationId r : copy.relations) {
      if (relation_map[r.value] >= 0) rs.push_back(RelationId(relation_map[r.value]));
    }
    copy.relations = rs;
    std::vector<ConnectionId> cs;
    for (ConnectionId c : copy.connections) {
      if (connection_map[c.value] >= 0) cs.push_back(ConnectionId(connection_map[c.value]));
    }
    copy.connections = cs;
    t.nodes.push_back(std::move(copy));
  }
  auto map_index = [&](int index) {
    return element_map[index / kParamsPerElement] * kParamsPerElement + index % kParamsPerElement;
  };
  for (std::size_t i = 0; i < relations.size(); ++i) {
    if (relation_map[i] < 0) continue;
    Relation r = relations[i];
    for (LinearTerm& term : r.terms) term.index = map_index(term.index);
    for (ElementId& e : r.elements) e = ElementId(element_map[e.value]);
    for (PlaneRef& p : r.planes) p.element = ElementId(element_map[p.element.value]);
    r.node = NodeId(node_map[r.node.value]);
    if (r.connection.valid()) r.connection = ConnectionId(connection_map[r.connection.value]);
    t.relations.push_back(std::move(r));
  }
  for (std::size_t i = 0; i < connections.size(); ++i) {
    if (connection_map[i] < 0) continue;
    Connection c = connections[i];
    for (ElementId& e : c.principal) e = ElementId(element_map[e.value]);
    for (ElementId& e : c.connecting) e = ElementId(element_map[e.value]);
    for (RelationId& r : c.relations) r = RelationId(relation_map[r.value]);
    for (RelationId& r : c.placement) r = RelationId(relation_map[r.value]);
    c.node = NodeId(node_map[c.node.value]);
    t.connections.push_back(std::move(c));
  }
  for (const TemplateArticulation& a : articulations) {
    bool keep = !removed_element[a.pivot_element.value];
    TemplateArticulation copy = a;
    copy.moving.clear();
    for (ElementId e : a.moving) {
      if (!removed_element[e.value]) copy.moving.push_back(ElementId(element_map[e.value]));
    }
    if (!keep || copy.moving.empty()) continue;
    copy.pivot_element = ElementId(element_map[a.pivot_element.value]);
    t.articulations.push_back(std::move(copy));
  }
  return t;
}

ConnectionId Template::add_connection(Connection c, NodeId parent) {
  if (node(parent).element) parent = node(parent).parent;
  const NodeId cn(static_cast<int>(nodes.size()));
  nodes.push_back(Node{c.name, parent, {}, std::nullopt, true, {}, {}});
  nodes[parent.value].children.push_back(cn);
  for (ElementId e : c.connecting) {
    const NodeId leaf(static_cast<int>(nodes.size()));
    nodes.push_back(Node{elements[e.value].name, cn, {}, e, false, {}, {}});
    nodes[cn.value].children.push_back(leaf);
    elements[e.value].node = leaf;
  }
  c.node = parent;
  const ConnectionId id(static_cast<int>(connections.size()));
  for (RelationId r : c.relations) relations[r.value].connection = id;
  for (RelationId r : c.placement) relations[r.value].connection = id;
  nodes[parent.value].connections.push_back(id);
  connections.push_back(std::move(c));
  return id;
}

}  // namespace fabkit::templates

namespace fabkit::templates {

Template Template::restricted_to(const std::vector<ElementId>& free) const {
  Template t;
  t.name = name;
  t.nodes.push_back(Node{name, NodeId(), {}, std::nullopt, false, {}, {}});
  std::vector<int> map(elements.size(), -1);
  t.q.resize(static_cast<Eigen::Index>(free.size()) * kParamsPerElement);
  for (std::size_t i = 0; i < free.size(); ++i) {
    map[free[i].value] = static_cast<int>(i);
    Element e = elements[free[i].value];
    e.node = NodeId(static_cast<int>(t.nodes.size()));
    t.nodes.push_back(Node{e.name, t.root(), {}, ElementId(static_cast<int>(i)), false, {}, {}});
    t.nodes[0].children.push_back(e.node);
    t.elements.push_back(std::move(e));
    t.q.segment<kParamsPerElement>(static_cast<Eigen::Index>(i) * kParamsPerElement) =
        q.segment<kParamsPerElement>(free[i].value * kParamsPerElement);
  }
  for (const Relation& r : relations) {
    bool touches = false;
    for (const LinearTerm& term : r.terms)
      touches = touches || map[term.index / kParamsPerElement] >= 0;
    if (!touches) continue;
    Relation copy = r;
    copy.terms.clear();
    copy.elements.clear();
    for (const LinearTerm& term : r.terms) {
      const int e = map[term.index / kParamsPerElement];
      if (e < 0) {
        copy.rhs -= term.coefficient * q[term.index];
      } else {
        copy.terms.push_back(
            {e * kParamsPerElement + term.index % kParamsPerElement, term.coefficient});
        if (std::find(copy.elements.begin(), copy.elements.end(), ElementId(e)) ==
            copy.elements.end()) {
          copy.elements.push_back(ElementId(e));
        }
      }
    }
    std::vector<PlaneRef> planes;
    for (PlaneRef p : r.planes) {
      if (map[p.element.value] >= 0) {
        p.element = ElementId(map[p.element.value]);
        planes.push_back(p);
      }
    }
    copy.planes = planes;
    copy.node = t.root();
    copy.connection = ConnectionId();
    t.relations.push_back(std::move(copy));
  }
  for (const TemplateArticulation& a : articulations) {
    bool inside = map[a.pivot_element.value] >= 0;
    for (ElementId e : a.moving) inside = inside && map[e.value] >= 0;
    if (!inside) continue;
    TemplateArticulation copy = a;
    copy.pivot_element = ElementId(map[a.pivot_element.value]);
    for (ElementId& e : copy.moving) e = ElementId(map[e.value]);
    t.articulations.push_back(std::move(copy));
  }
  return t;
}

}  // namespace fabkit::templates
