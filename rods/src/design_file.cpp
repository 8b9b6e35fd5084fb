#include "fabkit/rods/design_file.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <set>

#include "fabkit/core/file_io.h"
#include "fabkit/core/names.h"
#include "fabkit/core/text.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/rods/diagnostic_codes.h"

namespace fabkit::rods {
namespace {

constexpr std::string_view kFormatTag = "rods/1";
const NumberRange kCoordinate{-kMaxCoordinateMm, kMaxCoordinateMm, "mm"};

std::vector<std::string> preset_names_rod() {
  std::vector<std::string> out;
  for (const RodMaterial& m : rod_material_presets()) out.push_back(m.name);
  return out;
}
std::vector<std::string> preset_names_joint() {
  std::vector<std::string> out;
  for (const JointMaterial& m : joint_material_presets()) out.push_back(m.name);
  return out;
}
std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

class Reader {
 public:
  Reader(std::string file,
         std::filesystem::path base_dir,
         const DesignOptions& options,
         Diagnostics& diags)
      : in_(std::move(file), diags),
        base_dir_(std::move(base_dir)),
        options_(options),
        diags_(diags) {}

  void run(std::string_view text, Design& d) {
    const auto parsed = in_.parse_mapping(text, "rod, joint, nodes and edges (docs/rods.md)");
    if (!parsed) return;
    const YAML::Node root = *parsed;
    in_.check_keys(root,
                   {"fabkit",
                    "name",
                    "description",
                    "rod",
                    "joint",
                    "stock",
                    "min_rod_length",
                    "merge_tolerance",
                    "nodes",
                    "edges",
                    "network",
                    "scale",
                    "loads",
                    "supports",
                    "assembly_start",
                    "reuse_joints_from",
                    "tolerance_board",
                    "engrave"});
    if (auto tag = root["fabkit"]) {
      const auto t = in_.string(tag, "fabkit");
      if (t && *t != kFormatTag) {
        in_.error(
            codes::kMalformedInput,
            fmt::format(
                "unsupported format '{}'; this version reads '{}'", excerpt(*t, 40), kFormatTag),
            in_.at(tag));
      }
    }
    if (auto n = root["name"]) d.name = in_.string(n, "name").value_or("");
    if (auto n = root["description"]) d.description = in_.string(n, "description").value_or("");
    Parameters& p = d.parameters;
    if (auto rod = root["rod"]; rod && in_.is_mapping(rod, "rod")) read_rod(rod, p);
    if (auto joint = root["joint"]; joint && in_.is_mapping(joint, "joint")) read_joint(joint, p);
    if (auto stock = root["stock"]; stock && in_.is_mapping(stock, "stock")) {
      in_.check_keys(stock, {"length", "end_padding", "kerf"}, "stock");
      get(stock["length"], "stock length", {0, 1e5, "mm", true}, p.stock.length);
      get(stock["end_padding"], "stock end padding", {0, 1e4, "mm"}, p.stock.end_padding);
      get(stock["kerf"], "stock kerf", {0, 20, "mm"}, p.stock.kerf);
    }
    get(root["min_rod_length"], "min_rod_length", {0, 1e6, "mm"}, p.min_rod_length);
    get(root["merge_tolerance"], "merge_tolerance", {0, 100, "mm"}, p.merge_tolerance);
    if (auto e = root["engrave"]) d.engrave = in_.boolean(e, "engrave").value_or(true);
    double scale = 1;
    get(root["scale"], "scale", {0, 1e4, "", true}, scale);

    // The network: nodes and edges, or an OBJ file.
    std::vector<NodeInput> nodes;
    std::vector<EdgeInput> edges;
    if (auto net = root["network"]) {
      if (root["nodes"] || root["edges"]) {
        in_.error(codes::kMalformedInput,
                  "give either network (an OBJ file) or nodes and edges, not both",
                  in_.at(net));
      } else if (options_.files == FilePolicy::kRefuse) {
        in_.error(codes::kInvalidValue,
                  "network files are not accepted here: give nodes and edges",
                  in_.at(net));
      } else if (auto name = in_.string(net, "network")) {
        const std::filesystem::path path = base_dir_ / *name;
        Diagnostics read;
        if (auto obj = read_input_file(path, "network file", read)) {
          read_network_obj(*obj, path.string(), nodes, edges, diags_);
        }
        diags_.append(read);
      }
    } else {
      read_nodes(root, nodes);
      read_edges(root, edges);
    }
    if (static_cast<long long>(nodes.size()) > options_.max_nodes) {
      in_.error(
          codes::kLimitExceeded,
          fmt::format(
              "the design has {} nodes; at most {} are accepted", nodes.size(), options_.max_nodes),
          in_.start());
      return;
    }
    if (static_cast<long long>(edges.size()) > options_.max_edges) {
      in_.error(
          codes::kLimitExceeded,
          fmt::format(
              "the design has {} edges; at most {} are accepted", edges.size(), options_.max_edges),
          in_.start());
      return;
    }
    for (NodeInput& n : nodes) n.position *= scale;
    // Parameter rules that span keys (ε below σ, ...) are checked on the whole; each message
    // points at the key it starts with, when the file has it.
    auto key = [&](const char* section, const char* name) {
      const YAML::Node parent = root[section];
      return parent && parent.IsMap() ? parent[name] : YAML::Node();
    };
    const std::vector<std::pair<std::string_view, YAML::Node>> keys = {
        {"rod radius", key("rod", "radius") ? key("rod", "radius") : key("rod", "diameter")},
        {"tolerance", key("joint", "tolerance")},
        {"joint wall", key("joint", "wall")},
        {"socket length", key("joint", "socket")},
        {"leaf offset", key("joint", "leaf_offset")},
        {"stock", root["stock"]},
        {"rod material", key("rod", "material")},
        {"joint material", key("joint", "material")},
        {"minimum rod length", root["min_rod_length"]},
        {"merge tolerance", root["merge_tolerance"]}};
    for (const Diagnostic& x : p.validate()) {
      SourceLocation where = in_.start();
      for (const auto& [prefix, node] : keys) {
        if (x.message.starts_with(prefix) && node) where = in_.at(node);
      }
      diags_.add(Diagnostic{x.severity, x.code, x.message, where});
    }
    if (diags_.has_errors_of(DiagnosticClass::kInput)) return;
    auto s = build_structure(nodes, edges, 1, p.merge_tolerance, diags_);
    if (!s) return;
    d.structure = std::move(*s);
    // Joint numbers in the file → node indices (merged nodes map to their joint).
    read_loads(root, d);
    read_supports(root, d);
    if (auto start = root["assembly_start"]) {
      if (auto i = node_index(start, d, "assembly_start")) d.assembly_start = *i;
    }
    if (auto board = root["tolerance_board"]; board && in_.is_mapping(board, "tolerance_board")) {
      in_.check_keys(board, {"from", "to", "step", "depth", "columns"}, "tolerance_board");
      ToleranceBoardOptions o;
      get(board["from"], "tolerance_board from", {-10, 10, "mm"}, o.from);
      get(board["to"], "tolerance_board to", {-10, 10, "mm"}, o.to);
      get(board["step"], "tolerance_board step", {0, 10, "mm", true}, o.step);
      get(board["depth"], "tolerance_board depth", {0, 1000, "mm"}, o.depth);
      if (auto c = board["columns"])
        o.columns = static_cast<int>(in_.integer(c, "tolerance_board columns", 1, 20).value_or(5));
      d.tolerance_board = o;
    }
    if (auto reuse = root["reuse_joints_from"]) {
      if (options_.files == FilePolicy::kRefuse) {
        in_.error(codes::kInvalidValue,
                  "reuse_joints_from is not accepted here (it names a file)",
                  in_.at(reuse));
      } else if (auto name = in_.string(reuse, "reuse_joints_from")) {
        d.reuse_joints_from = base_dir_ / *name;
      }
    }
  }

