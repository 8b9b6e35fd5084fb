#pragma once
/// The annotated object library: named part generators with a typed parameter schema.

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/hacks/part.h"

namespace fabkit::hacks {

/// One parameter of a parametric part; drives CLI, Python kwargs, the web form and docs.
struct ParamSchema {
  std::string name;
  double default_value = 0;
  double min = 0;
  double max = 0;
  std::string unit;  ///< "mm"
  std::string doc;
};

using ParamValues = std::map<std::string, double>;

/// Builds a part from validated parameter values (every schema entry present, in range).
struct PartGenerator {
  std::string name;
  std::vector<std::string> aliases;  ///< other spellings, e.g. the paper's "HookEyeLeft5"
  std::string description;
  PartCategory category = PartCategory::kOther;
  std::vector<ParamSchema> params;
  std::function<Part(const ParamValues&)> build;
};

/// When a part file's parts are read: all of each part now (user files: every mistake is
/// reported at once), or its identity now and its contents when the part is first made (the
/// built-in file, tested to load: a process that uses three parts builds three).
enum class PartLoading { kEager, kOnFirstUse };

class PartsLibrary {
 public:
  /// Every part of the paper's library (reference §10.2) plus ParamTurnbuckle / ParamHanger.
  static const PartsLibrary& builtin();

  void add(PartGenerator generator);
  /// Generator by name or alias (exact, then case-insensitive); nullptr if none.
  const PartGenerator* find(std::string_view name) const;
  /// Builds a part; unknown names, unknown parameters and out-of-range values get a
  /// diagnostic (with a "did you mean" suggestion) and nullptr.
  std::shared_ptr<Part> make(std::string_view name,
                             const ParamValues& params,
                             Diagnostics& diags,
                             const SourceLocation& where = {}) const;
  const std::vector<PartGenerator>& generators() const { return generators_; }
  /// Closest known name to `name` (for suggestions); empty if nothing is close.
  std::string suggest(std::string_view name) const;

  /// Adds the parts described in a YAML part file (see docs/parts.md). Malformed files get
  /// file:line diagnostics and add nothing. Relative mesh paths resolve against the file.
  bool load_yaml(const std::filesystem::path& path, Diagnostics& diags);
  /// Same from text; `display_name` names it in diagnostics, mesh paths resolve against
  /// `base_dir`. Parts without a category get `default_category`. With
  /// PartLoading::kOnFirstUse only the parts' identities are checked here; a mistake in a
  /// part's contents then throws std::logic_error when the part is first made.
  bool load_yaml_text(std::string_view text,
                      std::string_view display_name,
                      const std::filesystem::path& base_dir,
                      Diagnostics& diags,
                      PartCategory default_category = PartCategory::kOther,
                      PartLoading loading = PartLoading::kEager);

 private:
  std::vector<PartGenerator> generators_;
};

/// Registers the built-in parts (hacks/src/builtin_parts.cpp).
void register_builtin_parts(PartsLibrary& library);

}  // namespace fabkit::hacks
