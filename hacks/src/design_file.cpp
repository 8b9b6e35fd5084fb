#include "fabkit/hacks/design_file.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "fabkit/core/names.h"

namespace fabkit::hacks {
namespace {

constexpr double kMaxCoordinateMm = 1e5;  // 100 m: anything bigger is a unit mistake
constexpr std::string_view kFormatTag = "hacks/1";

std::string did_you_mean(std::string_view name, const std::vector<std::string>& options) {
  const std::string best = closest_name(name, options);
  return best.empty() ? "" : fmt::format("; did you mean '{}'?", best);
}

// Reads one file's YAML into the design, collecting diagnostics with file:line.
class Reader {
 public:
  Reader(std::string file,
         const PartsLibrary& library,
         const DesignOptions& options,
         std::filesystem::path base_dir)
      : file_(std::move(file)),
        library_(library),
        options_(options),
        base_dir_(std::move(base_dir)) {}

  void run(std::string_view text, Design& design) {
    build(text, design);
    design.diagnostics = diags_;
  }

 private:
  void build(std::string_view text, Design& design) {
    YAML::Node root;
    try {
      root = YAML::Load(std::string(text));
    } catch (const YAML::ParserException& e) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("YAML syntax error: {}", e.msg),
            loc(e.mark));
      return;
    }
    if (!root.IsMap()) {
      error(DiagnosticCode::kMalformedInput,
            "a design file must be a YAML mapping with environment, parts, connections and target",
            root.IsDefined() ? at(root) : SourceLocation{file_, 1, 1});
      return;
    }
    check_keys(root,
               {"fabkit",
                "name",
                "description",
                "part_files",
                "environment",
                "parts",
                "target",
                "connections"});
    if (auto tag = root["fabkit"]) {
      const std::string t = scalar(tag, "fabkit");
      if (!t.empty() && t != kFormatTag) {
        error(DiagnosticCode::kMalformedInput,
              fmt::format("unsupported format '{}'; this version reads '{}'", t, kFormatTag),
              at(tag));
      }
    }
    if (auto n = root["name"]) design.name = scalar(n, "name");
    if (auto d = root["description"]) design.description = scalar(d, "description");

    PartsLibrary local = library_;
    const PartsLibrary* lib = &library_;
    if (auto files = root["part_files"]) {
      if (!files.IsSequence()) {
        error(
            DiagnosticCode::kMalformedInput, "part_files must be a list of file names", at(files));
      } else {
        for (const auto& f : files) {
          const std::filesystem::path p = base_dir_ / scalar(f, "part file");
          Diagnostics d;
          if (!local.load_yaml(p, d)) {
            for (Diagnostic x : d) {
              if (!x.where.known()) x.where = at(f);
              diags_.add(x);
            }
          }
        }
        lib = &local;
      }
    }

    // Declarations first (all names known), then the steps in order.
    std::vector<EnvDecl> environments;
    if (auto env = root["environment"]) {
      if (!env.IsSequence() && !env.IsMap()) {
        error(DiagnosticCode::kMalformedInput, "environment must be a list of entries", at(env));
      } else if (env.IsMap()) {
        declare_environment(env, *lib, design, environments);
      } else {
        for (const auto& e : env) declare_environment(e, *lib, design, environments);
      }
    } else {
      error(DiagnosticCode::kMalformedInput,
            "the design has no 'environment': a hack must hang from something fixed",
            SourceLocation{file_, 1, 1});
    }
    if (auto parts = root["parts"]) {
      if (!parts.IsSequence()) {
        error(DiagnosticCode::kMalformedInput, "parts must be a list", at(parts));
      } else {
        for (const auto& p : parts) declare_part(p, *lib, design, /*is_target=*/false);
      }
    }
    if (options_.max_parts > 0) {
      std::size_t count = 0;
      for (const char* key : {"environment", "parts"}) {
        if (auto n = root[key]; n && n.IsSequence()) count += n.size();
      }
      if (root["target"]) ++count;
      if (count > static_cast<std::size_t>(options_.max_parts)) {
        error(
            DiagnosticCode::kInvalidValue,
            fmt::format("the design has {} parts; the limit here is {}", count, options_.max_parts),
            SourceLocation{file_, 1, 1});
        return;
      }
    }
    YAML::Node target = root["target"];
    if (target) declare_part(target, *lib, design, /*is_target=*/true);

