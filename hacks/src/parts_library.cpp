#include "fabkit/hacks/parts_library.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <optional>
#include <set>

#include "fabkit/core/mesh_io.h"
#include "fabkit/core/names.h"

namespace fabkit::hacks {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  return out;
}

std::string join(const std::vector<std::string>& items, std::string_view sep = ", ") {
  std::string out;
  for (const std::string& s : items) {
    if (!out.empty()) out += sep;
    out += s;
  }
  return out;
}

bool is_identifier(std::string_view s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(
      s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c) || c == '_'; });
}

// ---------------------------------------------------------------------------------------------
// YAML part files (docs/parts.md).

// Which optional flags and ranges apply to which primitive types (reference §2.2).
bool flag_applies(std::string_view flag, PrimitiveType t) {
  using PT = PrimitiveType;
  if (flag == "flex") return t == PT::kHook || t == PT::kRing;
  if (flag == "centerline") return t == PT::kRod || t == PT::kRing || t == PT::kTube;
  if (flag == "is_open") {
    return t == PT::kRod || t == PT::kHook || t == PT::kTube || t == PT::kSurface;
  }
  if (flag == "open_for_connect") return t == PT::kRod || t == PT::kHook;
  if (flag == "theta_range") return t == PT::kHook;
  if (flag == "phi_range") return t == PT::kRod || t == PT::kHook || t == PT::kRing;
  return false;
}

constexpr std::string_view kPrimitiveOptionalKeys[] = {
    "frame", "flex", "centerline", "is_open", "open_for_connect", "theta_range", "phi_range"};
constexpr std::string_view kPartKeys[] = {
    "name", "description", "category", "mesh", "mass", "center_of_mass", "primitives"};

// Reads one YAML part file, collecting diagnostics with file:line locations.
class PartFileReader {
 public:
  PartFileReader(const std::filesystem::path& path, const PartsLibrary& library, Diagnostics& diags)
      : path_(path), file_(path.string()), library_(library), diags_(diags) {}

  // Parsed parts, or nullopt if anything was wrong.
  std::optional<std::vector<Part>> read() {
    std::ifstream in(path_, std::ios::binary);
    if (!in) {
      error(DiagnosticCode::kUnreadableFile, fmt::format("cannot open part file '{}'", file_), {});
      return std::nullopt;
    }
    YAML::Node root;
    try {
      root = YAML::Load(in);
    } catch (const YAML::Exception& e) {
      SourceLocation where{file_, 0, 0};
      if (e.mark.line >= 0) {
        where.line = e.mark.line + 1;
        where.column = e.mark.column + 1;
      }
      diags_.error(
          DiagnosticCode::kMalformedInput, fmt::format("YAML syntax error: {}", e.msg), where);
      return std::nullopt;
    }
    if (!root.IsMap()) {
      error(DiagnosticCode::kMalformedInput,
            "a part file must be a mapping with a 'parts' list",
            root.IsDefined() && !root.IsNull() ? at(root) : SourceLocation{file_, 1, 0});
      return std::nullopt;
    }
    YAML::Node parts;
    for (const auto& kv : root) {
      const std::string key = kv.first.as<std::string>("");
      if (key == "parts") {
        parts = kv.second;
      } else {
        error(DiagnosticCode::kUnknownName,
              fmt::format("unknown key '{}' at the top level; valid keys: parts", key),
              at(kv.first));
      }
    }
    if (!parts.IsDefined()) {
      error(DiagnosticCode::kMalformedInput, "missing required key 'parts'", at(root));
    } else if (!parts.IsSequence()) {
      error(DiagnosticCode::kMalformedInput, "'parts' must be a list of parts", at(parts));
    } else {
      for (const YAML::Node& node : parts) {
        if (auto part = read_part(node)) result_.push_back(std::move(*part));
      }
    }
    if (errors_ > 0) return std::nullopt;
    return std::move(result_);
  }