 private:
  void get(const YAML::Node& node, std::string_view what, const NumberRange& range, double& out) {
    if (!node) return;
    if (auto v = in_.number(node, what, range)) out = *v;
  }

  void read_rod(const YAML::Node& rod, Parameters& p) {
    in_.check_keys(rod, {"radius", "diameter", "profile", "circle_sides", "material"}, "rod");
    if (rod["radius"] && rod["diameter"]) {
      in_.error(codes::kMalformedInput,
                "give the rod's radius or its diameter, not both",
                in_.at(rod["diameter"]));
    }
    get(rod["radius"], "rod radius", {0, 500, "mm", true}, p.radius);
    double diameter = 0;
    if (rod["diameter"]) {
      get(rod["diameter"], "rod diameter", {0, 1000, "mm", true}, diameter);
      if (diameter > 0) p.radius = diameter / 2;
    }
    if (auto prof = rod["profile"]) {
      long long sides = 0;
      const std::string text = prof.IsScalar() ? prof.Scalar() : std::string();
      if (text == "circle" || text == "round") {
        p.sides = 0;
      } else if (text == "triangle") {
        p.sides = 3;
      } else if (text == "square") {
        p.sides = 4;
      } else if (text == "hexagon") {
        p.sides = 6;
      } else if (text == "octagon") {
        p.sides = 8;
      } else if (!text.empty() &&
                 std::from_chars(text.data(), text.data() + text.size(), sides).ec == std::errc() &&
                 std::to_string(sides) == text) {
        if (sides < 3 || sides > 64) {
          in_.error(
              codes::kInvalidValue,
              fmt::format("rod profile has {} sides; a polygon has 3 to 64 (or use circle)", sides),
              in_.at(prof));
        } else {
          p.sides = static_cast<int>(sides);
        }
      } else {
        in_.error(
            codes::kInvalidValue,
            fmt::format("rod profile '{}' is not circle, triangle, square, hexagon, octagon or a "
                        "number of sides",
                        excerpt(text, 30)),
            in_.at(prof));
      }
    }
    if (auto c = rod["circle_sides"])
      p.circle_sides = static_cast<int>(in_.integer(c, "circle_sides", 8, 256).value_or(32));
    if (auto m = rod["material"]) {
      if (m.IsScalar()) {
        const std::string name = m.Scalar();
        if (auto preset = find_rod_material(name)) {
          p.rod_material = *preset;
        } else {
          in_.error(codes::kUnknownName,
                    fmt::format("unknown rod material '{}'{}; presets: {} (or give density, "
                                "youngs_modulus, shear_modulus, strength)",
                                excerpt(name, 30),
                                did_you_mean(name, preset_names_rod()),
                                joined(preset_names_rod())),
                    in_.at(m));
        }
      } else if (in_.is_mapping(m, "rod material")) {
        in_.check_keys(m,
                       {"preset", "density", "youngs_modulus", "shear_modulus", "strength"},
                       "rod material");
        if (auto base = m["preset"]) {
          if (auto preset = find_rod_material(base.IsScalar() ? base.Scalar() : ""))
            p.rod_material = *preset;
          else
            in_.error(codes::kUnknownName, "unknown rod material preset", in_.at(base));
        }
        p.rod_material.name = m["preset"] ? p.rod_material.name : "custom";
        get(m["density"], "rod density", {0, 30000, "kg/m³", true}, p.rod_material.density);
        get(m["youngs_modulus"],
            "rod Young's modulus",
            {0, 1e6, "MPa", true},
            p.rod_material.youngs_modulus);
        get(m["shear_modulus"],
            "rod shear modulus",
            {0, 1e6, "MPa", true},
            p.rod_material.shear_modulus);
        get(m["strength"], "rod strength", {0, 1e5, "MPa", true}, p.rod_material.strength);
      }
    }
  }