    std::vector<ConnectDecl> connects;
    if (auto conns = root["connections"]) {
      if (!conns.IsSequence()) {
        error(DiagnosticCode::kMalformedInput, "connections must be a list", at(conns));
      } else {
        for (const auto& c : conns) parse_connection(c, design, connects);
      }
    }
    TargetDecl tdecl;
    if (target) tdecl = parse_target(target, design);

    if (diags_.has_errors()) return;  // input errors: build nothing
    design.readable = true;

    for (const EnvDecl& e : environments) {
      DesignStep step;
      step.kind = DesignStep::Kind::kAdd;
      step.where = e.where;
      step.text = fmt::format("add {} ({}) at {}", e.name, e.part->type_name, e.frame.to_string());
      step.report = design.assembly.add(e.part, e.frame, e.where);
      step.accepted = step.report.accepted;
      diags_.append(step.report.diagnostics);
      design.steps.push_back(std::move(step));
    }
    std::set<const Part*> missing;  // parts whose introducing connect failed
    for (const ConnectDecl& c : connects) {
      DesignStep step;
      step.kind = DesignStep::Kind::kConnect;
      step.where = c.where;
      step.text = fmt::format("connect {}, {}{}{}",
                              c.text_a,
                              c.text_b,
                              c.options.alignment == AlignmentChoice::kFlip ? " (flip)" : "",
                              c.options.fixed ? " (fixed)" : "");
      const bool a_in = design.assembly.find(c.a.part.get()).has_value();
      const bool b_in = design.assembly.find(c.b.part.get()).has_value();
      // A connect between two parts that are both out only because an earlier connect
      // failed cannot succeed: say so once instead of a confusing second error.
      if (!a_in && !b_in && (missing.count(c.a.part.get()) || missing.count(c.b.part.get()))) {
        step.skipped = true;
        diags_.add({Severity::kNote,
                    DiagnosticCode::kNotInAssembly,
                    fmt::format("skipped {}: {} is not in the assembly because an earlier connect "
                                "failed",
                                step.text,
                                missing.count(c.a.part.get()) ? c.name_a : c.name_b),
                    c.where});
        design.steps.push_back(std::move(step));
        continue;
      }
      step.report = design.assembly.connect(c.a, c.b, c.options);
      step.accepted = step.report.accepted;
      if (!step.accepted) {
        if (!a_in) missing.insert(c.a.part.get());
        if (!b_in) missing.insert(c.b.part.get());
      }
      diags_.append(step.report.diagnostics);
      design.steps.push_back(std::move(step));
    }
    if (tdecl.part) {
      DesignStep step;
      step.kind = DesignStep::Kind::kEndWith;
      step.where = tdecl.where;
      step.text = fmt::format("end_with {} at {}", tdecl.label, tdecl.frame.to_string());
      Diagnostics d = tdecl.primitive >= 0
                          ? design.assembly.end_with(
                                PrimitiveRef(tdecl.part, tdecl.primitive), tdecl.frame, tdecl.where)
                          : design.assembly.end_with(tdecl.part, tdecl.frame, tdecl.where);
      step.accepted = !d.has_errors();
      step.report.accepted = step.accepted;
      step.report.diagnostics = d;
      diags_.append(d);
      if (step.accepted && !design.assembly.find(tdecl.part.get())) {
        diags_.error(DiagnosticCode::kTargetMissing,
                     fmt::format("the target {} is not connected to the hack", tdecl.label),
                     tdecl.where);
      }
      design.steps.push_back(std::move(step));
    }
    for (const auto& [name, part] : design.parts) {
      if (!design.assembly.find(part.get()) && !missing.count(part.get())) {
        diags_.warning(DiagnosticCode::kNotConnected,
                       fmt::format("part {} is declared but never connected", name),
                       declared_at_[name]);
      }
    }
  }

  struct EnvDecl {
    std::string name;
    std::shared_ptr<Part> part;
    Frame frame;
    SourceLocation where;
  };
  struct ConnectDecl {
    PrimitiveRef a, b;
    std::string text_a, text_b, name_a, name_b;
    ConnectOptions options;
    SourceLocation where;
  };
  struct TargetDecl {
    std::shared_ptr<Part> part;
    int primitive = -1;
    Frame frame;
    std::string label;
    SourceLocation where;
  };

