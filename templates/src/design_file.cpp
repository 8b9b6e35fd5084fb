// Reading the kit's YAML files (source designs and working models).
#include "fabkit/templates/design_file.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <set>

#include "fabkit/core/text.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/templates/diagnostic_codes.h"

namespace fabkit::templates {

namespace {

constexpr std::array<std::string_view, 1> kKits = {"templates"};
constexpr NumberRange kCoordinate{-1e5, 1e5, "mm"};
constexpr NumberRange kSize{0, 1e5, "mm", true};

std::optional<int> axis_of(YamlReader& in,
                           const YAML::Node& node,
                           std::string_view what,
                           int* sign) {
  const auto s = in.string(node, what, 8);
  if (!s) return std::nullopt;
  std::string v = *s;
  int sg = 1;
  if (!v.empty() && (v[0] == '-' || v[0] == '+')) {
    sg = v[0] == '-' ? -1 : 1;
    v = v.substr(1);
  }
  if (v == "x" || v == "y" || v == "z") {
    if (sign) *sign = sg;
    return v[0] - 'x';
  }
  in.error(codes::kInvalidValue,
           fmt::format("{} '{}' must be x, y or z (optionally with a sign: -y)", what, *s),
           in.at(node));
  return std::nullopt;
}

std::optional<YAML::Node> header(YamlReader& in, std::string_view yaml) {
  auto root = in.parse_mapping(yaml, "'fabkit: templates/1' and either 'design:' or 'model:'");
  if (!root) return std::nullopt;
  if (!in.kit_tag(*root, kKits)) return std::nullopt;
  return root;
}

}  // namespace

std::optional<TemplatesFileKind> templates_file_kind(std::string_view yaml,
                                                     std::string_view file,
                                                     Diagnostics& diags) {
  YamlReader in(std::string(file), diags);
  auto root = header(in, yaml);
  if (!root) return std::nullopt;
  if ((*root)["design"]) return TemplatesFileKind::kDesign;
  if ((*root)["model"]) return TemplatesFileKind::kModel;
  in.error(codes::kMalformedInput,
           "a templates/1 file needs 'model:' (a working model: templates to compose) or "
           "'design:' (a source design for the database)",
           in.start());
  return std::nullopt;
}

namespace {

std::optional<SourceDesign> read_source_design_unguarded(std::string_view yaml,
                                                         std::string_view file,
                                                         Diagnostics& diags) {
  YamlReader in(std::string(file), diags);
  auto root_opt = header(in, yaml);
  if (!root_opt) return std::nullopt;
  const YAML::Node root = *root_opt;
  in.check_keys(root,
                {"fabkit", "design", "title", "category", "description", "parts", "articulations"},
                "a source design");
  SourceDesign d;
  d.file = std::string(file);
  if (!in.require(root, "design", "a source design")) return std::nullopt;
  if (auto n = in.name(root["design"], "design name")) d.name = *n;
  if (root["title"]) d.title = in.string(root["title"], "title").value_or("");
  if (root["category"]) d.category = in.string(root["category"], "category").value_or("");
  if (root["description"])
    d.description = in.string(root["description"], "description", 8192).value_or("");
  if (d.title.empty()) d.title = d.name;
  if (!in.require(root, "parts", "a source design") || !in.is_list(root["parts"], "parts")) {
    return std::nullopt;
  }
  std::set<std::string> names;
  for (const YAML::Node& p : root["parts"]) {
    if (!in.is_mapping(p, "a part")) continue;
    in.check_keys(p,
                  {"name",
                   "item",
                   "role",
                   "group",
                   "center",
                   "min",
                   "max",
                   "size",
                   "mirror",
                   "repeat",
                   "names"},
                  "a part");
    const auto name = p["name"] ? in.name(p["name"], "part name") : std::nullopt;
    if (!p["name"]) in.require(p, "name", "a part");
    const auto item = p["item"] ? in.string(p["item"], "item", 64) : std::nullopt;
    if (!p["item"]) in.require(p, "item", "a part");
    PartRole role = PartRole::kPrincipal;
    if (p["role"]) {
      const auto r = in.string(p["role"], "role", 16);
      if (r && *r == "connecting") {
        role = PartRole::kConnecting;
      } else if (r && *r != "principal") {
        in.error(codes::kInvalidValue,
                 fmt::format("role '{}' must be principal or connecting", *r),
                 in.at(p["role"]));
      }
    }
    std::string group;
    if (p["group"]) {
      group = in.string(p["group"], "group", 256).value_or("");
      for (std::size_t s = 0, e = 0; s <= group.size(); s = e + 1) {
        e = group.find('/', s);
        if (e == std::string::npos) e = group.size();
        const std::string seg = group.substr(s, e - s);
        if (seg.empty() || !std::all_of(seg.begin(), seg.end(), [](char c) {
              return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
            })) {
          in.error(codes::kInvalidValue,
                   fmt::format("group '{}' must be names of letters, digits, '_' or '-' separated "
                               "by '/'",
                               group),
                   in.at(p["group"]));
          break;
        }
      }
    }
    // The box: centre + size, min + size, or min + max.
    std::optional<Vec3> center, lo, hi, size;
    if (p["center"]) center = in.vec3(p["center"], "center", kCoordinate);
    if (p["min"]) lo = in.vec3(p["min"], "min", kCoordinate);
    if (p["max"]) hi = in.vec3(p["max"], "max", kCoordinate);
    if (p["size"]) size = in.vec3(p["size"], "size", kSize);
    Box box;
    const int given =
        (p["center"] ? 1 : 0) + (p["min"] ? 1 : 0) + (p["max"] ? 1 : 0) + (p["size"] ? 1 : 0);
    if (given != 2 || (p["center"] && !p["size"])) {
      in.error(codes::kMalformedInput,
               "a part's box is 'center' + 'size', 'min' + 'size' or 'min' + 'max' (mm)",
               in.at(p));
      continue;
    }
    if (center && size) {
      box.center = *center;
      box.size = *size;
    } else if (lo && size) {
      box.center = *lo + 0.5 * *size;
      box.size = *size;
    } else if (lo && hi) {
      if ((*hi - *lo).minCoeff() <= 0) {
        in.error(codes::kInvalidValue, "max must exceed min along every axis", in.at(p["max"]));
        continue;
      }
      box = Box::from_min_max(*lo, *hi);
    } else {
      continue;  // a value was already reported
    }
    // Copies: repeat (a grid), then mirror (each axis doubles them).
    std::vector<Vec3> centres{box.center};
    if (p["repeat"]) {
      const YAML::Node r = p["repeat"];
      if (!in.is_mapping(r, "repeat")) continue;
      in.check_keys(r, {"count", "step"}, "repeat");
      const auto count = r["count"] ? in.numbers(r["count"], "repeat count", 3, {1, 500, "", false})
                                    : std::nullopt;
      const auto step = r["step"] ? in.vec3(r["step"], "repeat step", kCoordinate) : std::nullopt;
      if (!count || !step) {
        if (!r["count"] || !r["step"])
          in.error(codes::kMalformedInput,
                   "repeat needs count: [nx, ny, nz] and step: [dx, dy, dz] (mm)",
                   in.at(r));
        continue;
      }
      std::vector<Vec3> grid;
      for (int k = 0; k < static_cast<int>((*count)[2]); ++k) {
        for (int j = 0; j < static_cast<int>((*count)[1]); ++j) {
          for (int i = 0; i < static_cast<int>((*count)[0]); ++i) {
            grid.push_back(box.center + Vec3(i * step->x(), j * step->y(), k * step->z()));
          }
        }
      }
      centres = grid;
    }
    if (p["mirror"]) {
      if (!in.is_list(p["mirror"], "mirror")) continue;
      for (const YAML::Node& a : p["mirror"]) {
        const auto axis = axis_of(in, a, "mirror axis", nullptr);
        if (!axis) continue;
        const std::size_t n = centres.size();
        for (std::size_t i = 0; i < n; ++i) {
          Vec3 c = centres[i];
          c[*axis] = -c[*axis];
          centres.push_back(c);
        }
      }
    }
    std::vector<std::string> copy_names;
    if (p["names"]) {
      if (!in.is_list(p["names"], "names")) continue;
      for (const YAML::Node& n : p["names"])
        copy_names.push_back(in.name(n, "part name").value_or(""));
      if (copy_names.size() != centres.size()) {
        in.error(
            codes::kInvalidValue,
            fmt::format("names lists {} names for {} copies", copy_names.size(), centres.size()),
            in.at(p["names"]));
        continue;
      }
    }
    if (!name || !item) continue;
    for (std::size_t i = 0; i < centres.size(); ++i) {
      DesignPart part;
      part.name = !copy_names.empty()  ? copy_names[i]
                  : centres.size() > 1 ? fmt::format("{}_{}", *name, i + 1)
                                       : *name;
      part.item = *item;
      part.role = role;
      part.group = group;
      part.box = box;
      part.box.center = centres[i];
      part.where = in.at(p);
      if (!names.insert(part.name).second) {
        in.error(codes::kDuplicateName,
                 fmt::format("part '{}' is defined twice", part.name),
                 part.where);
        continue;
      }
      d.parts.push_back(std::move(part));
    }
  }
  if (root["articulations"] && in.is_list(root["articulations"], "articulations")) {
    for (const YAML::Node& a : root["articulations"]) {
      if (!in.is_mapping(a, "an articulation")) continue;
      in.check_keys(
          a, {"name", "type", "parts", "group", "axis", "pivot", "limits"}, "an articulation");
      Articulation art;
      art.where = in.at(a);
      art.name = a["name"] ? in.name(a["name"], "articulation name").value_or("") : "";
      if (!a["name"]) in.require(a, "name", "an articulation");
      const auto type = a["type"] ? in.string(a["type"], "joint type", 16) : std::nullopt;
      if (type && *type == "prismatic") {
        art.type = JointType::kPrismatic;
      } else if (type && *type == "hinge") {
        art.type = JointType::kHinge;
      } else if (type && *type == "ball") {
        art.type = JointType::kBall;
      } else {
        in.error(codes::kInvalidValue,
                 fmt::format("joint type '{}' must be prismatic, hinge or ball", type.value_or("")),
                 a["type"] ? in.at(a["type"]) : art.where);
      }
      if (a["axis"]) art.axis = axis_of(in, a["axis"], "axis", &art.direction).value_or(2);
      if (a["pivot"]) art.pivot = in.vec3(a["pivot"], "pivot", kCoordinate).value_or(Vec3::Zero());
      if (a["limits"]) {
        const auto l = in.numbers(a["limits"], "limits", 2, {-1e5, 1e5, "", false});
        if (l) {
          art.lower = (*l)[0];
          art.upper = (*l)[1];
        }
      }
      std::vector<std::string> moving;
      if (a["parts"] && in.is_list(a["parts"], "parts")) {
        for (const YAML::Node& n : a["parts"]) {
          const auto pn = in.name(n, "part name");
          if (!pn) continue;
          if (!d.find(*pn)) {
            std::vector<std::string> all;
            for (const DesignPart& p : d.parts) all.push_back(p.name);
            in.error(codes::kUnknownName,
                     fmt::format("articulation '{}' moves unknown part '{}'{}",
                                 art.name,
                                 *pn,
                                 did_you_mean(*pn, all)),
                     in.at(n));
            continue;
          }
          moving.push_back(*pn);
        }
      }
      if (a["group"]) {
        const auto g = in.string(a["group"], "group", 256);
        bool any = false;
        for (const DesignPart& p : d.parts) {
          if (g && (p.group == *g || p.group.rfind(*g + "/", 0) == 0)) {
            moving.push_back(p.name);
            any = true;
          }
        }
        if (g && !any)
          in.error(codes::kUnknownName,
                   fmt::format("articulation '{}': no part is in group '{}'", art.name, *g),
                   in.at(a["group"]));
      }
      art.parts = moving;
      if (moving.empty() && !a["parts"] && !a["group"]) {
        in.error(codes::kMalformedInput,
                 "an articulation needs 'parts' or 'group' (what moves)",
                 art.where);
      }
      d.articulations.push_back(std::move(art));
    }
  }
  if (d.parts.empty() && in.errors() == 0) {
    in.error(codes::kMalformedInput, "a source design needs at least one part", in.start());
  }
  if (in.errors() > 0) return std::nullopt;
  return d;
}

std::optional<ModelFile> read_model_file_unguarded(std::string_view yaml,
                                                   std::string_view file,
                                                   Diagnostics& diags) {
  YamlReader in(std::string(file), diags);
  auto root_opt = header(in, yaml);
  if (!root_opt) return std::nullopt;
  const YAML::Node root = *root_opt;
  in.check_keys(root,
                {"fabkit", "name", "description", "model", "remove", "adjust", "loads", "friction"},
                "a model");
  ModelFile m;
  m.file = std::string(file);
  if (root["name"]) m.name = in.string(root["name"], "name").value_or("");
  if (root["description"])
    m.description = in.string(root["description"], "description", 8192).value_or("");
  if (root["friction"])
    m.friction = in.number(root["friction"], "friction", {0, 2, ""}).value_or(0.5);
  if (!in.require(root, "model", "a model") || !in.is_list(root["model"], "model"))
    return std::nullopt;
  std::set<std::string> names;
  for (const YAML::Node& s : root["model"]) {
    if (!in.is_mapping(s, "a model step")) continue;
    in.check_keys(s, {"use", "as", "set", "at", "snap", "connect"}, "a model step");
    ModelStep step;
    step.where = in.at(s);
    if (!in.require(s, "use", "a model step")) continue;
    step.use = in.string(s["use"], "use", 256).value_or("");
    step.as =
        s["as"] ? in.name(s["as"], "as").value_or("") : step.use.substr(step.use.rfind('/') + 1);
    if (!step.as.empty() && !names.insert(step.as).second) {
      in.error(codes::kDuplicateName,
               fmt::format("'{}' is already in the model; give this one another 'as:'", step.as),
               step.where);
    }
    if (s["set"] && in.is_mapping(s["set"], "set")) {
      for (const auto& kv : s["set"]) {
        const std::string key = kv.first.Scalar();
        const auto control = control_from_string(key);
        if (!control) {
          std::vector<std::string> all{
              "center_x", "center_y", "center_z", "size_x", "size_y", "size_z"};
          in.error(codes::kUnknownName,
                   fmt::format("unknown control '{}'{} (controls: center_x, center_y, center_z, "
                               "size_x, size_y, size_z)",
                               excerpt(key),
                               did_you_mean(key, all)),
                   in.at(kv.first));
          continue;
        }
        if (auto v = in.number(kv.second, key, kCoordinate)) step.set.emplace_back(*control, *v);
      }
    }
    if (s["at"]) step.at = in.vec3(s["at"], "at", kCoordinate);
    if (s["snap"]) step.snap = in.boolean(s["snap"], "snap").value_or(true);
    if (s["connect"]) step.connect = in.boolean(s["connect"], "connect").value_or(true);
    m.steps.push_back(std::move(step));
  }
  if (root["remove"] && in.is_list(root["remove"], "remove")) {
    for (const YAML::Node& r : root["remove"]) {
      Removal removal;
      removal.where = in.at(r);
      removal.node = in.string(r, "remove", 256).value_or("");
      if (!removal.node.empty()) m.remove.push_back(std::move(removal));
    }
  }
  if (root["adjust"] && in.is_list(root["adjust"], "adjust")) {
    for (const YAML::Node& a : root["adjust"]) {
      if (!in.is_mapping(a, "an adjustment")) continue;
      in.check_keys(a, {"node", "control", "to"}, "an adjustment");
      Adjustment adj;
      adj.where = in.at(a);
      if (!in.require(a, "node", "an adjustment") || !in.require(a, "control", "an adjustment") ||
          !in.require(a, "to", "an adjustment")) {
        continue;
      }
      adj.node = in.string(a["node"], "node", 256).value_or("");
      const std::string c = in.string(a["control"], "control", 16).value_or("");
      if (auto k = control_from_string(c)) {
        adj.control = *k;
      } else {
        in.error(codes::kUnknownName,
                 fmt::format("unknown control '{}' (controls: center_x, center_y, center_z, "
                             "size_x, size_y, size_z)",
                             excerpt(c)),
                 in.at(a["control"]));
      }
      adj.value = in.number(a["to"], "to", kCoordinate).value_or(0);
      m.adjust.push_back(std::move(adj));
    }
  }
  if (root["loads"] && in.is_list(root["loads"], "loads")) {
    for (const YAML::Node& l : root["loads"]) {
      if (!in.is_mapping(l, "a load")) continue;
      in.check_keys(l, {"part", "at", "force"}, "a load");
      LoadSpec load;
      load.where = in.at(l);
      if (!in.require(l, "part", "a load") || !in.require(l, "at", "a load") ||
          !in.require(l, "force", "a load"))
        continue;
      load.part = in.string(l["part"], "part", 256).value_or("");
      load.at = in.vec3(l["at"], "at", kCoordinate).value_or(Vec3::Zero());
      load.force = in.vec3(l["force"], "force", {-1e6, 1e6, "N"}).value_or(Vec3::Zero());
      m.loads.push_back(std::move(load));
    }
  }
  if (m.steps.empty() && in.errors() == 0) {
    in.error(codes::kMalformedInput, "a model needs at least one step in 'model:'", in.start());
  }
  if (in.errors() > 0) return std::nullopt;
  return m;
}

// A reader run so that a shape of YAML it did not expect (yaml-cpp throws on a subscript of a
// scalar) is a finding at the file, not an abort.
template <class Read>
auto guarded(Diagnostics& diags, std::string_view file, Read&& read) -> decltype(read()) {
  decltype(read()) result;
  if (const auto thrown = thrown_by([&] { result = read(); })) {
    report_unexpected_shape(diags, file, "a templates file", *thrown);
    return std::nullopt;
  }
  return result;
}

}  // namespace

std::optional<SourceDesign> read_source_design(std::string_view yaml,
                                               std::string_view file,
                                               Diagnostics& diags) {
  return guarded(diags, file, [&] { return read_source_design_unguarded(yaml, file, diags); });
}

std::optional<ModelFile> read_model_file(std::string_view yaml,
                                         std::string_view file,
                                         Diagnostics& diags) {
  return guarded(diags, file, [&] { return read_model_file_unguarded(yaml, file, diags); });
}

}  // namespace fabkit::templates
