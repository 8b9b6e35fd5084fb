// Reading and writing flatpack design files through the core YAML reader.
#include "fabkit/flatpack/design_file.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>

#include "fabkit/core/file_io.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/flatpack/diagnostic_codes.h"

namespace fabkit::flatpack {
namespace {

constexpr std::array<std::string_view, 4> kKits = {"hacks", "rods", "flatpack", "templates"};

Design load_nested(std::string_view yaml,
                   std::string_view display_name,
                   Diagnostics& diags,
                   const std::filesystem::path& base_dir,
                   const DesignFileOptions& options,
                   int depth,
                   std::vector<std::filesystem::path>& chain);

// A file's identity for finding designs that use themselves (symlinks and ../ resolved).
std::filesystem::path identity(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::weakly_canonical(path, ec);
  return ec ? path.lexically_normal() : p;
}

struct Reader {
  YamlReader& in;
  const std::filesystem::path& base_dir;
  const DesignFileOptions& options;
  int depth;  ///< 0 for the design the user gave; +1 per level of `uses:`
  std::vector<std::filesystem::path>& chain;  ///< the files being read, outermost first

  std::optional<Expression> expr(const YAML::Node& node, std::string_view what) {
    if (!node.IsScalar()) {
      in.error(codes::kInvalidValue,
               fmt::format("{} must be a number or an expression", what),
               in.at(node));
      return std::nullopt;
    }
    // Valid UTF-8 of a sane length, so that messages quoting it are too.
    const auto text = in.string(node, fmt::format("{} (an expression)", what), 1000);
    if (!text) return std::nullopt;
    return Expression{*text, in.at(node)};
  }

  std::optional<Material> material(const YAML::Node& node, Material m) {
    if (!in.is_mapping(node, "a material")) return std::nullopt;
    in.check_keys(node, {"name", "thickness", "kerf", "interference"}, "a material");
    if (node["name"]) {
      if (auto n = in.name(node["name"], "material name")) m.name = *n;
    }
    if (node["thickness"]) {
      if (auto v = in.number(node["thickness"],
                             "material thickness",
                             {.min = 0, .max = 200, .unit = "mm", .exclusive_min = true}))
        m.thickness_mm = *v;
    }
    if (node["kerf"]) {
      if (auto v = in.number(node["kerf"], "kerf (per side)", {.min = 0, .max = 5, .unit = "mm"}))
        m.kerf_mm = *v;
    }
    if (node["interference"]) {
      if (auto v =
              in.number(node["interference"], "interference", {.min = -2, .max = 2, .unit = "mm"}))
        m.interference_mm = *v;
    }
    return m;
  }