 private:
  SourceLocation at(const YAML::Node& node) const {
    const YAML::Mark m = node.Mark();
    if (m.line < 0) return {file_, 0, 0};
    return {file_, m.line + 1, m.column + 1};
  }

  void error(DiagnosticCode code, std::string message, SourceLocation where) {
    if (where.file.empty()) where.file = file_;
    diags_.error(code, std::move(message), std::move(where));
    ++errors_;
  }

  // Key -> (key node, value node) of a mapping; reports keys not in `allowed`.
  struct Entry {
    YAML::Node key;
    YAML::Node value;
  };
  std::map<std::string, Entry> entries(const YAML::Node& map,
                                       const std::vector<std::string>& allowed,
                                       std::string_view what) {
    std::map<std::string, Entry> out;
    for (const auto& kv : map) {
      const std::string key = kv.first.as<std::string>("");
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string msg = fmt::format("unknown key '{}' in {}", key, what);
        const std::string near = closest_name(key, allowed);
        if (!near.empty()) msg += fmt::format(" (did you mean '{}'?)", near);
        msg += fmt::format("; valid keys: {}", join(allowed));
        error(DiagnosticCode::kUnknownName, std::move(msg), at(kv.first));
        continue;
      }
      out[key] = Entry{kv.first, kv.second};
    }
    return out;
  }

  std::optional<std::string> string_value(const YAML::Node& node, std::string_view what) {
    if (!node.IsScalar()) {
      error(DiagnosticCode::kMalformedInput, fmt::format("{} must be a string", what), at(node));
      return std::nullopt;
    }
    return node.Scalar();
  }

  // A number (".nan" and ".inf" parse, so callers check finiteness with their own message).
  std::optional<double> number(const YAML::Node& node, std::string_view what) {
    double v = 0;
    if (!node.IsScalar() || !YAML::convert<double>::decode(node, v)) {
      error(DiagnosticCode::kMalformedInput, fmt::format("{} must be a number", what), at(node));
      return std::nullopt;
    }
    return v;
  }

  std::optional<double> finite_number(const YAML::Node& node, std::string_view what) {
    const auto v = number(node, what);
    if (v && !std::isfinite(*v)) {
      error(DiagnosticCode::kInvalidValue,
            fmt::format("{} is {}, not a finite number", what, *v),
            at(node));
      return std::nullopt;
    }
    return v;
  }

  std::optional<bool> boolean(const YAML::Node& node, std::string_view what) {
    bool b = false;
    if (!node.IsScalar() || !YAML::convert<bool>::decode(node, b)) {
      error(
          DiagnosticCode::kMalformedInput, fmt::format("{} must be true or false", what), at(node));
      return std::nullopt;
    }
    return b;
  }

  // A list of `n` finite numbers.
  std::optional<std::vector<double>> numbers(const YAML::Node& node,
                                             std::size_t n,
                                             std::string_view what) {
    if (!node.IsSequence() || node.size() != n) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("{} must be a list of {} numbers", what, n),
            at(node));
      return std::nullopt;
    }
    std::vector<double> out;
    for (const YAML::Node& item : node) {
      const auto v = finite_number(item, what);
      if (!v) return std::nullopt;
      out.push_back(*v);
    }
    return out;
  }

  std::optional<Vec3> vec3(const YAML::Node& node, std::string_view what) {
    const auto v = numbers(node, 3, what);
    if (!v) return std::nullopt;
    return Vec3((*v)[0], (*v)[1], (*v)[2]);
  }

  std::optional<Part> read_part(const YAML::Node& node) {
    const int errors_before = errors_;
    if (!node.IsMap()) {
      error(DiagnosticCode::kMalformedInput, "each entry of 'parts' must be a mapping", at(node));
      return std::nullopt;
    }
    const auto e = entries(
        node, std::vector<std::string>(std::begin(kPartKeys), std::end(kPartKeys)), "a part");
    Part part;
    part.category = PartCategory::kOther;

    std::string who = "part";
    if (!e.contains("name")) {
      error(DiagnosticCode::kMalformedInput, "part is missing required key 'name'", at(node));
    } else if (const auto name = string_value(e.at("name").value, "part name")) {
      const SourceLocation where = at(e.at("name").value);
      if (!is_identifier(*name)) {
        error(DiagnosticCode::kInvalidValue,
              fmt::format("part name '{}' must be an identifier (letters, digits, _)", *name),
              where);
      } else if (const PartGenerator* existing = library_.find(*name)) {
        error(DiagnosticCode::kDuplicateName,
              fmt::format(
                  "part name '{}' is already used by the library part {}", *name, existing->name),
              where);
      } else if (!names_.insert(lower(*name)).second) {
        error(DiagnosticCode::kDuplicateName,
              fmt::format("part '{}' is defined twice in this file", *name),
              where);
      }
      part.type_name = *name;
      who = *name;
    }
    if (e.contains("description")) {
      if (const auto d = string_value(e.at("description").value, "description")) {
        part.description = *d;
      }
    }
    if (e.contains("category")) {
      if (const auto c = string_value(e.at("category").value, "category")) {
        bool found = false;
        for (PartCategory pc : {PartCategory::kEnvironment,
                                PartCategory::kHack,
                                PartCategory::kBoth,
                                PartCategory::kOther}) {
          if (lower(*c) == to_string(pc)) {
            part.category = pc;
            found = true;
          }
        }
        if (!found) {
          error(DiagnosticCode::kUnknownName,
                fmt::format("unknown category '{}'; valid: environment, hack, both, other", *c),
                at(e.at("category").value));
        }
      }
    }

    // Primitives.
    if (!e.contains("primitives")) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("part {} is missing required key 'primitives'", who),
            at(node));
    } else {
      const YAML::Node& list = e.at("primitives").value;
      if (!list.IsSequence() || list.size() == 0) {
        error(DiagnosticCode::kMalformedInput,
              fmt::format("'primitives' of part {} must be a non-empty list", who),
              at(list));
      } else {
        std::set<std::string> prim_names;
        for (const YAML::Node& pn : list) {
          if (auto p = read_primitive(pn, who, prim_names))
            part.primitives.push_back(std::move(*p));
        }
      }
    }

    // Mesh: from the file if given, else drawn from the primitives.
    std::optional<SourceLocation> mesh_where;
    if (e.contains("mesh")) {
      const YAML::Node& mn = e.at("mesh").value;
      mesh_where = at(mn);
      if (const auto rel = string_value(mn, "mesh")) {
        std::filesystem::path mesh_path(*rel);
        if (mesh_path.is_relative()) mesh_path = path_.parent_path() / mesh_path;
        Diagnostics mesh_diags;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(mesh_path, ec)) {
          error(DiagnosticCode::kUnreadableFile,
                fmt::format("mesh file '{}' of part {} does not exist", mesh_path.string(), who),
                *mesh_where);
        } else if (auto mesh = read_mesh(mesh_path, mesh_diags)) {
          if (mesh->empty()) {
            error(DiagnosticCode::kInvalidValue,
                  fmt::format("mesh file '{}' has no triangles", mesh_path.string()),
                  *mesh_where);
          }
          part.mesh = std::move(*mesh);
        } else {
          const DiagnosticCode code = mesh_diags.empty() ? DiagnosticCode::kUnreadableFile
                                                         : mesh_diags.items().front().code;
          error(code,
                fmt::format("cannot read mesh '{}' of part {}: {}",
                            mesh_path.string(),
                            who,
                            mesh_diags.empty() ? std::string("unknown error")
                                               : mesh_diags.items().front().format()),
                *mesh_where);
        }
      }
    }
    if (errors_ > errors_before) return std::nullopt;
    if (!e.contains("mesh")) {
      for (const Primitive& p : part.primitives) part.mesh.append(primitive_mesh(p));
    }

    // Mass properties: explicit values win; otherwise the mesh at density 1 (reference §10.1).
    if (e.contains("mass")) {
      const YAML::Node& mn = e.at("mass").value;
      if (const auto m = finite_number(mn, "mass")) {
        if (*m <= 0) {
          error(DiagnosticCode::kInvalidValue,
                fmt::format("mass {} of part {} must be positive (mm³ at density 1)", *m, who),
                at(mn));
        }
        part.mass = *m;
      }
    } else {
      part.mass = std::abs(part.mesh.volume());
      if (!(part.mass > 1e-9)) {
        error(DiagnosticCode::kInvalidValue,
              fmt::format("the mesh of part {} encloses no volume; give 'mass' explicitly", who),
              mesh_where.value_or(at(node)));
      }
    }
    if (e.contains("center_of_mass")) {
      if (const auto c = vec3(e.at("center_of_mass").value, "center_of_mass")) {
        part.center_of_mass = *c;
      }
    } else {
      part.center_of_mass = part.mesh.centroid();
    }
    if (errors_ > errors_before) return std::nullopt;
    return part;
  }

  std::optional<Primitive> read_primitive(const YAML::Node& node,
                                          const std::string& part_name,
                                          std::set<std::string>& names) {
    const int errors_before = errors_;
    if (!node.IsMap()) {
      error(DiagnosticCode::kMalformedInput, "each primitive must be a mapping", at(node));
      return std::nullopt;
    }
    // The type decides which keys are valid, so read it first.
    std::optional<PrimitiveType> type;
    const YAML::Node type_node = node["type"];
    if (!type_node.IsDefined()) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("a primitive of part {} is missing required key 'type'", part_name),
            at(node));
      return std::nullopt;
    }
    if (const auto t = string_value(type_node, "primitive type")) {
      type = primitive_type_from_string(*t);
      if (!type) {
        error(DiagnosticCode::kUnknownName,
              fmt::format("unknown primitive type '{}'; valid types: rod, hook, ring (or hole), "
                          "clip, tube, edge, surface, hemisphere",
                          *t),
              at(type_node));
      }
    }
    if (!type) return std::nullopt;

    std::vector<std::string> allowed{"name", "type"};
    for (std::string_view f : shape_field_names(*type)) allowed.emplace_back(f);
    for (std::string_view k : kPrimitiveOptionalKeys) {
      if (k == "frame" || flag_applies(k, *type)) allowed.emplace_back(k);
    }
    const auto e = entries(node, allowed, fmt::format("a {} primitive", to_string(*type)));

    std::string name;
    if (!e.contains("name")) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("a primitive of part {} is missing required key 'name'", part_name),
            at(node));
    } else if (const auto n = string_value(e.at("name").value, "primitive name")) {
      name = *n;
      if (!is_identifier(name)) {
        error(DiagnosticCode::kInvalidValue,
              fmt::format("primitive name '{}' must be an identifier (letters, digits, _)", name),
              at(e.at("name").value));
      } else if (!names.insert(name).second) {
        error(DiagnosticCode::kDuplicateName,
              fmt::format("part {} has two primitives called '{}'", part_name, name),
              at(e.at("name").value));
      }
    }
    const std::string who = fmt::format("{}.{}", part_name, name);

    std::vector<std::string> shape_fields;
    for (std::string_view f : shape_field_names(*type)) shape_fields.emplace_back(f);
    PrimitiveShape shape;
    for (const std::string& field : shape_fields) {
      if (!e.contains(field)) {
        error(DiagnosticCode::kMalformedInput,
              fmt::format("{} primitive {} is missing required key '{}' (a {} needs {})",
                          to_string(*type),
                          who,
                          field,
                          to_string(*type),
                          join(shape_fields)),
              at(node));
        continue;
      }
      const YAML::Node& vn = e.at(field).value;
      const auto v = finite_number(vn, fmt::format("{} {}", who, field));
      if (!v) continue;
      const bool angle = field == "arc_angle";
      if (*v <= 0 || (angle && *v > 360)) {
        error(DiagnosticCode::kInvalidValue,
              angle ? fmt::format("{} arc_angle {}° must be in (0, 360]", who, *v)
                    : fmt::format("{} {} {} mm must be positive", who, field, *v),
              at(vn));
        continue;
      }
      *shape_field(shape, field) = *v;
    }

    Frame frame;
    if (e.contains("frame")) {
      const YAML::Node& fn = e.at("frame").value;
      if (!fn.IsMap()) {
        error(DiagnosticCode::kMalformedInput,
              "frame must be a mapping {pos: [x, y, z], rot: [a, b, c]}",
              at(fn));
      } else {
        const auto fe = entries(fn, {"pos", "rot"}, "a frame");
        if (fe.contains("pos")) {
          if (const auto p = vec3(fe.at("pos").value, "frame pos")) frame.pos = *p;
        }
        if (fe.contains("rot")) {
          if (const auto r = vec3(fe.at("rot").value, "frame rot")) frame.rot = *r;
        }
      }
    }

    Primitive prim = Primitive::make(name, *type, shape, frame);
    auto flag = [&](const char* key) -> std::optional<bool> {
      if (!e.contains(key)) return std::nullopt;
      return boolean(e.at(key).value, key);
    };
    if (const auto f = flag("flex")) prim.flex = *f;
    if (const auto f = flag("centerline")) prim.centerline = *f;
    const auto is_open = flag("is_open");
    const auto open_for_connect = flag("open_for_connect");
    if (is_open) {
      prim.is_open = *is_open;
      // As in the reference: is_open alone also sets open_for_connect (rods and hooks).
      if (!e.contains("open_for_connect") && flag_applies("open_for_connect", *type)) {
        prim.open_for_connect = *is_open;
      }
    }
    if (open_for_connect) prim.open_for_connect = *open_for_connect;
    for (const char* key : {"theta_range", "phi_range"}) {
      if (!e.contains(key)) continue;
      if (const auto r = numbers(e.at(key).value, 2, key)) {
        const std::array<double, 2> range{(*r)[0], (*r)[1]};
        if (range[0] > range[1]) {
          error(DiagnosticCode::kInvalidValue,
                fmt::format("{} {} [{}, {}] is not an interval", who, key, range[0], range[1]),
                at(e.at(key).value));
        }
        (std::string_view(key) == "theta_range" ? prim.theta_range : prim.phi_range) = range;
      }
    }
    if (errors_ > errors_before) return std::nullopt;

    // Relational checks (wire thinner than its arc, absurd sizes) at the primitive's line.
    Diagnostics checks;
    prim.validate(who, checks, at(node));
    for (const Diagnostic& d : checks) {
      if (d.severity == Severity::kError) ++errors_;
      diags_.add(d);
    }
    if (errors_ > errors_before) return std::nullopt;
    return prim;
  }

  std::filesystem::path path_;
  std::string file_;
  const PartsLibrary& library_;
  Diagnostics& diags_;
  int errors_ = 0;
  std::set<std::string> names_;  // lower-case part names defined in this file
  std::vector<Part> result_;
};

}  // namespace

