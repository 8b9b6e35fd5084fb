#pragma once
/// Display meshes of a model's parts (procedural, from each item's `mesh` kind) and the scene
/// written to glTF and STL.

#include <vector>

#include "fabkit/core/gltf.h"
#include "fabkit/templates/catalog.h"
#include "fabkit/templates/template.h"

namespace fabkit::templates {

/// How parts are coloured.
enum class SceneColors {
  kMaterials,  ///< wood, sheet goods and metal by material; connectors blue; unstable parts red
  kStability,  ///< stable principal parts green, unstable red, connectors grey (paper §4.6)
};

struct SceneOptions {
  SceneColors colors = SceneColors::kMaterials;
  /// Per element (as StabilityResult::element_stable); empty: all stable.
  std::vector<char> element_stable;
  /// Added to every z (mm): builds put the model's lowest point on z = 0.
  double lift = 0;
};

/// One closed mesh per part, in world coordinates (mm): boxes for boards and sheets,
/// cylinders for screws, dowels and pipe (along the part's longest axis), wheels (axle along
/// the thinnest), L-brackets as two plates on the faces that touch principal parts, casters as
/// a plate, a fork and a wheel.
TriangleMesh part_mesh(const Template& t, const PlacedPart& part, const Item* item);

/// Every part as a scene object named after it, coloured by `options`.
std::vector<SceneObject> model_scene(const Template& t,
                                     const ItemCatalog& catalog,
                                     const SceneOptions& options = {});

}  // namespace fabkit::templates