  SourceLocation at(const YAML::Node& n) const { return loc(n.Mark()); }
  SourceLocation loc(const YAML::Mark& m) const {
    if (m.line < 0) return SourceLocation{file_, 0, 0};
    return SourceLocation{file_, m.line + 1, m.column + 1};
  }
  void error(DiagnosticCode code, std::string msg, SourceLocation where) {
    diags_.error(code, std::move(msg), std::move(where));
  }

  void check_keys(const YAML::Node& map, std::initializer_list<std::string_view> allowed) {
    std::vector<std::string> names(allowed.begin(), allowed.end());
    for (const auto& kv : map) {
      std::string key;
      try {
        key = kv.first.as<std::string>();
      } catch (const YAML::Exception&) {
        error(DiagnosticCode::kMalformedInput, "keys must be plain names", at(kv.first));
        continue;
      }
      if (std::find(names.begin(), names.end(), key) == names.end()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        error(DiagnosticCode::kUnknownName,
              fmt::format(
                  "unknown key '{}'{} (expected one of: {})", key, did_you_mean(key, names), list),
              at(kv.first));
      }
    }
  }

  std::string scalar(const YAML::Node& n, std::string_view what) {
    if (!n.IsScalar()) {
      error(DiagnosticCode::kMalformedInput, fmt::format("{} must be a single value", what), at(n));
      return "";
    }
    return n.Scalar();
  }

