#include "fabkit/hacks/parts_library.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>

#include "builtin_identities.h"
#include "builtin_parts_data.h"
#include "fabkit/core/file_io.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/core/names.h"
#include "fabkit/core/text.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/hacks/body_shapes.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "fabkit/hacks/primitive_spec.h"

namespace fabkit::hacks {
namespace {

std::string join(const std::vector<std::string>& items, std::string_view sep = ", ") {
  std::string out;
  for (const std::string& s : items) {
    if (!out.empty()) out += sep;
    out += s;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// YAML part files (docs/parts.md).

constexpr std::string_view kPartKeys[] = {"name",
                                          "aliases",
                                          "description",
                                          "category",
                                          "primitives",
                                          "mesh",
                                          "body",
                                          "draw_primitives",
                                          "mass",
                                          "center_of_mass"};

// Reads one YAML part file, collecting diagnostics with file:line locations.
class PartFileReader {
 public:
  PartFileReader(std::string display_name,
                 std::filesystem::path base_dir,
                 const PartsLibrary& library,
                 Diagnostics& diags)
      : base_dir_(std::move(base_dir)), library_(library), in_(std::move(display_name), diags) {}

  /// Lines of a part file to read as one document, and the file's line of each (1-based), so
  /// that messages name the file's own lines. No lines: the document is not the file's text.
  struct Excerpt {
    std::string text;
    std::vector<int> lines;
  };

  struct Entry {
    Part part;  ///< with `contents`, only its name, description and category
    std::vector<std::string> aliases;
    /// When its contents are read later: a document of the file's header and the entry alone.
    std::optional<Excerpt> contents;
  };

  // Parsed parts, or nullopt if anything was wrong. With `defer_contents` each part's
  // identity (name, aliases, description, category) is read and checked now, its contents
  // (primitives, mesh, body, mass) when read_contents() is called for it.
  std::optional<std::vector<Entry>> read(std::string_view text, bool defer_contents = false) {
    if (defer_contents) {
      if (const std::optional<SplitFile> split = split_entries(text)) {
        if (text.data() == kBuiltinPartsYaml.data() && text.size() == kBuiltinPartsYaml.size()) {
          if (auto known = read_known(*split)) return known;
        }
        return read_split(*split);
      }
    }
    const auto root = in_.parse_mapping(text, "a 'parts' list");
    if (!root) return std::nullopt;
    in_.check_keys(*root, {"fabkit", "parts"}, "a part file");
    const YAML::Node parts = (*root)["parts"];
    if (!parts) {
      in_.error(codes::kMalformedInput, "missing required key 'parts'", in_.at(*root));
    } else if (!parts.IsSequence()) {
      in_.error(codes::kMalformedInput, "'parts' must be a list of parts", in_.at(parts));
    } else {
      result_.reserve(parts.size());
      for (const YAML::Node& node : parts) {
        std::vector<std::string> aliases;
        Part part;
        std::string who;
        if (!read_identity(node, part, aliases, who)) continue;
        if (defer_contents) {
          YAML::Emitter alone;
          alone << YAML::BeginMap << YAML::Key << "parts" << YAML::Value << YAML::BeginSeq << node
                << YAML::EndSeq << YAML::EndMap;
          result_.push_back(
              {std::move(part), std::move(aliases), Excerpt{std::string(alone.c_str()), {}}});
        } else if (read_contents(node, part, who)) {
          result_.push_back({std::move(part), std::move(aliases), std::nullopt});
        }
      }
    }
    if (in_.errors() > 0) return std::nullopt;
    return std::move(result_);
  }

 private:
  // The part's name, aliases, description and category (checked against the library and
  // this file); false if any is wrong.
  // A part file laid out as the built-in one is: a header ending in a `parts:` line, then one
  // entry per `  - ` line, each opening with its identity keys (name, aliases, description,
  // category) before anything else.
  struct SplitFile {
    std::vector<std::string_view> lines;
    std::size_t parts_line = 0;  // index of the `parts:` line
    struct Span {
      std::size_t first = 0, end = 0;  // the entry's lines [first, end)
      std::size_t head_end = 0;        // its identity lines end here
    };
    std::vector<Span> entries;
  };

  // The layout of `text`, or nullopt where it is not as above (the file is then read whole).
  static std::optional<SplitFile> split_entries(std::string_view text) {
    SplitFile f;
    for (std::size_t at = 0; at <= text.size();) {
      const std::size_t end = std::min(text.find('\n', at), text.size());
      f.lines.push_back(text.substr(at, end - at));
      at = end + 1;
    }
    auto starts = [](std::string_view line, std::string_view prefix) {
      return line.substr(0, prefix.size()) == prefix;
    };
    auto blank_or_comment = [](std::string_view line) {
      const std::size_t c = line.find_first_not_of(' ');
      return c == std::string_view::npos || line[c] == '#';
    };
    auto identity_line = [&](std::string_view line) {
      for (std::string_view key : {"name:", "aliases:", "description:", "category:"}) {
        if (starts(line, std::string("    ") + std::string(key))) return true;
      }
      return false;
    };
    std::size_t i = 0;
    while (i < f.lines.size() && f.lines[i] != "parts:") ++i;
    if (i == f.lines.size()) return std::nullopt;
    f.parts_line = i;
    for (++i; i < f.lines.size(); ++i) {
      const std::string_view line = f.lines[i];
      if (starts(line, "  - ")) {
        if (!f.entries.empty()) f.entries.back().end = i;
        f.entries.push_back({i, f.lines.size(), i + 1});
      } else if (!blank_or_comment(line) && (f.entries.empty() || !starts(line, "    "))) {
        return std::nullopt;  // something else at the top level, or a stray line
      }
    }
    for (SplitFile::Span& e : f.entries) {
      // Identity lines, and what continues their values on deeper lines (a folded
      // description, an alias list written one per line).
      std::size_t k = e.first + 1;
      while (k < e.end && (blank_or_comment(f.lines[k]) || identity_line(f.lines[k]) ||
                           starts(f.lines[k], "      "))) {
        ++k;
      }
      e.head_end = k;
      for (; k < e.end; ++k) {
        if (identity_line(f.lines[k])) return std::nullopt;  // an identity key further down
      }
    }
    if (f.entries.empty()) return std::nullopt;
    return f;
  }

  // The file's header and the lines `keep` says, each with the file's line it is: the lines
  // left out are not in the document at all (yaml-cpp scans about 100 ns a byte, and a part's
  // document that kept the whole file's other lines blank spent half its reading on them).
  // Comment lines are blank: the header's comments went into every document (a fifth of each
  // part's reading). A '#' no deeper than an entry's keys (column 4) cannot be inside a block
  // scalar: those lines are deeper than their key.
  template <class Keep>
  static Excerpt with_lines(const SplitFile& f, Keep keep) {
    auto comment = [](std::string_view line) {
      const std::size_t c = line.find_first_not_of(' ');
      return c != std::string_view::npos && c <= 4 && line[c] == '#';
    };
    Excerpt out;
    for (std::size_t i = 0; i < f.lines.size(); ++i) {
      if (i > f.parts_line && !keep(i)) continue;
      if (!comment(f.lines[i])) out.text += f.lines[i];
      out.text += '\n';
      out.lines.push_back(static_cast<int>(i) + 1);
    }
    return out;
  }

  // The embedded built-in file's entries with the identities the build read from it
  // (hacks/tools/builtin_identities.cpp, which checks them as read_identity does): a process
  // does not parse them again (yaml-cpp took a quarter of a small design's `fabkit check` to).
  // Each entry's contents are kept as read_split keeps them. Nullopt where the table does not
  // name the file's entries in order (then they are read from the file).
  std::optional<std::vector<Entry>> read_known(const SplitFile& f) {
    const std::vector<builtin::Identity>& known = builtin::kIdentities;
    if (known.size() != f.entries.size()) return std::nullopt;
    std::vector<Entry> out;
    out.reserve(known.size());
    for (std::size_t k = 0; k < known.size(); ++k) {
      const SplitFile::Span& e = f.entries[k];
      const builtin::Identity& id = known[k];
      if (f.lines[e.first] != fmt::format("  - name: {}", id.name)) return std::nullopt;
      Part part;
      part.type_name = std::string(id.name);
      part.description = std::string(id.description);
      part.category = category_named(id.category).value_or(PartCategory::kOther);
      std::vector<std::string> aliases(id.aliases.begin(), id.aliases.end());
      out.push_back({std::move(part), std::move(aliases), with_lines(f, [&](std::size_t i) {
                       return i >= e.first && i < e.end;
                     })});
    }
    return out;
  }

  // Reads the identities of every entry from one document of their identity lines; each entry's
  // contents are kept as a document of the header and that entry alone.
  std::optional<std::vector<Entry>> read_split(const SplitFile& f) {
    std::vector<char> head(f.lines.size(), 0);
    for (const SplitFile::Span& e : f.entries) {
      for (std::size_t k = e.first; k < e.head_end; ++k) head[k] = 1;
    }
    Excerpt identities = with_lines(f, [&](std::size_t i) { return head[i] != 0; });
    in_.set_line_numbers(std::move(identities.lines));
    const auto root = in_.parse_mapping(identities.text, "a 'parts' list");
    if (!root) return std::nullopt;
    in_.check_keys(*root, {"fabkit", "parts"}, "a part file");
    const YAML::Node parts = (*root)["parts"];
    if (!parts || !parts.IsSequence() || parts.size() != f.entries.size()) return std::nullopt;
    result_.reserve(parts.size());
    std::size_t index = 0;
    for (const YAML::Node& node : parts) {
      const SplitFile::Span& e = f.entries[index++];
      std::vector<std::string> aliases;
      Part part;
      std::string who;
      if (!read_identity(node, part, aliases, who)) continue;
      result_.push_back({std::move(part), std::move(aliases), with_lines(f, [&](std::size_t i) {
                           return i >= e.first && i < e.end;
                         })});
    }
    if (in_.errors() > 0) return std::nullopt;
    return std::move(result_);
  }

  bool read_identity(const YAML::Node& node,
                     Part& part,
                     std::vector<std::string>& aliases,
                     std::string& who) {
    const int errors_before = in_.errors();
    if (!in_.is_mapping(node, "each entry of 'parts'")) return false;
    in_.check_keys(node, kPartKeys, "a part");
    part.category = PartCategory::kOther;

    who = "part";
    if (const YAML::Node n = node["name"]; !n) {
      in_.error(codes::kMalformedInput, "part is missing required key 'name'", in_.at(node));
    } else if (const auto name = in_.string(n, "part name", 128)) {
      const SourceLocation where = in_.at(n);
      if (!is_identifier(*name)) {
        in_.error(codes::kInvalidValue,
                  fmt::format("part name '{}' must be an identifier (letters, digits, _)",
                              excerpt(*name, 40)),
                  where);
      } else if (const PartGenerator* existing = library_.find(*name)) {
        in_.error(
            codes::kDuplicateName,
            fmt::format(
                "part name '{}' is already used by the library part {}", *name, existing->name),
            where);
      } else if (!names_.insert(ascii_lower(*name)).second) {
        in_.error(codes::kDuplicateName,
                  fmt::format("part '{}' is defined twice in this file", *name),
                  where);
      }
      part.type_name = *name;
      who = *name;
    }
    if (const YAML::Node al = node["aliases"]) {
      if (in_.is_list(al, fmt::format("aliases of part {}", who))) {
        for (const YAML::Node& a : al) {
          auto name = in_.string(a, "alias", 128);
          if (!name) continue;
          if (!is_identifier(*name) || library_.find(*name) ||
              !names_.insert(ascii_lower(*name)).second) {
            in_.error(codes::kDuplicateName,
                      fmt::format(
                          "alias '{}' of part {} is not a new identifier", excerpt(*name, 40), who),
                      in_.at(a));
            continue;
          }
          aliases.push_back(*name);
        }
      }
    }
    if (const YAML::Node d = node["description"]) {
      if (const auto text = in_.string(d, "description")) part.description = *text;
    }
    if (const YAML::Node cn = node["category"]) {
      if (const auto c = in_.string(cn, "category", 64)) {
        if (const std::optional<PartCategory> named = category_named(*c)) {
          part.category = *named;
        } else {
          in_.error(codes::kUnknownName,
                    fmt::format("unknown category '{}'; valid: environment, hack, both, other",
                                excerpt(*c, 40)),
                    in_.at(cn));
        }
      }
    }

    return in_.errors() == errors_before;
  }

 public:
  // The rest of the part: primitives, mesh, body, mass properties; false if any is wrong.
  // The contents of the one entry of a deferred entry's document (Entry::contents).
  bool read_deferred(const Excerpt& document, Part& part, const std::string& who) {
    in_.set_line_numbers(document.lines);
    const auto root = in_.parse_mapping(document.text, "a 'parts' list");
    if (!root) return false;
    const YAML::Node parts = (*root)["parts"];
    if (!parts || !parts.IsSequence() || parts.size() != 1) {
      in_.error(codes::kMalformedInput, "a deferred part must be one entry", in_.at(*root));
      return false;
    }
    return read_contents(parts[0], part, who);
  }

  bool read_contents(const YAML::Node& node, Part& part, const std::string& who) {
    const int errors_before = in_.errors();
    // Primitives.
    if (const YAML::Node list = node["primitives"]; !list) {
      in_.error(codes::kMalformedInput,
                fmt::format("part {} is missing required key 'primitives'", who),
                in_.at(node));
    } else if (!list.IsSequence() || list.size() == 0) {
      in_.error(codes::kMalformedInput,
                fmt::format("'primitives' of part {} must be a non-empty list", who),
                in_.at(list));
    } else {
      std::set<std::string> prim_names;
      for (const YAML::Node& pn : list) {
        auto p = read_primitive_spec(in_, pn, who, std::nullopt);
        if (!p) continue;
        if (!prim_names.insert(p->name).second) {
          in_.error(codes::kDuplicateName,
                    fmt::format("part {} has two primitives called '{}'", who, p->name),
                    in_.at(pn));
          continue;
        }
        part.primitives.push_back(std::move(*p));
      }
    }

    // Mesh: from the file if given, else drawn from the primitives.
    std::optional<SourceLocation> mesh_where;
    if (const YAML::Node mn = node["mesh"]) {
      mesh_where = in_.at(mn);
      if (const auto rel = in_.string(mn, "mesh")) {
        std::filesystem::path mesh_path(*rel);
        if (mesh_path.is_relative()) mesh_path = base_dir_ / mesh_path;
        Diagnostics mesh_diags;
        if (auto mesh = read_mesh(mesh_path, mesh_diags)) {
          if (mesh->empty()) {
            in_.error(codes::kInvalidValue,
                      fmt::format("mesh file '{}' has no triangles", mesh_path.string()),
                      *mesh_where);
          }
          part.mesh = std::move(*mesh);
        } else {
          const DiagnosticCode code =
              mesh_diags.empty() ? codes::kUnreadableFile : mesh_diags.items().front().code;
          in_.error(code,
                    fmt::format("mesh of part {}: {}",
                                who,
                                mesh_diags.empty() ? std::string("unknown error")
                                                   : mesh_diags.items().front().format()),
                    *mesh_where);
        }
      }
    }
    if (const YAML::Node bn = node["body"]) {
      if (!mesh_where) mesh_where = in_.at(bn);
      std::vector<TriangleMesh> pieces;
      if (auto body = read_body(in_, bn, who, &pieces)) {
        part.mesh.append(*body);
        for (TriangleMesh& piece : pieces) {
          part.collision_pieces.push_back(std::move(piece));
          part.collision_tags.push_back(-1);
        }
      }
    }
    // With a body, or with nothing but its connectors, the object's shape is known (its
    // connectors are part of it); a scanned mesh alone gives no convex pieces.
    if (node["body"] || !node["mesh"]) {
      for (std::size_t i = 0; i < part.primitives.size(); ++i) {
        add_primitive_pieces(part, static_cast<int>(i));
      }
    }
    // The primitives are drawn too, unless a scanned mesh already shows them.
    bool draw_primitives = !node["mesh"];
    if (const YAML::Node dp = node["draw_primitives"]) {
      draw_primitives = in_.boolean(dp, "draw_primitives").value_or(draw_primitives);
    }
    if (in_.errors() > errors_before) return false;
    if (draw_primitives) {
      for (const Primitive& p : part.primitives) part.mesh.append(primitive_mesh(p));
    }

    // Mass properties: explicit values win; otherwise the mesh at density 1 (reference §10.1).
    if (const YAML::Node mn = node["mass"]) {
      if (const auto m = in_.number(mn, fmt::format("mass of part {}", who))) {
        if (*m <= 0) {
          in_.error(
              codes::kInvalidValue,
              fmt::format("mass {:g} of part {} must be positive (mm³ at density 1)", *m, who),
              in_.at(mn));
        }
        part.mass = *m;
      }
    } else {
      part.mass = std::abs(part.mesh.volume());
      if (!(part.mass > 1e-9)) {
        in_.error(
            codes::kInvalidValue,
            fmt::format("the mesh of part {} encloses no volume; give 'mass' explicitly", who),
            mesh_where.value_or(in_.at(node)));
      }
    }
    if (const YAML::Node cn = node["center_of_mass"]) {
      if (const auto c =
              in_.vec3(cn, "center_of_mass", {-kMaxCoordinateMm, kMaxCoordinateMm, "mm"})) {
        part.center_of_mass = *c;
      }
    } else {
      part.center_of_mass = part.mesh.centroid();
    }
    return in_.errors() == errors_before;
  }

 private:
  std::filesystem::path base_dir_;
  const PartsLibrary& library_;
  YamlReader in_;
  std::set<std::string> names_;  // lower-case part (and alias) names defined in this file
  std::vector<Entry> result_;
};

// A part whose contents are read on first use (PartLoading::kOnFirstUse), once, from its own
// document (the file's header and the entry at its own lines: a solve of three parts parses
// three entries, not the whole file); later uses copy it without a lock.
class DeferredPart {
 public:
  DeferredPart(std::string file,
               std::filesystem::path base_dir,
               PartFileReader::Excerpt document,
               Part identity)
      : file_(std::move(file)),
        base_dir_(std::move(base_dir)),
        document_(std::move(document)),
        identity_(std::move(identity)) {}

  Part get() {
    // A throw leaves the flag unset: the next use tries again, and throws again.
    std::call_once(built_, [this] {
      Diagnostics diags;
      const PartsLibrary none;
      PartFileReader reader(file_, base_dir_, none, diags);
      Part part = identity_;
      // Only files tested to load (the built-in one) are read so: a failure is a bug here.
      if (!reader.read_deferred(document_, part, identity_.type_name)) {
        throw std::logic_error(fmt::format(
            "{}: part {} did not load: {}",
            file_,
            identity_.type_name,
            diags.empty() ? std::string("unknown error") : diags.items().front().format()));
      }
      part_ = std::move(part);
      document_ = {};
    });
    return *part_;
  }

 private:
  std::string file_;
  std::filesystem::path base_dir_;
  PartFileReader::Excerpt document_;
  Part identity_;
  std::optional<Part> part_;
  std::once_flag built_;
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
  const std::string l = ascii_lower(name);
  for (const PartGenerator& g : generators_) {
    if (ascii_lower(g.name) == l) return &g;
    for (const std::string& a : g.aliases) {
      if (ascii_lower(a) == l) return &g;
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
    std::string msg = fmt::format("unknown part '{}'", excerpt(name, 60));
    const std::string near = suggest(name);
    if (!near.empty()) msg += fmt::format("; did you mean {}?", near);
    diags.error(codes::kUnknownPart, std::move(msg), where);
    return nullptr;
  }

  bool ok = true;
  std::vector<std::string> valid;
  for (const ParamSchema& s : gen->params) valid.push_back(s.name);
  for (const auto& [key, value] : params) {
    const std::string& wanted = key;  // (clang 14 cannot capture a structured binding)
    const auto it = std::find_if(gen->params.begin(), gen->params.end(), [&](const ParamSchema& s) {
      return s.name == wanted;
    });
    if (it == gen->params.end()) {
      std::string msg;
      if (valid.empty()) {
        msg = fmt::format("part {} has no parameters (got '{}')", gen->name, excerpt(key, 60));
      } else {
        msg = fmt::format("part {} has no parameter '{}'", gen->name, excerpt(key, 60));
        const std::string near = closest_name(key, valid);
        if (!near.empty()) msg += fmt::format(" (did you mean '{}'?)", near);
        msg += fmt::format("; valid parameters: {}", join(valid));
      }
      diags.error(codes::kUnknownName, std::move(msg), where);
      ok = false;
      continue;
    }
    const ParamSchema& s = *it;
    if (!std::isfinite(value)) {
      diags.error(codes::kInvalidValue,
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
      diags.error(codes::kInvalidValue,
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
  const auto text = read_input_file(path, "part file", diags);
  if (!text) return false;
  return load_yaml_text(*text, path.string(), path.parent_path(), diags);
}

bool PartsLibrary::load_yaml_text(std::string_view text,
                                  std::string_view display_name,
                                  const std::filesystem::path& base_dir,
                                  Diagnostics& diags,
                                  PartCategory default_category,
                                  PartLoading loading) {
  PartFileReader reader(std::string(display_name), base_dir, *this, diags);
  auto entries = reader.read(text, loading == PartLoading::kOnFirstUse);
  if (!entries) return false;
  for (auto& [part, aliases, contents] : *entries) {
    if (part.category == PartCategory::kOther) part.category = default_category;
    PartGenerator g;
    g.name = part.type_name;
    g.aliases = aliases;
    g.description = part.description;
    g.category = part.category;
    if (!contents) {
      auto shared = std::make_shared<const Part>(std::move(part));
      g.build = [shared](const ParamValues&) { return *shared; };
    } else {
      g.build = [deferred = std::make_shared<DeferredPart>(
                     std::string(display_name), base_dir, std::move(*contents), std::move(part))](
                    const ParamValues&) { return deferred->get(); };
    }
    add(std::move(g));
  }
  return true;
}
}  // namespace fabkit::hacks
