#pragma once
/// Turning a source design into a template automatically (paper §3.2, Appendices A and B):
/// leaves and patterns, the hierarchy, connections from proximity, and every geosemantic
/// relation read off the design's geometry and its items.

#include <optional>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/catalog.h"
#include "fabkit/templates/template.h"

namespace fabkit::templates {

struct ExtractOptions {
  double plane_tolerance_mm = 0.05;   ///< planes (and centres) closer than this coincide
  double contact_tolerance_mm = 0.5;  ///< parts closer than this touch
  double overlap_min_mm = 1.0;        ///< order relations need this much overlap across
  int axes = 3;                       ///< 2: relations along x and y only (the paper's 2D table)
  bool find_patterns = true;
  int min_principal_pattern = 3;  ///< fewer identical principal parts are separate elements
  int min_connecting_pattern = 2;
};

/// The template of `design`. Items come from `catalog`; a part whose item id is empty is
/// resizable in every axis (for constructed examples). Unknown items and parts that their item
/// cannot make are input errors naming the part (nullopt).
std::optional<Template> make_template(const SourceDesign& design,
                                      const ItemCatalog* catalog,
                                      Diagnostics& diags,
                                      const ExtractOptions& options = {});

/// Which item dimension lies along each world axis for a part of `size`, or nullopt if the
/// item cannot make it (a fixed dimension differs by more than 0.5 mm, or a resizable one
/// exceeds its largest stock).
std::optional<std::array<int, 3>> item_axes(const Item& item, const Vec3& size);

/// The geosemantic relations between the elements `among` of `t` (coplanarity, concentricity,
/// symmetry, order, in every rest pose), as extracted at the current q; used by extraction and
/// by composition to relate an added template to the working model (paper §4.5). Only pairs
/// with at least one element in `first` and one in `second` are related when both are given.
std::vector<Relation> principal_relations(const Template& t,
                                          const std::vector<ElementId>& first,
                                          const std::vector<ElementId>& second,
                                          const ExtractOptions& options = {});

/// Order relations that keep each element of `first` out of each facing element of `second`
/// (design pose), including pairs that touch: what connecting must not violate (paper §4.5:
/// principal elements may shift to make room for connectors, but not into each other).
std::vector<Relation> non_penetration_relations(const Template& t,
                                                const std::vector<ElementId>& first,
                                                const std::vector<ElementId>& second,
                                                const ExtractOptions& options = {});

/// The hard relations between the connecting and principal elements of a connection (all four
/// plane comparisons per axis) and its soft placement relations on the contact patch.
void connection_relations(const Template& t,
                          const Connection& c,
                          std::vector<Relation>& hard,
                          std::vector<Relation>& soft,
                          const ExtractOptions& options = {});

/// Stores `r` in `t` at the lowest common ancestor of its elements (or at `node` when valid);
/// returns its id.
RelationId store_relation(Template& t, Relation r, NodeId node = NodeId());

}  // namespace fabkit::templates