  std::optional<double> number(const YAML::Node& n, std::string_view what) {
    if (!n.IsScalar()) {
      error(DiagnosticCode::kMalformedInput, fmt::format("{} must be a number", what), at(n));
      return std::nullopt;
    }
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("{} must be a number, not '{}'", what, n.Scalar()),
            at(n));
      return std::nullopt;
    }
    if (!std::isfinite(v)) {
      error(DiagnosticCode::kInvalidValue,
            fmt::format("{} is {}, not a finite number", what, n.Scalar()),
            at(n));
      return std::nullopt;
    }
    return v;
  }

  std::optional<bool> boolean(const YAML::Node& n, std::string_view what) {
    try {
      if (n.IsScalar()) return n.as<bool>();
    } catch (const YAML::Exception&) {
    }
    error(DiagnosticCode::kMalformedInput, fmt::format("{} must be true or false", what), at(n));
    return std::nullopt;
  }

  std::optional<Vec3> vec3(const YAML::Node& n,
                           std::string_view what,
                           double limit,
                           std::string_view unit) {
    if (!n.IsSequence() || n.size() != 3) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("{} must be a list of three numbers [x, y, z]", what),
            at(n));
      return std::nullopt;
    }
    Vec3 v;
    for (std::size_t i = 0; i < 3; ++i) {
      auto x = number(n[i], what);
      if (!x) return std::nullopt;
      if (std::abs(*x) > limit) {
        error(DiagnosticCode::kInvalidValue,
              fmt::format(
                  "{} value {:g} {} is absurd (more than {:g} {})", what, *x, unit, limit, unit),
              at(n[i]));
        return std::nullopt;
      }
      v[static_cast<int>(i)] = *x;
    }
    return v;
  }

  Frame frame(const YAML::Node& n, std::string_view what) {
    Frame f;
    if (!n) return f;
    if (!n.IsMap()) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("{} must be a mapping {{pos: [x, y, z], rot: [a, b, c]}}", what),
            at(n));
      return f;
    }
    check_keys(n, {"pos", "rot"});
    if (auto p = n["pos"]) {
      if (auto v = vec3(p, fmt::format("{} pos", what), kMaxCoordinateMm, "mm")) f.pos = *v;
    }
    if (auto r = n["rot"]) {
      if (auto v = vec3(r, fmt::format("{} rot", what), 36000, "degrees")) f.rot = *v;
    }
    return f;
  }

  std::shared_ptr<Part> make_part(const YAML::Node& n,
                                  const PartsLibrary& lib,
                                  const std::string& name) {
    if (auto prims = n["primitives"]) {
      if (n["part"]) {
        error(DiagnosticCode::kMalformedInput,
              fmt::format("{}: give either 'part' or 'primitives', not both", name),
              at(n));
        return nullptr;
      }
      return make_primitives(prims, name);
    }
    auto type = n["part"];
    if (!type) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("{}: missing 'part' (a library part name) or 'primitives'", name),
            at(n));
      return nullptr;
    }
    ParamValues values;
    if (auto params = n["params"]) {
      if (!params.IsMap()) {
        error(DiagnosticCode::kMalformedInput, "params must be a mapping name: value", at(params));
        return nullptr;
      }
      for (const auto& kv : params) {
        const std::string key = scalar(kv.first, "parameter name");
        if (auto v = number(kv.second, fmt::format("parameter {}", key))) values[key] = *v;
      }
    }
    Diagnostics d;
    auto part = lib.make(scalar(type, "part"), values, d, at(type));
    diags_.append(d);
    return part;
  }

  std::shared_ptr<Part> make_primitives(const YAML::Node& prims, const std::string& name) {
    if (!prims.IsMap() || prims.size() == 0) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("{}: primitives must map names to primitives, e.g. "
                        "{{rod: {{type: rod, radius: 5, length: 500}}}}",
                        name),
            at(prims));
      return nullptr;
    }
    std::vector<Primitive> list;
    for (const auto& kv : prims) {
      const std::string pname = scalar(kv.first, "primitive name");
      const YAML::Node& spec = kv.second;
      if (!spec.IsMap() || !spec["type"]) {
        error(DiagnosticCode::kMalformedInput,
              fmt::format("{}.{}: a primitive needs a 'type'", name, pname),
              at(kv.first));
        continue;
      }
      const std::string tname = scalar(spec["type"], "type");
      const auto type = primitive_type_from_string(tname);
      if (!type) {
        error(DiagnosticCode::kUnknownName,
              fmt::format("{}.{}: unknown primitive type '{}' (expected rod, hook, ring, hole, "
                          "clip, tube, edge, surface or hemisphere)",
                          name,
                          pname,
                          tname),
              at(spec["type"]));
        continue;
      }
      std::vector<std::string_view> fields = shape_field_names(*type);
      std::vector<std::string> allowed{
          "type", "frame", "flex", "centerline", "is_open", "open_for_connect"};
      for (auto f : fields) allowed.emplace_back(f);
      PrimitiveShape shape;
      for (const auto& field : spec) {
        const std::string key = scalar(field.first, "key");
        if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
          error(DiagnosticCode::kUnknownName,
                fmt::format("{}.{}: '{}' is not a {} parameter{}",
                            name,
                            pname,
                            key,
                            tname,
                            did_you_mean(key, allowed)),
                at(field.first));
        }
      }
      bool complete = true;
      for (auto f : fields) {
        if (auto v = spec[std::string(f)]) {
          if (auto x = number(v, fmt::format("{}.{} {}", name, pname, f))) {
            *shape_field(shape, f) = *x;
          } else {
            complete = false;
          }
        } else {
          error(DiagnosticCode::kMalformedInput,
                fmt::format("{}.{}: a {} needs '{}'", name, pname, tname, f),
                at(spec));
          complete = false;
        }
      }
      Primitive p = Primitive::make(pname, *type, shape, frame(spec["frame"], pname));
      for (auto [key, flag] : {std::pair{"flex", &p.flex},
                               std::pair{"centerline", &p.centerline},
                               std::pair{"is_open", &p.is_open},
                               std::pair{"open_for_connect", &p.open_for_connect}}) {
        if (auto v = spec[key]) {
          if (auto b = boolean(v, key)) *flag = *b;
        }
      }
      if (spec["is_open"] && !spec["open_for_connect"] &&
          (p.type == PrimitiveType::kRod || p.type == PrimitiveType::kHook)) {
        p.open_for_connect = p.is_open;
      }
      if (complete) {
        Diagnostics d;
        p.validate(fmt::format("{}.{}", name, pname), d, at(kv.first));
        diags_.append(d);
      }
      list.push_back(std::move(p));
    }
    return std::make_shared<Part>(make_primitive_part(std::move(list)));
  }

  void declare_name(const std::string& name,
                    const YAML::Node& where_node,
                    Design& design,
                    std::shared_ptr<Part> part) {
    if (name.empty()) return;
    if (design.parts.count(name)) {
      error(DiagnosticCode::kDuplicateName,
            fmt::format(
                "the name '{}' is used twice (first on line {})", name, declared_at_[name].line),
            at(where_node));
      return;
    }
    declared_at_[name] = at(where_node);
    if (part) {
      part->instance_name = name;
      design.parts[name] = std::move(part);
    } else {
      design.parts[name] = nullptr;  // reserve the name; errors already reported
    }
  }

  std::string entry_name(const YAML::Node& n, std::string_view what) {
    auto name = n["name"];
    if (!name) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("each {} entry needs a 'name' to refer to it in connections", what),
            at(n));
      return "";
    }
    const std::string s = scalar(name, "name");
    if (s.empty() || s.find('.') != std::string::npos) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("name '{}' must be non-empty and contain no '.'", s),
            at(name));
      return "";
    }
    return s;
  }

  void declare_environment(const YAML::Node& n,
                           const PartsLibrary& lib,
                           Design& design,
                           std::vector<EnvDecl>& out) {
    if (!n.IsMap()) {
      error(DiagnosticCode::kMalformedInput, "an environment entry must be a mapping", at(n));
      return;
    }
    check_keys(n, {"name", "part", "params", "primitives", "frame"});
    const std::string name = entry_name(n, "environment");
    if (name.empty()) return;
    auto part = make_part(n, lib, name);
    declare_name(name, n, design, part);
    if (part) out.push_back({name, part, frame(n["frame"], name), at(n)});
  }

  void declare_part(const YAML::Node& n, const PartsLibrary& lib, Design& design, bool is_target) {
    if (!n.IsMap()) {
      error(DiagnosticCode::kMalformedInput,
            is_target ? "target must be a mapping" : "a parts entry must be a mapping",
            at(n));
      return;
    }
    if (is_target) {
      check_keys(n, {"name", "part", "params", "primitives", "primitive", "frame"});
      // A target may name a part declared under parts instead of declaring one.
      if (!n["part"] && !n["primitives"]) return;
    } else {
      check_keys(n, {"name", "part", "params", "primitives"});
    }
    const std::string name = entry_name(n, is_target ? "target" : "parts");
    if (name.empty()) return;
    declare_name(name, n, design, make_part(n, lib, name));
  }

  std::optional<PrimitiveRef> resolve(const YAML::Node& n,
                                      Design& design,
                                      std::string& text,
                                      std::string& part_name) {
    text = scalar(n, "primitive reference");
    const auto dot = text.find('.');
    if (dot == std::string::npos) {
      error(DiagnosticCode::kMalformedInput,
            fmt::format("'{}' must name a primitive as part.primitive, e.g. eyehook1.hook", text),
            at(n));
      return std::nullopt;
    }
    part_name = text.substr(0, dot);
    const std::string prim = text.substr(dot + 1);
    auto it = design.parts.find(part_name);
    if (it == design.parts.end()) {
      std::vector<std::string> names;
      for (const auto& kv : design.parts) names.push_back(kv.first);
      error(DiagnosticCode::kUnknownName,
            fmt::format(
                "no part named '{}' in this design{}", part_name, did_you_mean(part_name, names)),
            at(n));
      return std::nullopt;
    }
    if (!it->second) return std::nullopt;  // its declaration failed and was reported
    PrimitiveRef ref(it->second, prim);
    if (!ref.valid()) {
      std::vector<std::string> names;
      for (const auto& p : it->second->primitives) names.push_back(p.name);
      error(DiagnosticCode::kUnknownPrimitive,
            fmt::format("{} ({}) has no primitive '{}' (it has {}){}",
                        part_name,
                        it->second->type_name,
                        prim,
                        it->second->primitive_list(),
                        did_you_mean(prim, names)),
            at(n));
      return std::nullopt;
    }
    return ref;
  }

  void parse_connection(const YAML::Node& n, Design& design, std::vector<ConnectDecl>& out) {
    if (!n.IsMap()) {
      error(DiagnosticCode::kMalformedInput,
            "a connection must be a mapping like {connect: [a.hook, b.rod], alignment: flip}",
            at(n));
      return;
    }
    check_keys(n, {"connect", "alignment", "fixed"});
    auto pair = n["connect"];
    if (!pair || !pair.IsSequence() || pair.size() != 2) {
      error(DiagnosticCode::kMalformedInput,
            "a connection needs 'connect: [part.primitive, part.primitive]'",
            at(pair ? pair : n));
      return;
    }
    ConnectDecl d;
    d.where = at(n);
    d.options.where = d.where;
    d.options.verify = options_.verify;
    auto a = resolve(pair[0], design, d.text_a, d.name_a);
    auto b = resolve(pair[1], design, d.text_b, d.name_b);
    if (auto al = n["alignment"]) {
      const std::string s = scalar(al, "alignment");
      if (auto choice = alignment_choice_from_string(s)) {
        d.options.alignment = *choice;
      } else {
        error(DiagnosticCode::kUnknownName,
              fmt::format("alignment must be 'default' or 'flip', not '{}'", s),
              at(al));
      }
    }
    if (auto f = n["fixed"]) {
      if (auto v = boolean(f, "fixed")) d.options.fixed = *v;
    }
    if (!a || !b) return;
    d.a = *a;
    d.b = *b;
    out.push_back(std::move(d));
  }

  TargetDecl parse_target(const YAML::Node& n, Design& design) {
    TargetDecl t;
    if (!n.IsMap()) return t;
    const std::string name = n["name"] ? scalar(n["name"], "name") : "";
    auto it = design.parts.find(name);
    if (it == design.parts.end()) {
      error(DiagnosticCode::kUnknownName,
            fmt::format("target '{}' is neither declared here (give 'part') nor under parts", name),
            at(n));
      return t;
    }
    if (!it->second) return t;
    if (!n["frame"]) {
      error(DiagnosticCode::kMalformedInput, "target needs a 'frame' to aim for", at(n));
      return t;
    }
    t.part = it->second;
    t.frame = frame(n["frame"], "target frame");
    t.label = name;
    t.where = at(n);
    if (auto p = n["primitive"]) {
      const std::string pname = scalar(p, "primitive");
      t.primitive = t.part->find_primitive(pname);
      if (t.primitive < 0) {
        error(DiagnosticCode::kUnknownPrimitive,
              fmt::format("target {} ({}) has no primitive '{}' (it has {})",
                          name,
                          t.part->type_name,
                          pname,
                          t.part->primitive_list()),
              at(p));
        t.part = nullptr;
      } else {
        t.label = fmt::format("{}.{}", name, pname);
      }
    }
    return t;
  }

  std::string file_;
  const PartsLibrary& library_;
  const DesignOptions& options_;
  std::filesystem::path base_dir_;
  Diagnostics diags_;
  std::map<std::string, SourceLocation> declared_at_;
};

}  // namespace

