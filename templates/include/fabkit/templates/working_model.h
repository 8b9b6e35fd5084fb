#pragma once
/// The working model (paper §4.1, §4.3): a template composed from templates of the database.
/// Each added template becomes a child of the root; snapping (snap.h) positions and sizes it,
/// connecting (connect.h) finds the connectors and relations that join it to the rest, and the
/// result stays a template, so manipulate.h keeps working on the whole.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/template.h"

namespace fabkit::templates {

/// One template added to the model.
struct Composition {
  std::string name;    ///< its name in the model ("shelf")
  std::string source;  ///< what was added ("bookshelf/shelves/bottom_shelf")
  NodeId node;         ///< its node in the model
};

class WorkingModel {
 public:
  explicit WorkingModel(std::string name = "model");

  const Template& model() const { return model_; }
  /// For manipulation: set model().q through this (every relation must keep holding).
  Template& model() { return model_; }

  /// Adds a copy of `part` as a child of the root named `name`; with `at`, it is translated so
  /// that its box centre is there (mm). Returns the composition, or nullopt with a
  /// duplicate-name diagnostic.
  std::optional<Composition> add(const Template& part,
                                 std::string_view source,
                                 const std::string& name,
                                 std::optional<Vec3> at,
                                 Diagnostics& diags);
  /// Removes a composition (or any node): its elements and every relation and connection
  /// that involves them (paper §4.3).
  bool remove(std::string_view node, Diagnostics& diags);

  const std::vector<Composition>& compositions() const { return compositions_; }
  const Composition* composition(std::string_view name) const;
  /// The elements of a composition.
  std::vector<ElementId> elements_of(const Composition& c) const;

 private:
  Template model_;
  std::vector<Composition> compositions_;
};

}  // namespace fabkit::templates