const PartsLibrary& PartsLibrary::builtin() {
  static const PartsLibrary library = [] {
    PartsLibrary lib;
    register_builtin_parts(lib);
    return lib;
  }();
  return library;
}

void PartsLibrary::add(PartGenerator generator) {
  // A generator of the same name replaces the old one, so names stay unique.
  for (PartGenerator& g : generators_) {
    if (g.name == generator.name) {
      g = std::move(generator);
      return;
    }
  }
  generators_.push_back(std::move(generator));
}

const PartGenerator* PartsLibrary::find(std::string_view name) const {
  for (const PartGenerator& g : generators_) {
    if (g.name == name) return &g;
  }
  for (const PartGenerator& g : generators_) {
    for (const std::string& a : g.aliases) {
      if (a == name) return &g;
    }
  }
  const std::string l = lower(name);
  for (const PartGenerator& g : generators_) {
    if (lower(g.name) == l) return &g;
    for (const std::string& a : g.aliases) {
      if (lower(a) == l) return &g;
    }
  }
  return nullptr;
}

std::string PartsLibrary::suggest(std::string_view name) const {
  std::vector<std::string> candidates;
  for (const PartGenerator& g : generators_) candidates.push_back(g.name);
  for (const PartGenerator& g : generators_) {
    candidates.insert(candidates.end(), g.aliases.begin(), g.aliases.end());
  }
  return closest_name(name, candidates);
}