  void read_joint(const YAML::Node& joint, Parameters& p) {
    in_.check_keys(joint, {"wall", "socket", "tolerance", "leaf_offset", "material"}, "joint");
    get(joint["wall"], "joint wall", {0, 100, "mm", true}, p.wall);
    get(joint["socket"], "joint socket length", {0, 1000, "mm", true}, p.socket);
    get(joint["tolerance"], "joint tolerance", {-10, 10, "mm"}, p.tolerance);
    get(joint["leaf_offset"], "joint leaf_offset", {0, 1000, "mm"}, p.leaf_offset);
    if (auto m = joint["material"]) {
      if (m.IsScalar()) {
        const std::string name = m.Scalar();
        if (auto preset = find_joint_material(name)) {
          p.joint_material = *preset;
        } else {
          in_.error(codes::kUnknownName,
                    fmt::format("unknown joint material '{}'{}; presets: {} (or give density)",
                                excerpt(name, 30),
                                did_you_mean(name, preset_names_joint()),
                                joined(preset_names_joint())),
                    in_.at(m));
        }
      } else if (in_.is_mapping(m, "joint material")) {
        in_.check_keys(m, {"density"}, "joint material");
        p.joint_material.name = "custom";
        get(m["density"], "joint density", {0, 30000, "kg/m³", true}, p.joint_material.density);
      }
    }
  }