  void read(const YAML::Node& root, Design& d) {
    static constexpr std::array<std::string_view, 14> kKeys = {"fabkit",
                                                               "name",
                                                               "description",
                                                               "parameters",
                                                               "material",
                                                               "materials",
                                                               "uses",
                                                               "components",
                                                               "constraints",
                                                               "connections",
                                                               "interfaces",
                                                               "joints",
                                                               "labels",
                                                               "sheet"};
    in.check_keys(root, kKeys, "a flatpack design");
    if (root["name"]) {
      if (auto s = in.string(root["name"], "design name")) d.name = *s;
    }
    if (root["description"]) {
      if (auto s = in.string(root["description"], "description", 65536)) d.description = *s;
    }
    if (const YAML::Node ps = root["parameters"]; ps && in.is_mapping(ps, "parameters")) {
      for (const auto& kv : ps) {
        DesignParameter p;
        const auto name = in.name(kv.first, "parameter name");
        if (!name) continue;
        p.name = *name;
        p.where = in.at(kv.first);
        const YAML::Node& v = kv.second;
        if (v.IsScalar()) {
          p.value = in.number(v,
                              fmt::format("parameter {}", p.name),
                              {.min = -kMaxCoordinateMm, .max = kMaxCoordinateMm, .unit = "mm"});
        } else if (in.is_mapping(v, fmt::format("parameter {}", p.name))) {
          in.check_keys(
              v, {"value", "type", "meta", "description"}, fmt::format("parameter {}", p.name));
          if (v["value"])
            p.value = in.number(v["value"],
                                fmt::format("parameter {}", p.name),
                                {.min = -kMaxCoordinateMm, .max = kMaxCoordinateMm, .unit = "mm"});
          if (v["type"]) {
            const auto t = in.string(v["type"], "parameter type");
            const auto kind = t ? param_kind_from_string(*t) : std::nullopt;
            if (t && !kind) {
              in.error(
                  codes::kInvalidValue,
                  fmt::format("parameter {}: type '{}' is not one of length, angle, count, number",
                              p.name,
                              *t),
                  in.at(v["type"]));
            }
            if (kind) p.kind = *kind;
          }
          if (v["meta"]) p.meta = in.boolean(v["meta"], "meta").value_or(false);
          if (v["description"])
            p.description = in.string(v["description"], "description").value_or("");
        }
        d.parameters.push_back(std::move(p));
      }
    }
    if (root["material"]) {
      if (auto m = material(root["material"], d.material)) d.material = *m;
    }
    if (const YAML::Node ms = root["materials"]; ms && in.is_list(ms, "materials")) {
      for (const YAML::Node& m : ms) {
        if (auto mm = material(m, d.material)) d.materials.push_back(*mm);
      }
    }
    if (const YAML::Node us = root["uses"];
        us && in.is_mapping(us, "uses (type name: design file)")) {
      for (const auto& kv : us) {
        const auto type = in.name(kv.first, "type name");
        const auto file = in.string(kv.second, "design file");
        if (!type || !file) continue;
        if (!options.allow_uses) {
          in.error(codes::kInvalidValue,
                   "designs sent here may not read other files (uses:)",
                   in.at(kv.first));
          continue;
        }
        if (depth >= options.max_depth) {
          in.error(codes::kLimitExceeded,
                   fmt::format("designs used as components nest deeper than {} levels here ({} "
                               "uses {})",
                               options.max_depth,
                               in.file(),
                               *file),
                   in.at(kv.second));
          continue;
        }
        const std::filesystem::path path = base_dir / *file;
        const std::filesystem::path id = identity(path);
        if (const auto again = std::find(chain.begin(), chain.end(), id); again != chain.end()) {
          std::vector<std::string> names;
          for (auto it = again; it != chain.end(); ++it) names.push_back(it->filename().string());
          names.push_back(id.filename().string());
          in.error(
              codes::kInvalidValue,
              fmt::format("component type {} ({}) would contain itself: {}; a design cannot be "
                          "a component of itself",
                          *type,
                          *file,
                          fmt::join(names, " uses ")),
              in.at(kv.second));
          continue;
        }
        Diagnostics sub;
        auto text = read_input_file(path, "design file", sub);
        std::shared_ptr<Design> used = std::make_shared<Design>();
        if (text) {
          chain.push_back(id);
          *used =
              load_nested(*text, path.string(), sub, path.parent_path(), options, depth + 1, chain);
          chain.pop_back();
          used->source = path;
        }
        for (Diagnostic dg : sub) {
          // A file that cannot be read is reported where it is named.
          if (!dg.where.known() || dg.where.line == 0) dg.where = in.at(kv.second);
          in.diagnostics().add(dg);
        }
        if (sub.has_errors()) {
          in.error(codes::kUnreadableFile,
                   fmt::format("cannot use {} as component type {}", path.string(), *type),
                   in.at(kv.second));
          continue;
        }
        d.library[*type] = used;
      }
    }
    if (const YAML::Node cs = root["components"]; cs && in.is_list(cs, "components")) {
      for (const YAML::Node& c : cs) {
        if (!in.is_mapping(c, "a component")) continue;
        ComponentUse u;
        u.where = in.at(c);
        if (!in.require(c, "name", "a component") || !in.require(c, "type", "a component"))
          continue;
        u.name = in.name(c["name"], "component name").value_or("");
        u.type = in.name(c["type"], "component type").value_or("");
        for (const auto& kv : c) {
          const auto name = in.name(kv.first, "a component's key");
          if (!name) continue;
          const std::string key = *name;
          if (key == "name" || key == "type") continue;
          if (key == "material") {
            u.material = in.name(kv.second, "material name").value_or("");
          } else if (key == "points") {
            if (!in.is_list(kv.second, "points")) continue;
            for (const YAML::Node& pt : kv.second) {
              if (auto xy =
                      in.numbers(pt,
                                 "a point [x, y]",
                                 2,
                                 {.min = -kMaxCoordinateMm, .max = kMaxCoordinateMm, .unit = "mm"}))
                u.points.emplace_back((*xy)[0], (*xy)[1]);
            }
          } else if (key == "edges") {
            if (!in.is_list(kv.second, "edge names")) continue;
            for (const YAML::Node& e : kv.second)
              u.edge_names.push_back(in.name(e, "edge name").value_or(""));
          } else if (key == "cutouts") {
            if (!in.is_list(kv.second, "cutouts")) continue;
            for (const YAML::Node& co : kv.second) {
              Cutout cut;
              cut.where = in.at(co);
              if (!in.is_mapping(co, "a cutout")) continue;
              in.check_keys(co, {"rectangle", "circle"}, "a cutout");
              const bool circ = static_cast<bool>(co["circle"]);
              const YAML::Node body = circ ? co["circle"] : co["rectangle"];
              if (!body || !in.is_mapping(body, "a cutout")) continue;
              cut.shape = circ ? Cutout::Shape::kCircle : Cutout::Shape::kRectangle;
              in.check_keys(body,
                            circ ? std::initializer_list<std::string_view>{"at", "d"}
                                 : std::initializer_list<std::string_view>{"at", "size"},
                            "a cutout");
              const YAML::Node at = body["at"];
              if (at && at.IsSequence() && at.size() == 2) {
                cut.at = {expr(at[0], "x").value_or(Expression{}),
                          expr(at[1], "y").value_or(Expression{})};
              } else {
                in.error(codes::kInvalidValue, "a cutout needs at: [x, y]", cut.where);
              }
              if (circ) {
                if (body["d"]) cut.size[0] = expr(body["d"], "diameter").value_or(Expression{});
              } else if (const YAML::Node sz = body["size"];
                         sz && sz.IsSequence() && sz.size() == 2) {
                cut.size = {expr(sz[0], "width").value_or(Expression{}),
                            expr(sz[1], "height").value_or(Expression{})};
              } else {
                in.error(codes::kInvalidValue,
                         "a rectangular cutout needs size: [width, height]",
                         cut.where);
              }
              u.cutouts.push_back(std::move(cut));
            }
          } else if (auto e = expr(kv.second, fmt::format("{}.{}", u.name, key))) {
            e->where = in.at(kv.second);
            u.params[key] = *e;
          }
        }
        d.components.push_back(std::move(u));
      }
    }
    if (const YAML::Node cs = root["constraints"]; cs && in.is_list(cs, "constraints")) {
      for (const YAML::Node& c : cs) {
        const auto text = in.string(c, "a constraint 'lhs = rhs'");
        if (!text) continue;
        const auto eq = text->find('=');
        if (eq == std::string::npos || text->find('=', eq + 1) != std::string::npos) {
          in.error(codes::kBadExpression,
                   fmt::format("a constraint must be 'left = right' with one '=', not '{}'", *text),
                   in.at(c));
          continue;
        }
        auto trim = [](std::string s) {
          const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
          return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
        };
        d.constraints.push_back({Expression{trim(text->substr(0, eq)), in.at(c)},
                                 Expression{trim(text->substr(eq + 1)), in.at(c)},
                                 in.at(c)});
      }
    }
    if (const YAML::Node cs = root["connections"]; cs && in.is_list(cs, "connections")) {
      for (const YAML::Node& c : cs) {
        if (!in.is_mapping(c, "a connection")) continue;
        in.check_keys(
            c, {"connect", "alignment", "offset", "rotation", "name", "joint"}, "a connection");
        Connection con;
        con.where = in.at(c);
        if (c["name"]) con.name = in.name(c["name"], "connection name").value_or("");
        const YAML::Node ends = c["connect"];
        if (!ends || !ends.IsSequence() || ends.size() != 2) {
          in.error(
              codes::kMalformedInput, "a connection needs connect: [A.edge, B.edge]", con.where);
          continue;
        }
        bool good = true;
        for (int k = 0; k < 2; ++k) {
          const auto s = in.string(ends[k], "component.edge");
          const auto dot = s ? s->rfind('.') : std::string::npos;
          if (!s || dot == std::string::npos || dot == 0 || dot + 1 == s->size()) {
            in.error(codes::kMalformedInput,
                     "connection ends are written component.edge (like A.t)",
                     in.at(ends[k]));
            good = false;
            continue;
          }
          (k == 0 ? con.a_component : con.b_component) = s->substr(0, dot);
          (k == 0 ? con.a_edge : con.b_edge) = s->substr(dot + 1);
        }
        if (c["alignment"]) {
          const auto s = in.string(c["alignment"], "alignment");
          const auto a = s ? alignment_from_string(*s) : std::nullopt;
          if (!a) {
            in.error(codes::kInvalidValue,
                     fmt::format("alignment must be front-front or front-back{}",
                                 s ? fmt::format(", not '{}'", *s) : ""),
                     in.at(c["alignment"]));
            good = false;
          } else {
            con.alignment = *a;
          }
        }
        if (c["joint"]) {
          const auto s = in.string(c["joint"], "joint");
          if (s && *s == "none") {
            con.places_only = true;
          } else if (s) {
            in.error(codes::kInvalidValue,
                     fmt::format("joint: '{}' is not known; a connection's joint is found from the "
                                 "geometry, and only 'none' (the connection only places) can be "
                                 "written",
                                 *s),
                     in.at(c["joint"]));
            good = false;
          }
        }
        for (const char* key : {"offset", "rotation"}) {
          const YAML::Node v = c[key];
          if (!v) continue;
          if (!v.IsSequence() || v.size() != 3) {
            in.error(codes::kInvalidValue, fmt::format("{} must be [x, y, z]", key), in.at(v));
            good = false;
            continue;
          }
          for (std::size_t k = 0; k < 3; ++k) {
            auto e = expr(v[k], key);
            if (!e)
              good = false;
            else
              (std::string_view(key) == "offset" ? con.offset : con.rotation)[k] = *e;
          }
        }
        if (good) d.connections.push_back(std::move(con));
      }
    }
    if (const YAML::Node is = root["interfaces"]; is && in.is_mapping(is, "interfaces")) {
      for (const auto& kv : is) {
        const auto n = in.name(kv.first, "interface name");
        const auto t = in.string(kv.second, "component.edge");
        if (!n || !t) continue;
        if (t->find('.') == std::string::npos) {
          in.error(codes::kMalformedInput, "an interface names component.edge", in.at(kv.second));
          continue;
        }
        d.interfaces[*n] = *t;
      }
    }
    if (const YAML::Node j = root["joints"]; j && in.is_mapping(j, "joints")) {
      in.check_keys(j, {"finger_width", "end_margin", "dogbone", "angle_tolerance"}, "joints");
      if (j["finger_width"])
        d.joints.finger_width_mm =
            in.number(j["finger_width"], "finger width", {.min = 0, .max = 1000, .unit = "mm"})
                .value_or(0);
      if (j["end_margin"])
        d.joints.end_margin_mm =
            in.number(j["end_margin"], "end margin", {.min = 0, .max = 1000, .unit = "mm"})
                .value_or(0);
      if (j["dogbone"])
        d.joints.dogbone_tool_mm =
            in.number(j["dogbone"], "dog-bone tool diameter", {.min = 0, .max = 50, .unit = "mm"})
                .value_or(0);
      if (j["angle_tolerance"])
        d.joints.angle_tolerance_deg =
            in.number(
                  j["angle_tolerance"], "angle tolerance", {.min = 0, .max = 45, .unit = "degrees"})
                .value_or(0.5);
    }
    if (const YAML::Node l = root["labels"]; l && in.is_mapping(l, "labels")) {
      in.check_keys(l, {"names", "marks", "height"}, "labels");
      if (l["names"]) d.labels.piece_names = in.boolean(l["names"], "names").value_or(true);
      if (l["marks"]) d.labels.assembly_marks = in.boolean(l["marks"], "marks").value_or(true);
      if (l["height"])
        d.labels.height_mm =
            in.number(l["height"], "label height", {.min = 0, .max = 100, .unit = "mm"})
                .value_or(0);
    }
    if (const YAML::Node s = root["sheet"]; s && in.is_mapping(s, "sheet")) {
      in.check_keys(s, {"width", "height", "spacing", "margin", "rotations", "accuracy"}, "sheet");
      const NumberRange size{.min = 0, .max = 1e5, .unit = "mm", .exclusive_min = true};
      if (s["width"])
        d.sheet.sheet_width_mm = in.number(s["width"], "sheet width", size).value_or(600);
      if (s["height"])
        d.sheet.sheet_height_mm = in.number(s["height"], "sheet height", size).value_or(400);
      if (s["spacing"])
        d.sheet.spacing_mm =
            in.number(s["spacing"], "sheet spacing", {.min = 0, .max = 1000, .unit = "mm"})
                .value_or(3);
      if (s["margin"])
        d.sheet.margin_mm =
            in.number(s["margin"], "sheet margin", {.min = 0, .max = 1000, .unit = "mm"})
                .value_or(5);
      if (s["rotations"])
        d.sheet.rotations_deg =
            in.numbers(
                  s["rotations"], "rotations", 0, {.min = -360, .max = 360, .unit = "degrees"}, 36)
                .value_or(d.sheet.rotations_deg);
      if (s["accuracy"])
        d.sheet.accuracy = in.number(s["accuracy"],
                                     "nesting accuracy",
                                     {.min = 0, .max = 1, .unit = "", .exclusive_min = true})
                               .value_or(0.65);
    }
  }
};

Design load_nested(std::string_view yaml,
                   std::string_view display_name,
                   Diagnostics& diags,
                   const std::filesystem::path& base_dir,
                   const DesignFileOptions& options,
                   int depth,
                   std::vector<std::filesystem::path>& chain) {
  Design d;
  YamlReader in{std::string(display_name), diags};
  const auto root = in.parse_mapping(yaml, "fabkit: flatpack/1, components and connections");
  if (!root) return d;
  const auto tag = in.kit_tag(*root, kKits);
  if (!tag) return d;
  if (tag->kit != "flatpack" || tag->version != 1) {
    in.error(codes::kUnknownKit,
             fmt::format("this is a {} file; the flatpack kit reads flatpack/1", tag->spelled()),
             tag->where);
    return d;
  }
  Reader r{in, base_dir, options, depth, chain};
  r.read(*root, d);
  return d;
}

}  // namespace

Design load_design_text(std::string_view yaml,
                        std::string_view display_name,
                        Diagnostics& diags,
                        const std::filesystem::path& base_dir,
                        const DesignFileOptions& options) {
  std::vector<std::filesystem::path> chain;
  if (!options.file.empty()) chain.push_back(identity(options.file));
  return load_nested(yaml, display_name, diags, base_dir, options, 0, chain);
}

Design load_design(const std::filesystem::path& path,
                   Diagnostics& diags,
                   const DesignFileOptions& options) {
  const auto text = read_input_file(path, "design file", diags);
  if (!text) return {};
  std::vector<std::filesystem::path> chain{identity(path)};
  Design d = load_nested(*text, path.string(), diags, path.parent_path(), options, 0, chain);
  d.source = path;
  return d;
}

std::string to_yaml(const Design& d) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "fabkit" << YAML::Value << "flatpack/1";
  if (!d.name.empty()) out << YAML::Key << "name" << YAML::Value << d.name;
  if (!d.description.empty()) out << YAML::Key << "description" << YAML::Value << d.description;
  if (!d.parameters.empty()) {
    out << YAML::Key << "parameters" << YAML::Value << YAML::BeginMap;
    for (const DesignParameter& p : d.parameters) {
      out << YAML::Key << p.name << YAML::Value << YAML::Flow << YAML::BeginMap;
      if (p.value) out << YAML::Key << "value" << YAML::Value << *p.value;
      out << YAML::Key << "type" << YAML::Value << std::string(to_string(p.kind));
      if (p.meta) out << YAML::Key << "meta" << YAML::Value << true;
      if (!p.description.empty()) out << YAML::Key << "description" << YAML::Value << p.description;
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  auto material = [&](const Material& m) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << m.name << YAML::Key
        << "thickness" << YAML::Value << m.thickness_mm << YAML::Key << "kerf" << YAML::Value
        << m.kerf_mm << YAML::Key << "interference" << YAML::Value << m.interference_mm
        << YAML::EndMap;
  };
  out << YAML::Key << "material" << YAML::Value;
  material(d.material);
  if (!d.materials.empty()) {
    out << YAML::Key << "materials" << YAML::Value << YAML::BeginSeq;
    for (const Material& m : d.materials) material(m);
    out << YAML::EndSeq;
  }
  if (!d.library.empty()) {
    out << YAML::Key << "uses" << YAML::Value << YAML::BeginMap;
    for (const auto& [type, sub] : d.library) {
      out << YAML::Key << type << YAML::Value << sub->source.filename().string();
    }
    out << YAML::EndMap;
  }
  out << YAML::Key << "components" << YAML::Value << YAML::BeginSeq;
  for (const ComponentUse& u : d.components) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << u.name << YAML::Key
        << "type" << YAML::Value << u.type;
    for (const auto& [k, e] : u.params) out << YAML::Key << k << YAML::Value << e.text;
    if (!u.material.empty()) out << YAML::Key << "material" << YAML::Value << u.material;
    if (!u.points.empty()) {
      out << YAML::Key << "points" << YAML::Value << YAML::BeginSeq;
      for (const Vec2& p : u.points)
        out << YAML::Flow << YAML::BeginSeq << p.x() << p.y() << YAML::EndSeq;
      out << YAML::EndSeq;
    }
    if (!u.edge_names.empty()) out << YAML::Key << "edges" << YAML::Value << u.edge_names;
    if (!u.cutouts.empty()) {
      out << YAML::Key << "cutouts" << YAML::Value << YAML::BeginSeq;
      for (const Cutout& c : u.cutouts) {
        out << YAML::BeginMap << YAML::Key
            << (c.shape == Cutout::Shape::kCircle ? "circle" : "rectangle") << YAML::Value
            << YAML::BeginMap << YAML::Key << "at" << YAML::Value << YAML::Flow << YAML::BeginSeq
            << c.at[0].text << c.at[1].text << YAML::EndSeq;
        if (c.shape == Cutout::Shape::kCircle) {
          out << YAML::Key << "d" << YAML::Value << c.size[0].text;
        } else {
          out << YAML::Key << "size" << YAML::Value << YAML::Flow << YAML::BeginSeq
              << c.size[0].text << c.size[1].text << YAML::EndSeq;
        }
        out << YAML::EndMap << YAML::EndMap;
      }
      out << YAML::EndSeq;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (!d.constraints.empty()) {
    out << YAML::Key << "constraints" << YAML::Value << YAML::BeginSeq;
    for (const Constraint& c : d.constraints) out << c.text();
    out << YAML::EndSeq;
  }
  if (!d.connections.empty()) {
    out << YAML::Key << "connections" << YAML::Value << YAML::BeginSeq;
    for (const Connection& c : d.connections) {
      out << YAML::Flow << YAML::BeginMap;
      if (!c.name.empty()) out << YAML::Key << "name" << YAML::Value << c.name;
      out << YAML::Key << "connect" << YAML::Value << YAML::Flow << YAML::BeginSeq
          << (c.a_component + "." + c.a_edge) << (c.b_component + "." + c.b_edge) << YAML::EndSeq;
      out << YAML::Key << "alignment" << YAML::Value << std::string(to_string(c.alignment));
      for (int which = 0; which < 2; ++which) {
        const auto& v = which == 0 ? c.offset : c.rotation;
        out << YAML::Key << (which == 0 ? "offset" : "rotation") << YAML::Value << YAML::Flow
            << YAML::BeginSeq;
        for (const Expression& e : v) out << (e.text.empty() ? std::string("0") : e.text);
        out << YAML::EndSeq;
      }
      if (c.places_only) out << YAML::Key << "joint" << YAML::Value << "none";
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  if (!d.interfaces.empty()) {
    out << YAML::Key << "interfaces" << YAML::Value << YAML::BeginMap;
    for (const auto& [k, v] : d.interfaces) out << YAML::Key << k << YAML::Value << v;
    out << YAML::EndMap;
  }
  out << YAML::Key << "joints" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "finger_width" << YAML::Value << d.joints.finger_width_mm << YAML::Key << "end_margin"
      << YAML::Value << d.joints.end_margin_mm << YAML::Key << "dogbone" << YAML::Value
      << d.joints.dogbone_tool_mm << YAML::EndMap;
  out << YAML::Key << "sheet" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "width"
      << YAML::Value << d.sheet.sheet_width_mm << YAML::Key << "height" << YAML::Value
      << d.sheet.sheet_height_mm << YAML::Key << "spacing" << YAML::Value << d.sheet.spacing_mm
      << YAML::Key << "margin" << YAML::Value << d.sheet.margin_mm << YAML::Key << "rotations"
      << YAML::Value << d.sheet.rotations_deg << YAML::EndMap;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace fabkit::flatpack