bool is_input_error(const Diagnostic& d) {
  switch (d.code) {
    case DiagnosticCode::kMalformedInput:
    case DiagnosticCode::kUnreadableFile:
    case DiagnosticCode::kInvalidValue:
    case DiagnosticCode::kUnknownName:
    case DiagnosticCode::kUnknownPart:
    case DiagnosticCode::kUnknownPrimitive:
    case DiagnosticCode::kDuplicateName:
      return d.severity == Severity::kError;
    default:
      return false;
  }
}

Design load_design_text(std::string_view yaml,
                        std::string_view display_name,
                        const PartsLibrary& library,
                        const DesignOptions& options,
                        const std::filesystem::path& base_dir) {
  Design design;
  Reader reader(std::string(display_name), library, options, base_dir);
  reader.run(yaml, design);
  return design;
}

Design load_design(const std::filesystem::path& path,
                   const PartsLibrary& library,
                   const DesignOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    Design design;
    design.source = path;
    design.diagnostics.error(DiagnosticCode::kUnreadableFile,
                             fmt::format("'{}' is a directory, not a design file", path.string()),
                             SourceLocation{path.string(), 0, 0});
    return design;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    Design design;
    design.source = path;
    design.diagnostics.error(DiagnosticCode::kUnreadableFile,
                             fmt::format("cannot open design file '{}'", path.string()),
                             SourceLocation{path.string(), 0, 0});
    return design;
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  Design design =
      load_design_text(buffer.str(), path.string(), library, options, path.parent_path());
  design.source = path;
  return design;
}

}  // namespace fabkit::hacks
