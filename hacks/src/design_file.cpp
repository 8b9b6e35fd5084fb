#include "fabkit/hacks/design_file.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cmath>
#include <set>

#include "fabkit/core/file_io.h"
#include "fabkit/core/stop_clock.h"
#include "fabkit/core/text.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/hacks/deadline.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "fabkit/hacks/primitive_spec.h"

namespace fabkit::hacks {
namespace {

constexpr std::string_view kFormatTag = "hacks/1";

// Reads one file's YAML into the design, collecting diagnostics with file:line.
class Reader {
 public:
  Reader(std::string file,
         const PartsLibrary& library,
         const DesignOptions& options,
         std::filesystem::path base_dir)
      : file_(file),
        library_(library),
        options_(options),
        base_dir_(std::move(base_dir)),
        in_(std::move(file), diags_) {}

  void run(std::string_view text, Design& design) {
    build(text, design);
    design.diagnostics = diags_;
  }

 private:
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
    PrimitiveId primitive;
    Frame frame;
    std::string label;
    SourceLocation where;
  };

  void build(std::string_view text, Design& design) {
    const auto parsed = in_.parse_mapping(
        text, "environment, parts, connections and target (docs/design-format.md)");
    if (!parsed) return;
    const YAML::Node root = *parsed;
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
        error(codes::kMalformedInput,
              fmt::format(
                  "unsupported format '{}'; this version reads '{}'", excerpt(t, 40), kFormatTag),
              at(tag));
      }
    }
    if (auto n = root["name"]) design.name = scalar(n, "name");
    if (auto d = root["description"]) design.description = scalar(d, "description");

    // Size limits before any work (parts made, part files read, connects verified).
    if (options_.max_parts > 0) {
      std::size_t count = 0;
      for (const char* key : {"environment", "parts"}) {
        if (auto n = root[key]; n && n.IsSequence()) count += n.size();
      }
      if (root["target"]) ++count;
      if (count > static_cast<std::size_t>(options_.max_parts)) {
        error(
            codes::kLimitExceeded,
            fmt::format("the design has {} parts; the limit here is {}", count, options_.max_parts),
            SourceLocation{file_, 1, 1});
        return;
      }
    }
    if (auto conns = root["connections"];
        conns && conns.IsSequence() && options_.max_connections > 0 &&
        conns.size() > static_cast<std::size_t>(options_.max_connections)) {
      error(codes::kLimitExceeded,
            fmt::format("the design has {} connections; the limit here is {}",
                        conns.size(),
                        options_.max_connections),
            at(conns));
      return;
    }

