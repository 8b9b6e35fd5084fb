#pragma once
/// Parameterized templates (paper §3.2): a tree whose leaves are *elements* (one part, or a
/// regular pattern of identical parts) with q = [centre x, y, z, size x, y, z] (mm), whose
/// feasible set is A·q = b, G·q ≤ h built from geosemantic relations stored at the lowest
/// common ancestor of the elements they relate, and whose connection nodes record which
/// connecting elements hold which principal elements together.
///
/// Every subtree is a template by itself: subtree(node) keeps exactly the elements below the
/// node and the relations and connections stored at or below it.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/templates/box.h"
#include "fabkit/templates/source_design.h"

namespace fabkit::templates {

/// A typed index (geometry-central style): ElementId and NodeId do not mix.
template <class Tag>
struct Id {
  int value = -1;
  constexpr Id() = default;
  constexpr explicit Id(int v) : value(v) {}
  constexpr bool valid() const { return value >= 0; }
  constexpr auto operator<=>(const Id&) const = default;
};
struct ElementTag;
struct NodeTag;
struct RelationTag;
struct ConnectionTag;
using ElementId = Id<ElementTag>;
using NodeId = Id<NodeTag>;
using RelationId = Id<RelationTag>;
using ConnectionId = Id<ConnectionTag>;

/// Parameters per element in q.
inline constexpr int kParamsPerElement = 6;
/// Index in q of element `e`'s centre (axis 0..2) or size (axis 0..2).
inline int center_index(ElementId e, int axis) {
  return kParamsPerElement * e.value + axis;
}
inline int size_index(ElementId e, int axis) {
  return kParamsPerElement * e.value + 3 + axis;
}

/// A regular 1D or 2D translational pattern of identical parts (paper Appendix A), stored as
/// one element whose box holds them all. On resize, F recomputes count and spacing.
struct Pattern {
  int dims = 1;                      ///< 1 or 2 directions
  std::array<int, 2> axis{0, 1};     ///< world axis of each direction
  std::array<int, 2> count{1, 1};    ///< parts along each direction (design)
  std::array<double, 2> step{0, 0};  ///< generator translation along each direction, mm (design)
  Vec3 part_size = Vec3::Zero();     ///< one part, mm (design)
  std::array<bool, 3> part_resizable{};  ///< per world axis: can one part be cut there?
  int total() const { return count[0] * (dims == 2 ? count[1] : 1); }
};

/// A leaf of the template tree: the least fabricable unit.
struct Element {
  std::string name;
  PartRole role = PartRole::kPrincipal;
  std::string item;                     ///< catalog item id
  std::vector<std::string> part_names;  ///< the design parts it stands for (several: pattern)
  std::optional<Pattern> pattern;
  std::array<bool, 3> resizable{};       ///< per world axis: may the box change size there?
  std::array<int, 3> item_dim{0, 1, 2};  ///< item dimension (length/width/thickness) per axis
  std::array<double, 3> max_size{};      ///< per axis, mm (resizable: longest stock; else fixed)
  NodeId node;                           ///< its leaf node
  std::string source;                    ///< "design/path" it came from (for transfer)
  ElementId source_element;              ///< its id in the source template
  bool is_principal() const { return role == PartRole::kPrincipal; }
};

/// The kinds of geosemantic relations (paper §3.2, Appendix B) plus the catalog's.
enum class RelationKind {
  kCoplanar,    ///< two prominent planes stay one plane
  kConcentric,  ///< two box centres stay equal along an axis
  kSymmetric,   ///< two elements stay mirror images about a third's centre
  kOrder,       ///< one plane stays on its side of another (no penetration, no swapping)
  kFixedSize,   ///< an item dimension that cannot be resized
  kMaxSize,     ///< a cut piece stays within the longest stock
  kMinSize,     ///< a size stays positive (a pattern keeps at least one part)
  kPlacement,   ///< soft: a connecting element keeps its place on the contact patch
};
/// "coplanar", "concentric", "symmetric", "order", "fixed-size", "max-size", "min-size",
/// "placement".
std::string_view to_string(RelationKind k);

struct LinearTerm {
  int index = 0;  ///< into q
  double coefficient = 0;
};

/// Which plane of an element a relation speaks of.
enum class Side { kMin = -1, kCenter = 0, kMax = 1 };

/// A plane (or centre) of an element, possibly in an articulation's other rest pose.
struct PlaneRef {
  ElementId element;
  int axis = 0;
  Side side = Side::kMin;
  std::string pose;  ///< "" for the design pose, else "<articulation> at <value>"
};

/// One linear relation: Σ terms·q = rhs (equality) or ≤ rhs.
struct Relation {
  RelationKind kind = RelationKind::kCoplanar;
  bool equality = true;
  bool soft = false;  ///< placement relations: minimised, not enforced
  std::vector<LinearTerm> terms;
  double rhs = 0;
  std::vector<PlaneRef> planes;     ///< what it relates (for messages and transfer)
  std::vector<ElementId> elements;  ///< every element in terms
  NodeId node;                      ///< where it is stored (lowest common ancestor)
  ConnectionId connection;          ///< set for relations of a connection
  /// Σ terms·q − rhs.
  double residual(const Eigen::VectorXd& q) const;
};

/// Principal elements held together by connecting elements (paper §3.2 "Connections").
struct Connection {
  std::string name;
  std::vector<ElementId> principal;   ///< in contact (usually two)
  std::vector<ElementId> connecting;  ///< screws, brackets, hinges, slides holding them
  std::vector<RelationId> relations;  ///< hard: connecting ↔ principal and among connecting
  std::vector<RelationId> placement;  ///< soft: connecting elements on the contact patch
  NodeId node;                        ///< lowest common ancestor of the principal elements
  std::string source;                 ///< "design" it was extracted from, or transferred from
};

struct Node {
  std::string name;
  NodeId parent;
  std::vector<NodeId> children;
  std::optional<ElementId> element;   ///< leaves
  bool connection_node = false;       ///< groups a connection's connecting elements
  std::vector<RelationId> relations;  ///< stored here
  std::vector<ConnectionId> connections;
};

/// A moving sub-assembly in template terms: which elements move and how their boxes map in the
/// other rest pose (linear in q, Appendix B).
struct TemplateArticulation {
  std::string name;
  JointType type = JointType::kHinge;
  std::vector<ElementId> moving;
  int axis = 2;
  int direction = 1;
  ElementId pivot_element;             ///< the pivot is anchored on this element's box
  Vec3 pivot_fraction = Vec3::Zero();  ///< pivot = min + fraction ∘ size of that box
  double lower = 0, upper = 0;
};

/// An affine function of q (terms + constant): a coordinate of a box in some pose.
struct AffineExpr {
  std::vector<LinearTerm> terms;
  double constant = 0;
  double value(const Eigen::VectorXd& q) const;
};
/// A box whose centre and size are affine in q.
struct AffineBox {
  std::array<AffineExpr, 3> center, size;
  /// The min (side -1), centre (0) or max (+1) plane along `axis`.
  AffineExpr plane(int axis, Side side) const;
  Box value(const Eigen::VectorXd& q) const;
};

/// One part placed by the deformation function F.
struct PlacedPart {
  std::string name;
  std::string item;
  Box box;
  PartRole role = PartRole::kPrincipal;
  ElementId element;
};

class Template;

/// The box of moving element `e` in the articulation's other rest pose (its upper limit), as
/// an affine function of q (Appendix B: q_j = V·q). Hinges turn by multiples of 90° about the
/// pivot; slides move by the travel.
AffineBox rest_pose_box(const Template& t, const TemplateArticulation& a, ElementId e);
/// "door_hinge at 90°", "drawer_slide at 300 mm".
std::string rest_pose_name(const TemplateArticulation& a);

class Template {
 public:
  std::string name;  ///< design name, or "design/path/to/node" for a sub-template
  std::string title;
  std::string category;
  std::vector<Node> nodes;  ///< nodes[0] is the root
  std::vector<Element> elements;
  std::vector<Relation> relations;
  std::vector<Connection> connections;
  std::vector<TemplateArticulation> articulations;
  Eigen::VectorXd q;  ///< current parameters, 6 per element