  void read_nodes(const YAML::Node& root, std::vector<NodeInput>& nodes) {
    const YAML::Node list = root["nodes"];
    if (!list) {
      in_.error(codes::kMalformedInput,
                "a rods design needs nodes and edges (or a network file)",
                in_.start());
      return;
    }
    if (!in_.is_list(list, "nodes")) return;
    int k = 0;
    for (const auto& n : list) {
      ++k;
      if (auto v = in_.vec3(n, fmt::format("node {}", k), kCoordinate)) {
        nodes.push_back(NodeInput{*v, in_.at(n)});
      } else {
        nodes.push_back(NodeInput{Vec3::Zero(), in_.at(n)});  // keep the numbering
      }
    }
  }

  void read_edges(const YAML::Node& root, std::vector<EdgeInput>& edges) {
    const YAML::Node list = root["edges"];
    if (!list) {
      in_.error(
          codes::kMalformedInput, "a rods design needs edges: pairs of node numbers", in_.start());
      return;
    }
    if (!in_.is_list(list, "edges")) return;
    int k = 0;
    for (const auto& e : list) {
      ++k;
      if (!e.IsSequence() || e.size() != 2) {
        in_.error(codes::kMalformedInput,
                  fmt::format("edge {} must be a pair of node numbers [a, b]", k),
                  in_.at(e));
        continue;
      }
      const auto a =
          in_.integer(e[0], fmt::format("edge {} first node", k), -1'000'000'000, 1'000'000'000);
      const auto b =
          in_.integer(e[1], fmt::format("edge {} second node", k), -1'000'000'000, 1'000'000'000);
      if (a && b) edges.push_back(EdgeInput{*a, *b, in_.at(e)});
    }
  }