    PartsLibrary local = library_;
    const PartsLibrary* lib = &library_;
    if (auto files = root["part_files"]) {
      if (options_.part_files == PartFilePolicy::kRefuse) {
        error(codes::kInvalidValue,
              "part_files are not accepted here: a design sent to the server may not name files "
              "(load part files when starting it, or use the command line)",
              at(files));
      } else if (!files.IsSequence()) {
        error(codes::kMalformedInput, "part_files must be a list of file names", at(files));
      } else {
        for (const auto& f : files) {
          const std::string name = scalar(f, "part file");
          if (name.empty()) continue;
          const std::filesystem::path p = base_dir_ / name;
          Diagnostics d;
          if (!local.load_yaml(p, d)) {
            for (Diagnostic x : d) {
              // Problems with the file as a whole are located at the line naming it.
              if (!x.where.known() || x.where.line == 0) x.where = at(f);
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
        error(codes::kMalformedInput, "environment must be a list of entries", at(env));
      } else if (env.IsMap()) {
        declare_environment(env, *lib, design, environments);
      } else {
        for (const auto& e : env) declare_environment(e, *lib, design, environments);
      }
    } else {
      error(codes::kMalformedInput,
            "the design has no 'environment': a hack must hang from something fixed",
            SourceLocation{file_, 1, 1});
    }
    if (auto parts = root["parts"]) {
      if (!parts.IsSequence()) {
        error(codes::kMalformedInput, "parts must be a list", at(parts));
      } else {
        // Making a part (its mesh, its collision body) is most of reading a long design: a
        // 400-part chain's parts took 23-36 ms, past a deadline nothing else looked at.
        const std::size_t total = parts.size();
        std::size_t made = 0;
        for (const auto& p : parts) {
          if (past_deadline()) {
            diags_.error(codes::kTimeLimit,
                         fmt::format("stopped at the deadline after making {} of {} parts; nothing "
                                     "was verified",
                                     made,
                                     total),
                         at(p));
            design.readable = true;  // read and understood as far as it went: not bad input
            return;
          }
          declare_part(p, *lib, design, /*is_target=*/false);
          ++made;
        }
      }
    }
    YAML::Node target = root["target"];
    if (target) declare_part(target, *lib, design, /*is_target=*/true);

    std::vector<ConnectDecl> connects;
    if (auto conns = root["connections"]) {
      if (!conns.IsSequence()) {
        error(codes::kMalformedInput, "connections must be a list", at(conns));
      } else {
        for (const auto& c : conns) parse_connection(c, design, connects);
      }
    }
    TargetDecl tdecl;
    if (target) tdecl = parse_target(target, design);

    if (diags_.has_errors()) return;  // input errors: build nothing
    design.readable = true;

    // Each cycle's closure search is most of the verification, and the design is solved in the
    // canonical order of its connects whatever the file's: the connects are made in the file's
    // order with their cycles left open (every other check still runs there, with the file's
    // lines), then once in the canonical order with the closure searches. Only where that does
    // not verify is everything made again in the file's order with closures, for the messages
    // the file's order gives.
    const Assembly unbuilt = design.assembly;
    const Diagnostics before = diags_;
    std::set<const Part*> missing;  // parts whose introducing connect failed
    bool stopped = false;
    if (!make_steps(
            design, environments, connects, tdecl, /*defer_closures=*/true, missing, stopped)) {
      design.assembly = unbuilt;
      design.steps.clear();
      diags_ = before;
      missing.clear();
      stopped = false;
      make_steps(design, environments, connects, tdecl, /*defer_closures=*/false, missing, stopped);
    }
    for (const auto& [name, part] : design.parts) {
      if (stopped) break;  // unverified connects: "never connected" would be wrong
      if (!design.assembly.find(part.get()) && !missing.count(part.get())) {
        diags_.warning(codes::kNotConnected,
                       fmt::format("part {} is declared but never connected", name),
                       declared_at_[name]);
      }
    }
  }

  // The design's adds, connects and end_with, as steps (design.steps). With `defer_closures`,
  // the connects are made with their cycles open and then every connect again in the canonical
  // order with the closure searches (Assembly::verified_in_canonical_order), each step getting
  // its connect's report from there; false (the steps and diagnostics left for the caller to
  // discard) where anything fails that way. Without it, each connect verifies as the file
  // makes it, and the design is what that gives; true.
  bool make_steps(Design& design,
                  const std::vector<EnvDecl>& environments,
                  const std::vector<ConnectDecl>& connects,
                  const TargetDecl& tdecl,
                  bool defer_closures,
                  std::set<const Part*>& missing,
                  bool& stopped) {
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
    std::size_t verified = 0;
    for (const ConnectDecl& c : connects) {
      if (past_deadline()) {
        stop_at_deadline(design, connects, verified, c.where);
        stopped = true;
        break;
      }
      ++verified;
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
                    codes::kNotInAssembly,
                    fmt::format("skipped {}: {} is not in the assembly because an earlier connect "
                                "failed",
                                step.text,
                                missing.count(c.a.part.get()) ? c.name_a : c.name_b),
                    c.where});
        design.steps.push_back(std::move(step));
        continue;
      }
      ConnectOptions options = c.options;
      if (defer_closures) options.verify.close_cycles = false;
      step.report = design.assembly.connect(c.a, c.b, options);
      step.accepted = step.report.accepted;
      if (!step.accepted) mark_cut_by_deadline(step.report, options_.verify);
      if (!step.accepted) {
        if (!a_in) missing.insert(c.a.part.get());
        if (!b_in) missing.insert(c.b.part.get());
      }
      diags_.append(step.report.diagnostics);
      design.steps.push_back(std::move(step));
    }
    if (tdecl.part && !stopped) {
      DesignStep step;
      step.kind = DesignStep::Kind::kEndWith;
      step.where = tdecl.where;
      step.text = fmt::format("end_with {} at {}", tdecl.label, tdecl.frame.to_string());
      Diagnostics d = tdecl.primitive.valid()
                          ? design.assembly.end_with(
                                PrimitiveRef(tdecl.part, tdecl.primitive), tdecl.frame, tdecl.where)
                          : design.assembly.end_with(tdecl.part, tdecl.frame, tdecl.where);
      step.accepted = !d.has_errors();
      step.report.accepted = step.accepted;
      step.report.diagnostics = d;
      diags_.append(d);
      if (step.accepted && !design.assembly.find(tdecl.part.get())) {
        diags_.error(codes::kTargetMissing,
                     fmt::format("the target {} is not connected to the hack", tdecl.label),
                     tdecl.where);
      }
      design.steps.push_back(std::move(step));
    }
    // Verified in the file's order as it went: where the canonical order did not verify, the
    // design stands (or fails) as the file made it.
    if (!defer_closures) return true;
    if (stopped || diags_.has_errors()) return false;
    std::vector<ConnectReport> reports;
    std::optional<Assembly> made =
        design.assembly.verified_in_canonical_order(options_.verify.deadline, &reports);
    if (!made && past_deadline()) {
      // The deadline cut the closure searches: say how far they got. (The file's order, made
      // again now, would stop before its first connect and say none was verified.)
      std::size_t closed = 0;
      std::optional<SourceLocation> first_open;
      std::size_t k = 0;
      for (const DesignStep& step : design.steps) {
        if (step.kind != DesignStep::Kind::kConnect) continue;
        if (reports.at(k++).accepted) {
          ++closed;
        } else if (!first_open) {
          first_open = step.where;
        }
      }
      if (first_open) {
        diags_.error(codes::kTimeLimit,
                     fmt::format("stopped at the deadline after {} iteration{} (connects verified "
                                 "in the canonical order of the connects, which the design is "
                                 "made in, of {}); this connect and the other {} were not "
                                 "verified",
                                 closed,
                                 closed == 1 ? "" : "s",
                                 connects.size(),
                                 connects.size() - closed - 1),
                     *first_open);
        stopped = true;
        return true;
      }
    }
    if (!made) return false;
    design.assembly = std::move(*made);
    // Each connect's step reports how it verified in the canonical order: a cycle is closed by
    // the connect that completes it there (a chain between two rods: in its middle).
    std::size_t k = 0;
    for (DesignStep& step : design.steps) {
      if (step.kind != DesignStep::Kind::kConnect) continue;
      ConnectReport r = std::move(reports.at(k++));
      r.description = step.report.description;
      step.report = std::move(r);
    }
    return true;
  }

  // The verification's deadline passed before `where`: the remaining connects are not tried.
  template <typename Connects>
  void stop_at_deadline(Design& design,
                        const Connects& connects,
                        std::size_t verified,
                        const SourceLocation& where) {
    diags_.error(codes::kTimeLimit,
                 fmt::format("stopped at the deadline after {} iteration{} (connects verified, of "
                             "{}); this connect and the {} after it were not verified",
                             verified,
                             verified == 1 ? "" : "s",
                             connects.size(),
                             connects.size() - verified - 1),
                 where);
    for (std::size_t k = verified; k < connects.size(); ++k) {
      DesignStep step;
      step.kind = DesignStep::Kind::kConnect;
      step.where = connects[k].where;
      step.text = fmt::format("connect {}, {}", connects[k].text_a, connects[k].text_b);
      step.skipped = true;
      design.steps.push_back(std::move(step));
    }
  }

  // Whether the verification's deadline has passed (reading stops at it as verifying does).
  bool past_deadline() const { return deadline_passed(options_.verify.deadline); }

  SourceLocation at(const YAML::Node& n) const { return in_.at(n); }
  void error(DiagnosticCode code, std::string msg, SourceLocation where) {
    in_.error(code, std::move(msg), std::move(where));
  }
  void check_keys(const YAML::Node& map, std::initializer_list<std::string_view> allowed) {
    in_.check_keys(map, allowed);
  }
  // The value of a scalar; "" (reported) if it is not one.
  std::string scalar(const YAML::Node& n, std::string_view what) {
    return in_.string(n, what).value_or("");
  }
  std::optional<double> number(const YAML::Node& n, std::string_view what) {
    return in_.number(n, what);
  }
  std::optional<bool> boolean(const YAML::Node& n, std::string_view what) {
    return in_.boolean(n, what);
  }
  Frame frame(const YAML::Node& n, std::string_view what) {
    if (!n) return Frame();
    return in_.frame(n, what).value_or(Frame());
  }

  std::shared_ptr<Part> make_part(const YAML::Node& n,
                                  const PartsLibrary& lib,
                                  const std::string& name) {
    if (auto prims = n["primitives"]) {
      if (n["part"]) {
        error(codes::kMalformedInput,
              fmt::format("{}: give either 'part' or 'primitives', not both", name),
              at(n));
        return nullptr;
      }
      return make_primitives(prims, name);
    }
    auto type = n["part"];
    if (!type) {
      error(codes::kMalformedInput,
            fmt::format("{}: missing 'part' (a library part name) or 'primitives'", name),
            at(n));
      return nullptr;
    }
    ParamValues values;
    if (auto params = n["params"]) {
      if (!params.IsMap()) {
        error(codes::kMalformedInput, "params must be a mapping name: value", at(params));
        return nullptr;
      }
      for (const auto& kv : params) {
        const std::string key = scalar(kv.first, "parameter name");
        if (auto v = number(kv.second, fmt::format("parameter {}", key))) values[key] = *v;
      }
    }
    const std::optional<std::string> part_name = in_.string(type, "part");
    if (!part_name) return nullptr;  // said why (not text, not UTF-8, too long)
    Diagnostics d;
    auto part = lib.make(*part_name, values, d, at(type));
    diags_.append(d);
    return part;
  }

  std::shared_ptr<Part> make_primitives(const YAML::Node& prims, const std::string& name) {
    if (!prims.IsMap() || prims.size() == 0) {
      error(codes::kMalformedInput,
            fmt::format("{}: primitives must map names to primitives, e.g. "
                        "{{rod: {{type: rod, radius: 5, length: 500}}}}",
                        name),
            at(prims));
      return nullptr;
    }
    std::vector<Primitive> list;
    bool failed = false;
    for (const auto& kv : prims) {
      const auto pname = in_.name(kv.first, "primitive name");
      auto p = pname ? read_primitive_spec(in_, kv.second, name, *pname) : std::nullopt;
      if (p) {
        list.push_back(std::move(*p));
      } else {
        failed = true;
      }
    }
    // A primitive that could not be read was reported where it is written; without it the
    // environment is not the one described, and connects to it would only repeat the error
    // as "has no primitive" (nothing is solved with an error anyway).
    if (failed) return nullptr;
    return std::make_shared<Part>(make_primitive_part(std::move(list)));
  }

  void declare_name(const std::string& name,
                    const YAML::Node& where_node,
                    Design& design,
                    std::shared_ptr<Part> part) {
    if (name.empty()) return;
    if (design.parts.count(name)) {
      error(codes::kDuplicateName,
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
      error(codes::kMalformedInput,
            fmt::format("each {} entry needs a 'name' to refer to it in connections", what),
            at(n));
      return "";
    }
    const std::optional<std::string> read = in_.string(name, "name", 128);
    if (!read) return "";  // said why (not text, not UTF-8, too long)
    const std::string& s = *read;
    if (s.empty() || s.find('.') != std::string::npos) {
      error(codes::kMalformedInput,
            fmt::format("name '{}' must be non-empty and contain no '.'", excerpt(s, 60)),
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
      error(codes::kMalformedInput, "an environment entry must be a mapping", at(n));
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
      error(codes::kMalformedInput,
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
      error(codes::kMalformedInput,
            fmt::format("'{}' must name a primitive as part.primitive, e.g. eyehook1.hook",
                        excerpt(text, 60)),
            at(n));
      return std::nullopt;
    }
    part_name = text.substr(0, dot);
    const std::string prim = text.substr(dot + 1);
    auto it = design.parts.find(part_name);
    if (it == design.parts.end()) {
      std::vector<std::string> names;
      for (const auto& kv : design.parts) names.push_back(kv.first);
      error(codes::kUnknownName,
            fmt::format("no part named '{}' in this design{}",
                        excerpt(part_name, 60),
                        did_you_mean(part_name, names)),
            at(n));
      return std::nullopt;
    }
    if (!it->second) return std::nullopt;  // its declaration failed and was reported
    PrimitiveRef ref(it->second, prim);
    if (!ref.valid()) {
      std::vector<std::string> names;
      for (const auto& p : it->second->primitives) names.push_back(p.name);
      error(codes::kUnknownPrimitive,
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
      error(codes::kMalformedInput,
            "a connection must be a mapping like {connect: [a.hook, b.rod], alignment: flip}",
            at(n));
      return;
    }
    check_keys(n, {"connect", "alignment", "fixed"});
    auto pair = n["connect"];
    if (!pair || !pair.IsSequence() || pair.size() != 2) {
      error(codes::kMalformedInput,
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
        error(codes::kUnknownName,
              fmt::format("alignment must be 'default' or 'flip', not '{}'", excerpt(s, 40)),
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
      error(codes::kUnknownName,
            fmt::format("target '{}' is neither declared here (give 'part') nor under parts",
                        excerpt(name, 60)),
            at(n));
      return t;
    }
    if (!it->second) return t;
    if (!n["frame"]) {
      error(codes::kMalformedInput, "target needs a 'frame' to aim for", at(n));
      return t;
    }
    t.part = it->second;
    t.frame = frame(n["frame"], "target frame");
    t.label = name;
    t.where = at(n);
    if (auto p = n["primitive"]) {
      const std::string pname = scalar(p, "primitive");
      t.primitive = t.part->find_primitive(pname);
      if (!t.primitive.valid()) {
        error(codes::kUnknownPrimitive,
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
  YamlReader in_;
  std::map<std::string, SourceLocation> declared_at_;
};

}  // namespace

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
  Diagnostics read;
  const auto text = read_input_file(path, "design file", read);
  if (!text) {
    Design design;
    design.source = path;
    design.diagnostics = read;
    return design;
  }
  Design design = load_design_text(*text, path.string(), library, options, path.parent_path());
  design.source = path;
  return design;
}

}  // namespace fabkit::hacks