std::shared_ptr<Part> PartsLibrary::make(std::string_view name,
                                         const ParamValues& params,
                                         Diagnostics& diags,
                                         const SourceLocation& where) const {
  const PartGenerator* gen = find(name);
  if (gen == nullptr) {
    std::string msg = fmt::format("unknown part '{}'", name);
    const std::string near = suggest(name);
    if (!near.empty()) msg += fmt::format("; did you mean {}?", near);
    diags.error(DiagnosticCode::kUnknownPart, std::move(msg), where);
    return nullptr;
  }

  bool ok = true;
  std::vector<std::string> valid;
  for (const ParamSchema& s : gen->params) valid.push_back(s.name);
  for (const auto& [key, value] : params) {
    const auto it = std::find_if(gen->params.begin(), gen->params.end(), [&](const ParamSchema& s) {
      return s.name == key;
    });
    if (it == gen->params.end()) {
      std::string msg;
      if (valid.empty()) {
        msg = fmt::format("part {} has no parameters (got '{}')", gen->name, key);
      } else {
        msg = fmt::format("part {} has no parameter '{}'", gen->name, key);
        const std::string near = closest_name(key, valid);
        if (!near.empty()) msg += fmt::format(" (did you mean '{}'?)", near);
        msg += fmt::format("; valid parameters: {}", join(valid));
      }
      diags.error(DiagnosticCode::kUnknownName, std::move(msg), where);
      ok = false;
      continue;
    }
    const ParamSchema& s = *it;
    if (!std::isfinite(value)) {
      diags.error(DiagnosticCode::kInvalidValue,
                  fmt::format("{} {} = {} is not a finite number; expected {:g} to {:g} {}",
                              gen->name,
                              key,
                              value,
                              s.min,
                              s.max,
                              s.unit),
                  where);
      ok = false;
    } else if (value < s.min || value > s.max) {
      diags.error(DiagnosticCode::kInvalidValue,
                  fmt::format("{} {} = {:g} {} is out of range [{:g}, {:g}] {}",
                              gen->name,
                              key,
                              value,
                              s.unit,
                              s.min,
                              s.max,
                              s.unit),
                  where);
      ok = false;
    }
  }
  if (!ok) return nullptr;

  ParamValues values;
  for (const ParamSchema& s : gen->params) {
    const auto it = params.find(s.name);
    values[s.name] = it != params.end() ? it->second : s.default_value;
  }
  Part part = gen->build(values);
  part.type_name = gen->name;
  part.category = gen->category;
  if (part.description.empty()) part.description = gen->description;
  if (!gen->params.empty()) part.params = values;

  // Parameter combinations can still produce impossible geometry (a hanger shorter than its
  // bends); report it per primitive rather than building a broken part.
  Diagnostics checks;
  for (const Primitive& p : part.primitives) {
    p.validate(fmt::format("{}.{}", gen->name, p.name), checks, where);
  }
  diags.append(checks);
  if (checks.has_errors()) return nullptr;
  return std::make_shared<Part>(std::move(part));
}

bool PartsLibrary::load_yaml(const std::filesystem::path& path, Diagnostics& diags) {
  PartFileReader reader(path, *this, diags);
  auto parts = reader.read();
  if (!parts) return false;
  for (Part& part : *parts) {
    PartGenerator g;
    g.name = part.type_name;
    g.description = part.description;
    g.category = part.category;
    auto shared = std::make_shared<const Part>(std::move(part));
    g.build = [shared](const ParamValues&) { return *shared; };
    add(std::move(g));
  }
  return true;
}

}  // namespace fabkit::hacks