  std::optional<int> node_index(const YAML::Node& n, const Design& d, std::string_view what) {
    const auto number = in_.integer(n, what, 1, 1'000'000'000);
    if (!number) return std::nullopt;
    for (std::size_t i = 0; i < d.structure.nodes.size(); ++i) {
      if (d.structure.nodes[i].id == *number) return static_cast<int>(i);
    }
    in_.error(
        codes::kNoSuchNode,
        fmt::format("{} names node {}, which is not a joint of the design (merged or missing)",
                    what,
                    *number),
        in_.at(n));
    return std::nullopt;
  }

  void read_loads(const YAML::Node& root, Design& d) {
    const YAML::Node list = root["loads"];
    if (!list || !in_.is_list(list, "loads")) return;
    for (const auto& l : list) {
      if (!in_.is_mapping(l, "a load")) continue;
      in_.check_keys(l, {"node", "force"}, "a load");
      if (!in_.require(l, "node", "a load") || !in_.require(l, "force", "a load")) continue;
      const auto i = node_index(l["node"], d, "load node");
      const auto f = in_.vec3(l["force"], "load force", {-1e7, 1e7, "N"});
      if (i && f) d.loads.push_back(PointLoad{*i, *f, in_.at(l)});
    }
  }

  void read_supports(const YAML::Node& root, Design& d) {
    const YAML::Node list = root["supports"];
    if (!list || !in_.is_list(list, "supports")) return;
    for (const auto& s : list) {
      if (!in_.is_mapping(s, "a support")) continue;
      in_.check_keys(s, {"node", "fixed"}, "a support");
      if (!in_.require(s, "node", "a support")) continue;
      const auto i = node_index(s["node"], d, "support node");
      const bool fixed =
          s["fixed"] ? in_.boolean(s["fixed"], "support fixed").value_or(false) : false;
      if (i) d.supports.push_back(Support{*i, fixed, in_.at(s)});
    }
  }

  YamlReader in_;
  std::filesystem::path base_dir_;
  const DesignOptions& options_;
  Diagnostics& diags_;
};

// "12", "12/3", "12//4", "-1": the vertex index before any slash.
std::optional<long long> obj_index(std::string_view token, long long vertex_count) {
  const auto slash = token.find('/');
  const std::string_view head = token.substr(0, slash);
  long long v = 0;
  const auto [p, ec] = std::from_chars(head.data(), head.data() + head.size(), v);
  if (ec != std::errc() || p != head.data() + head.size() || v == 0) return std::nullopt;
  return v < 0 ? vertex_count + v + 1 : v;
}

}  // namespace

bool read_network_obj(std::string_view text,
                      std::string_view display_name,
                      std::vector<NodeInput>& nodes,
                      std::vector<EdgeInput>& edges,
                      Diagnostics& diags) {
  const std::size_t before = diags.size();
  std::set<std::pair<long long, long long>> seen;
  int line_number = 0;
  const std::string file(display_name);
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    std::vector<std::string_view> tokens;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      std::size_t j = i;
      while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
      if (j > i) tokens.push_back(line.substr(i, j - i));
      i = j;
    }
    if (tokens.empty()) continue;
    const SourceLocation where{file, line_number, 1};
    if (tokens[0] == "v") {
      Vec3 p = Vec3::Zero();
      bool ok = tokens.size() >= 4;
      for (int k = 0; k < 3 && ok; ++k) {
        const std::string_view t = tokens[static_cast<std::size_t>(k) + 1];
        const auto r = std::from_chars(t.data(), t.data() + t.size(), p[k]);
        ok = r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(p[k]);
      }
      if (!ok)
        diags.error(codes::kMalformedInput, "a vertex needs three finite numbers: v x y z", where);
      nodes.push_back(NodeInput{p, where});
    } else if (tokens[0] == "l" || tokens[0] == "f") {
      std::vector<long long> ids;
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        const auto v = obj_index(tokens[k], static_cast<long long>(nodes.size()));
        if (!v) {
          diags.error(codes::kMalformedInput,
                      fmt::format("'{}' is not a vertex index", excerpt(tokens[k], 20)),
                      where);
          ids.clear();
          break;
        }
        ids.push_back(*v);
      }
      const bool closed = tokens[0] == "f";
      if (ids.size() < 2) continue;
      const std::size_t segments = closed ? ids.size() : ids.size() - 1;
      for (std::size_t k = 0; k < segments; ++k) {
        const long long a = ids[k], b = ids[(k + 1) % ids.size()];
        // Faces share their edges; each edge becomes one rod.
        if (!seen.insert({std::min(a, b), std::max(a, b)}).second) continue;
        edges.push_back(EdgeInput{a, b, where});
      }
    }
  }
  for (std::size_t i = before; i < diags.size(); ++i) {
    if (diags.items()[i].severity == Severity::kError) return false;
  }
  return true;
}

Design load_design_text(std::string_view yaml,
                        std::string_view display_name,
                        const std::filesystem::path& base_dir,
                        const DesignOptions& options) {
  Design d;
  Reader reader(std::string(display_name), base_dir, options, d.diagnostics);
  if (const auto thrown = thrown_by([&] { reader.run(yaml, d); })) {
    d = Design{};  // nothing half-read is kept
    report_unexpected_shape(d.diagnostics, display_name, "a rods design", *thrown);
  }
  d.readable = !d.diagnostics.has_errors_of(DiagnosticClass::kInput) && !d.structure.nodes.empty();
  return d;
}

Design load_design(const std::filesystem::path& path, const DesignOptions& options) {
  Design d;
  const auto text = read_input_file(path, "design file", d.diagnostics);
  if (!text) return d;
  d = load_design_text(*text, path.string(), path.parent_path(), options);
  d.source = path;
  return d;
}

Design design_from_lists(const std::vector<Vec3>& nodes,
                         const std::vector<std::pair<long long, long long>>& edges,
                         const Parameters& parameters) {
  Design d;
  d.parameters = parameters;
  d.diagnostics = parameters.validate();
  if (d.diagnostics.has_errors()) return d;
  std::vector<NodeInput> in_nodes;
  for (const Vec3& v : nodes) in_nodes.push_back(NodeInput{v, {}});
  std::vector<EdgeInput> in_edges;
  for (const auto& [a, b] : edges) in_edges.push_back(EdgeInput{a, b, {}});
  auto s = build_structure(in_nodes, in_edges, 0, parameters.merge_tolerance, d.diagnostics);
  if (s) d.structure = std::move(*s);
  d.readable = s.has_value();
  return d;
}

}  // namespace fabkit::rods
