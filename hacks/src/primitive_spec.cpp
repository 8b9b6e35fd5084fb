#include "fabkit/hacks/primitive_spec.h"

#include <fmt/format.h>

#include <array>

#include "fabkit/core/text.h"
#include "fabkit/hacks/diagnostic_codes.h"

namespace fabkit::hacks {
namespace {

using PT = PrimitiveType;

// Which optional flags and ranges apply to which primitive types (reference §2.2).
bool flag_applies(std::string_view flag, PT t) {
  if (flag == "frame") return true;
  if (flag == "flex") return t == PT::kHook || t == PT::kRing;
  if (flag == "centerline") return t == PT::kRod || t == PT::kRing || t == PT::kTube;
  if (flag == "is_open")
    return t == PT::kRod || t == PT::kHook || t == PT::kTube || t == PT::kSurface;
  if (flag == "open_for_connect") return t == PT::kRod || t == PT::kHook;
  if (flag == "open_ends")
    return t == PT::kRod || t == PT::kHook || t == PT::kTube || t == PT::kEdge;
  if (flag == "theta_range") return t == PT::kHook;
  if (flag == "phi_range") return t == PT::kRod || t == PT::kHook || t == PT::kRing;
  return false;
}

constexpr std::array<std::string_view, 8> kOptionalKeys = {"frame",
                                                           "flex",
                                                           "centerline",
                                                           "is_open",
                                                           "open_for_connect",
                                                           "open_ends",
                                                           "theta_range",
                                                           "phi_range"};

// The reference's defaults (§2.2) for sizes a program leaves out.
void reference_defaults(PT type, PrimitiveShape& shape) {
  switch (type) {
    case PT::kRod:
      shape.radius = 0.5;
      shape.length = 10;
      break;
    case PT::kTube:
      shape.inner_radius = 0.5;
      shape.thickness = 0.1;
      shape.length = 10;
      break;
    case PT::kEdge:
      shape.width = shape.length = shape.height = 10;
      break;
    case PT::kSurface:
      shape.width = shape.length = 100;
      break;
    default:
      break;
  }
}

std::string join(const std::vector<std::string_view>& items) {
  std::string out;
  for (std::string_view s : items) {
    if (!out.empty()) out += ", ";
    out += s;
  }
  return out;
}

}  // namespace

std::vector<std::string_view> primitive_spec_keys(PrimitiveType t) {
  std::vector<std::string_view> out;
  for (std::string_view k : kOptionalKeys) {
    if (flag_applies(k, t)) out.push_back(k);
  }
  return out;
}

std::optional<Primitive> read_primitive_spec(YamlReader& in,
                                             const YAML::Node& spec,
                                             std::string_view owner,
                                             std::optional<std::string> name,
                                             const PrimitiveSpecOptions& options) {
  const int errors_before = in.errors();
  const bool name_in_spec = !name.has_value();
  const std::string prefix = owner.empty() ? "" : fmt::format("{}.", owner);
  if (!spec.IsMap()) {
    in.error(codes::kMalformedInput,
             fmt::format("{}{}: a primitive must be a mapping like {{type: rod, radius: 5, "
                         "length: 500}}",
                         prefix,
                         name.value_or("primitive")),
             in.at(spec));
    return std::nullopt;
  }
  // The name first (messages use it), then the type, which decides the valid keys.
  if (!name) {
    if (const YAML::Node n = spec["name"]) {
      if (auto s = in.string(n, "primitive name", 128)) {
        if (!is_identifier(*s)) {
          in.error(codes::kInvalidValue,
                   fmt::format("primitive name '{}' must be an identifier (letters, digits, _)",
                               excerpt(*s, 60)),
                   in.at(n));
        }
        name = *s;
      }
    } else {
      in.error(codes::kMalformedInput,
               fmt::format("a primitive of {} is missing required key 'name'",
                           owner.empty() ? "this part" : owner),
               in.at(spec));
    }
  }
  const std::string who = prefix + name.value_or("primitive");
  const YAML::Node type_node = spec["type"];
  if (!type_node) {
    in.error(codes::kMalformedInput,
             fmt::format("{}: a primitive needs a 'type' (rod, hook, ring, hole, clip, tube, "
                         "edge, surface or hemisphere)",
                         who),
             in.at(spec));
    return std::nullopt;
  }
  const auto tname = in.string(type_node, "primitive type", 64);
  if (!tname) return std::nullopt;
  const auto type = primitive_type_from_string(*tname);
  if (!type) {
    in.error(codes::kUnknownName,
             fmt::format("{}: unknown primitive type '{}' (expected rod, hook, ring, hole, clip, "
                         "tube, edge, surface or hemisphere)",
                         who,
                         *tname),
             in.at(type_node));
    return std::nullopt;
  }

  const std::vector<std::string_view> fields = shape_field_names(*type);
  std::vector<std::string_view> allowed{"type"};
  if (name_in_spec) allowed.push_back("name");
  allowed.insert(allowed.end(), fields.begin(), fields.end());
  for (std::string_view k : primitive_spec_keys(*type)) allowed.push_back(k);
  in.check_keys(spec, allowed, fmt::format("a {} primitive ({})", to_string(*type), who));

  PrimitiveShape shape;
  if (options.reference_defaults) reference_defaults(*type, shape);
  for (std::string_view f : fields) {
    const YAML::Node v = spec[std::string(f)];
    if (!v) {
      if (options.reference_defaults && shape_field_value(shape, f) > 0) continue;
      in.error(codes::kMalformedInput,
               fmt::format("{}: a {} needs '{}' (a {} takes {})",
                           who,
                           to_string(*type),
                           f,
                           to_string(*type),
                           join(fields)),
               in.at(spec));
      continue;
    }
    const auto x = in.number(v, fmt::format("{} {}", who, f));
    if (!x) continue;
    if (auto problem = shape_field_problem(*type, f, *x, who)) {
      in.error(codes::kInvalidValue, std::move(*problem), in.at(v));
      continue;
    }
    *shape_field(shape, f) = *x;
  }

  Frame frame;
  if (const YAML::Node fn = spec["frame"]) {
    if (auto f = in.frame(fn, fmt::format("{} frame", who))) frame = *f;
  }
  Primitive p = Primitive::make(name.value_or(""), *type, shape, frame);
  auto flag = [&](const char* key) -> std::optional<bool> {
    const YAML::Node v = spec[key];
    if (!v || !flag_applies(key, *type)) return std::nullopt;
    return in.boolean(v, fmt::format("{} {}", who, key));
  };
  if (const auto f = flag("flex")) p.flex = *f;
  if (const auto f = flag("centerline")) p.centerline = *f;
  if (const auto f = flag("is_open")) {
    p.is_open = *f;
    // As in the reference: is_open alone also sets open_for_connect (rods and hooks).
    if (!spec["open_for_connect"] && flag_applies("open_for_connect", *type)) {
      p.open_for_connect = *f;
    }
  }
  if (const auto f = flag("open_for_connect")) p.open_for_connect = *f;
  if (const YAML::Node ends = spec["open_ends"]; ends && flag_applies("open_ends", *type)) {
    if (!ends.IsSequence() || ends.size() != 2) {
      in.error(codes::kMalformedInput,
               fmt::format("{} open_ends must be two flags [start, end], like [true, false]", who),
               in.at(ends));
    } else {
      for (std::size_t i = 0; i < 2; ++i) {
        if (auto b = in.boolean(ends[i], fmt::format("{} open_ends", who))) p.open_ends[i] = *b;
      }
    }
  }
  for (const char* key : {"theta_range", "phi_range"}) {
    const YAML::Node rn = spec[key];
    if (!rn || !flag_applies(key, *type)) continue;
    if (const auto r =
            in.numbers(rn, fmt::format("{} {}", who, key), 2, {-36000, 36000, "degrees"})) {
      const std::array<double, 2> range{(*r)[0], (*r)[1]};
      if (range[0] > range[1]) {
        in.error(codes::kInvalidValue,
                 fmt::format("{} {} [{:g}, {:g}] is not an interval", who, key, range[0], range[1]),
                 in.at(rn));
      }
      (std::string_view(key) == "theta_range" ? p.theta_range : p.phi_range) = range;
    }
  }
  if (in.errors() > errors_before) return std::nullopt;

  // Relational checks (a wire thicker than its arc, absurd sizes) at the primitive's line.
  Diagnostics checks;
  p.validate(who, checks, in.at(spec));
  for (const Diagnostic& d : checks) {
    if (d.severity == Severity::kError) {
      in.error(d.code, d.message, d.where);
    } else {
      in.diagnostics().add(d);
    }
  }
  if (in.errors() > errors_before) return std::nullopt;
  return p;
}

}  // namespace fabkit::hacks
