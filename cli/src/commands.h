#pragma once
// fabkit's command-line front end: main() parses into settings and calls run_<command>.

#include <string>
#include <vector>

namespace fabkit::cli {

/// Exit codes, one per failure class (documented in README.md).
enum ExitCode : int {
  kExitOk = 0,          ///< valid design / stable
  kExitUsage = 1,       ///< bad command line
  kExitBadInput = 2,    ///< unreadable or malformed input
  kExitInfeasible = 3,  ///< the design cannot be built (a connect was rejected)
  kExitFallsApart = 4,  ///< solved, but a connection slips off under gravity
};

struct CheckSettings {
  std::string design;                   ///< path, or the embedded demo when empty
  std::vector<std::string> part_files;  ///< extra part libraries (YAML)
  bool quiet = false;                   ///< only diagnostics, no per-step lines
  int restarts = 16;
  unsigned seed = 1;
};

int run_check(const CheckSettings& settings);

struct SolveSettings {
  std::string design;      ///< path, or the embedded demo when empty
  std::string output_dir;  ///< where result.json, scene.glb, STL and OBJ go
  std::vector<std::string> part_files;
  bool quiet = false;
  bool write = true;  ///< write the output files
};
int run_solve(const SolveSettings& settings);

struct DemoSettings {
  std::string output_dir = "fabkit-demo";
};
int run_demo(const DemoSettings& settings);

/// `fabkit run PROGRAM.py [args]` and `fabkit sweep FAMILY.py`: run Python with the fabkit
/// module importable. Replaces this process; returns only on failure.
int run_python(const std::string& mode,
               const std::string& script,
               const std::vector<std::string>& args);

struct ServeSettings {
  std::string host = "127.0.0.1";  ///< loopback unless given explicitly
  int port = 8080;
  std::string design;  ///< optional design to open
};
int run_serve(const ServeSettings& settings);

struct PartsSettings {
  std::string name;  ///< one part in detail, or all when empty
};
int run_parts(const PartsSettings& settings);

}  // namespace fabkit::cli
