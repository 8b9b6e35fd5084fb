#pragma once
/// The template database: an items catalog plus source designs, each turned into a template
/// tree whose every node is a template by itself (paper §3.2, end). The bundled database is
/// compiled into fabkit from templates/data; a user's directory of designs can sit beside it.

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/catalog.h"
#include "fabkit/templates/extract.h"
#include "fabkit/templates/source_design.h"
#include "fabkit/templates/template.h"

namespace fabkit::templates {

/// A connection of some template in the database with its retrieval descriptor (paper §4.5):
/// the materials and box sizes of its two principal elements, which sizes the template
/// constrains, and the four plane distances per axis between them.
struct ConnectionExample {
  std::string design;       ///< the template it belongs to
  ConnectionId connection;  ///< in that design's template
  std::array<ElementId, 2> principal;
  std::array<std::string, 2> material;             ///< material class: wood, metal, plastic, ...
  std::array<Vec3, 2> size;                        ///< mm
  std::array<std::array<bool, 3>, 2> constrained;  ///< fixed-size axes
  std::array<std::array<double, 4>, 3> planes;  ///< per axis: min−min, min−max, max−min, max−max
};

/// "wood", "metal", "plastic", "rubber", "glass" from a catalog material ("birch plywood").
std::string material_class(std::string_view material);

class TemplateDatabase {
 public:
  /// The bundled database (catalog and designs compiled in); built once, on first use.
  static const TemplateDatabase& bundled();
  /// A database of `designs` (YAML texts with their file names) over `catalog`. Designs that
  /// fail to read or extract are reported and left out; nullopt only if none is usable.
  static std::optional<TemplateDatabase> load(
      const ItemCatalog& catalog,
      const std::vector<std::pair<std::string, std::string>>& designs,
      Diagnostics& diags);
  /// The bundled designs plus every *.yaml design in `directory`.
  static std::optional<TemplateDatabase> with_directory(const std::filesystem::path& directory,
                                                        const ItemCatalog& catalog,
                                                        Diagnostics& diags);

  const ItemCatalog& catalog() const { return catalog_; }
  /// Design names, sorted.
  std::vector<std::string> names() const;
  const SourceDesign* design(std::string_view name) const;
  /// The full template of a design.
  const Template* source_template(std::string_view name) const;
  /// A template by "design" or "design/path/to/node" (a sub-template); an unknown-template
  /// diagnostic with a suggestion when there is none.
  std::optional<Template> find(std::string_view spec, Diagnostics& diags) const;
  /// Every connection in the database with its descriptor.
  const std::vector<ConnectionExample>& connection_examples() const { return examples_; }

 private:
  ItemCatalog catalog_ = ItemCatalog::bundled();
  std::map<std::string, SourceDesign, std::less<>> designs_;
  std::map<std::string, Template, std::less<>> templates_;
  std::vector<ConnectionExample> examples_;
  void index();
};

/// The descriptor of the pair (a, b) of elements of `t` at its current q.
ConnectionExample describe_pair(const Template& t,
                                const ItemCatalog& catalog,
                                ElementId a,
                                ElementId b);
/// The weighted descriptor distance (paper §4.5): infinite when materials differ; sizes
/// weighted 3× along constrained axes; plane distances compare order and coplanarity.
/// `swapped` is set when the example matches with its principal elements exchanged.
double descriptor_distance(const ConnectionExample& query,
                           const ConnectionExample& example,
                           bool* swapped = nullptr);

}  // namespace fabkit::templates

namespace fabkit::templates {

/// A readable summary of a template: its tree (elements with items, sizes and visible
/// controls), its connections with their connecting parts, and counts of relations by kind.
std::string describe_template(const Template& t, const ItemCatalog& catalog);

}  // namespace fabkit::templates
