#pragma once
/// One reader for primitive specs, used by design files (`primitives:` of an environment),
/// part files (`primitives:` of a part) and the Python module (Rod({...})), so all three
/// accept the same keys and give the same parts or the same errors:
///
///   {type: hook, arc_radius: 19, arc_angle: 210, thickness: 5, flex: true,
///    frame: {pos: [0, 0, -54.2], rot: [90, 0, 0]}, theta_range: [0, 200]}

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/yaml_reader.h"
#include "fabkit/hacks/primitive.h"

namespace fabkit::hacks {

struct PrimitiveSpecOptions {
  /// Sizes left out take the reference's defaults (§2.2) instead of being an error: the
  /// paper's programs write Surface({"length": 500, "width": 500}) with no thickness.
  bool reference_defaults = false;
};

/// The keys a spec of type `t` may have besides its shape fields (which ones apply depends
/// on the type: `flex` only for hooks and rings, ...).
std::vector<std::string_view> primitive_spec_keys(PrimitiveType t);

/// Reads a primitive spec. `name` is the primitive's name when the caller knows it (a mapping
/// key); nullopt means the spec must carry `name:` itself. `owner` prefixes messages
/// ("rods" → "rods.rod1 radius ..."). Every problem is reported through `in` (file:line);
/// nullopt if any.
std::optional<Primitive> read_primitive_spec(YamlReader& in,
                                             const YAML::Node& spec,
                                             std::string_view owner,
                                             std::optional<std::string> name,
                                             const PrimitiveSpecOptions& options = {});

}  // namespace fabkit::hacks
