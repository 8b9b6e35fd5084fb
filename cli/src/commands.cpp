#include "commands.h"

#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "fabkit/core/file_io.h"
#include "fabkit/core/yaml_reader.h"
#include "kits.h"

namespace fabkit::cli {

std::span<const KitCommands> kits() {
#ifdef FABKIT_CLI_HACKS_ONLY
  // fabkit-hacks (cli/src/launcher.cpp): the hacks kit alone.
  static constexpr std::array<KitCommands, 1> kAll = {
#else
  static constexpr std::array<KitCommands, 4> kAll = {
#endif
    KitCommands{"hacks",
                "fixture hacks from everyday parts (FabHaL); build solves and exports",
                hacks_check,
                hacks_build},
#ifndef FABKIT_CLI_HACKS_ONLY
    KitCommands{"flatpack",
                "flat-pack furniture from planar pieces; build writes cut sheets and a 3D model",
                flatpack_check,
                flatpack_build},
    KitCommands{"rods",
                "rod-and-joint structures (RodSteward); build writes printable joints, a cut "
                "plan and an assembly order",
                rods_check,
                rods_build},
    KitCommands{"templates",
                "furniture composed from a database of fabricable templates; build writes the "
                "bill of materials, cut diagrams and 3D model",
                templates_check,
                templates_build},
#endif
  };
  return kAll;
}

void print_diagnostic(const Diagnostic& d) {
  std::fprintf(stderr, "%s\n", d.format().c_str());
}

void print_diagnostics(const Diagnostics& ds) {
  for (const Diagnostic& d : ds) print_diagnostic(d);
}

int exit_code(DiagnosticClass c) {
  switch (c) {
    case DiagnosticClass::kInput:
      return kExitBadInput;
    case DiagnosticClass::kInfeasible:
      return kExitInfeasible;
    case DiagnosticClass::kFallsApart:
      return kExitFallsApart;
    case DiagnosticClass::kCheck:
      return kExitCheckFailed;
    case DiagnosticClass::kIo:
      return kExitWriteFailed;
    case DiagnosticClass::kTimeout:
      return kExitTimeLimit;
    case DiagnosticClass::kInternal:
      return kExitInternal;
  }
  return kExitInternal;
}

int exit_code(const Diagnostics& diags) {
  const auto c = diags.deciding_class();
  return c ? exit_code(*c) : kExitOk;
}

namespace {

// Reads the design and finds its kit from the header; prints why not and returns nullptr.
const KitCommands* kit_of(const DesignSettings& settings, std::string& text, int& failure) {
  Diagnostics d;
  const auto bytes = read_input_file(settings.design, "design file", d);
  std::vector<std::string_view> names;
  for (const KitCommands& k : kits()) names.push_back(k.kit);
  std::optional<KitTag> tag;
  if (bytes) tag = read_kit_tag(*bytes, settings.design, names, d);
  if (!tag) {
    print_diagnostics(d);
    failure = exit_code(d);
    return nullptr;
  }
  text = *bytes;
  for (const KitCommands& k : kits()) {
    if (k.kit == tag->kit) return &k;
  }
  failure = kExitInternal;
  return nullptr;
}

}  // namespace

int run_check(const DesignSettings& settings) {
  std::string text;
  int failure = kExitOk;
  const KitCommands* kit = kit_of(settings, text, failure);
  if (!kit) return failure;
  return kit->check(DesignInput{settings, std::move(text)});
}

int run_build(const DesignSettings& settings) {
  std::string text;
  int failure = kExitOk;
  const KitCommands* kit = kit_of(settings, text, failure);
  if (!kit) return failure;
  return kit->build(DesignInput{settings, std::move(text)});
}

int run_python(const std::string& mode,
               const std::string& script,
               const std::vector<std::string>& args) {
#if defined(FABKIT_PYTHON_PATH) && defined(FABKIT_PYTHON_EXECUTABLE)
  std::error_code ec;
  if (!std::filesystem::is_regular_file(script, ec)) {
    std::fprintf(stderr, "error: cannot open '%s'\n", script.c_str());
    return kExitBadInput;
  }
  const std::string module_dir = FABKIT_PYTHON_PATH;
  if (!std::filesystem::exists(std::filesystem::path(module_dir) / "fabkit", ec)) {
    std::fprintf(
        stderr,
        "error: the fabkit Python module is not built (expected in %s); run ./scripts/setup\n",
        module_dir.c_str());
    return kExitUsage;
  }
  const char* old = std::getenv("PYTHONPATH");
  const std::string path = old && *old ? module_dir + ":" + old : module_dir;
  setenv("PYTHONPATH", path.c_str(), 1);
  std::vector<std::string> argv_strings = {FABKIT_PYTHON_EXECUTABLE, "-m", "fabkit", mode, script};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_strings) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(FABKIT_PYTHON_EXECUTABLE, argv.data());
  std::fprintf(
      stderr, "error: cannot start %s: %s\n", FABKIT_PYTHON_EXECUTABLE, std::strerror(errno));
  return kExitUsage;
#else
  (void)mode;
  (void)script;
  (void)args;
  std::fprintf(stderr, "error: this fabkit was built without Python (FABKIT_BUILD_PYTHON=OFF)\n");
  return kExitUsage;
#endif
}

}  // namespace fabkit::cli