  NodeId root() const { return NodeId(0); }
  const Node& node(NodeId n) const { return nodes[n.value]; }
  const Element& element(ElementId e) const { return elements[e.value]; }
  const Relation& relation(RelationId r) const { return relations[r.value]; }
  int element_count() const { return static_cast<int>(elements.size()); }
  /// Parts the current q makes (a pattern counts each of its parts).
  int part_count() const;

  /// "root/base/legs/leg_fl"-style path of a node (without the root's name).
  std::string path(NodeId n) const;
  /// The node at `path` ("" = root; names separated by '/'); invalid id if none.
  NodeId find(std::string_view path) const;
  /// A node or element by its own name when unique, else by path.
  NodeId find_node_or_element(std::string_view name) const;
  /// Elements below (or at) `n`.
  std::vector<ElementId> elements_under(NodeId n) const;
  /// Whether `a` is `b` or an ancestor of it.
  bool is_ancestor(NodeId a, NodeId b) const;
  NodeId lowest_common_ancestor(NodeId a, NodeId b) const;
  /// Nodes from `n` up to the root.
  int depth(NodeId n) const;

  /// An element's box at parameters `at` (default: the current q).
  Box box(ElementId e) const;
  Box box(ElementId e, const Eigen::VectorXd& at) const;
  /// The box of everything below `n`.
  Box node_box(NodeId n) const;
  /// The element's box as an affine function of q (identity map).
  AffineBox affine_box(ElementId e) const;

  /// The parts at the current q: each element through its deformation function F (patterns
  /// recomputed, Appendix A).
  std::vector<PlacedPart> placed_parts() const;

  /// The template rooted at `n`, re-indexed: its elements, the relations and connections stored
  /// at or below it, and its articulations. Its name becomes "<name>/<path>".
  Template subtree(NodeId n) const;

  /// Appends a copy of `other` as a new child of `parent` named `name` (its root renamed);
  /// returns the new node. Elements, relations and connections are re-indexed after this
  /// template's own; q grows by other's parameters.
  NodeId append(const Template& other, NodeId parent, const std::string& name);
  /// This template without the nodes below (and at) `n`, and without every relation and
  /// connection that involves a removed element (a connection's connecting elements go with
  /// it). The root cannot be removed.
  Template without(NodeId n) const;
  /// Adds a connection node under `parent` holding new connecting elements; returns the
  /// connection's id. `elements` and `relations` must already be in this template.
  ConnectionId add_connection(Connection c, NodeId parent);

  /// The problem of moving only `free` (in that order): every relation touching a free
  /// element, with the other elements' terms folded in as constants at the current q. Used to
  /// evaluate local changes (a connection between two elements) on a small QP.
  Template restricted_to(const std::vector<ElementId>& free) const;

  /// Every relation's largest violation at q (equalities |r|, inequalities max(0, r)); hard
  /// relations only.
  double max_violation(const Eigen::VectorXd& at) const;
  double max_violation() const { return max_violation(q); }
};

}  // namespace fabkit::templates
