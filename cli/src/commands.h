#pragma once
// fabkit's command-line front end: main() parses into settings and calls run_<command>. The
// kit-neutral verbs (check, build) read a design file's `fabkit:` header and hand over to that
// kit's commands (kits.h).

#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"

namespace fabkit::cli {

/// Exit codes, one per failure class (documented in README.md).
enum ExitCode : int {
  kExitOk = 0,           ///< valid design / stable / built
  kExitUsage = 1,        ///< bad command line
  kExitBadInput = 2,     ///< unreadable or malformed input
  kExitInfeasible = 3,   ///< the design cannot be made as asked (a connect was rejected, ...)
  kExitFallsApart = 4,   ///< made, but it does not hold (slips off, tips over)
  kExitWriteFailed = 5,  ///< an output file or directory could not be written
  kExitTimeLimit = 6,    ///< stopped at the time limit
  kExitCheckFailed = 7,  ///< built, but a fabrication check failed (collision, fit, balance)
  kExitInternal = 8,     ///< a bug in fabkit (please report it)
};

/// The exit code for the class that decides `diags` (kExitOk when there are no errors).
int exit_code(const Diagnostics& diags);
/// The exit code for one class.
int exit_code(DiagnosticClass c);

/// What every kit's check and build take from the command line.
struct DesignSettings {
  std::string design;                   ///< path of the design file
  std::string output_dir;               ///< build: where the outputs go
  std::vector<std::string> part_files;  ///< hacks: extra part libraries (YAML)
  bool quiet = false;                   ///< only diagnostics and the verdict
  std::optional<double> time_limit_s;   ///< stop after this long (exit 6)
  int restarts = 16;                    ///< hacks: starts of the cycle-closure search
  unsigned seed = 1;                    ///< seeds every random start
};

/// `fabkit check DESIGN`: the kit named by the file's header checks it.
int run_check(const DesignSettings& settings);
/// `fabkit build DESIGN -o OUT`: the kit named by the header builds every output.
int run_build(const DesignSettings& settings);

/// `fabkit solve DESIGN [-o OUT]`: a hacks design solved under gravity (with outputs).
int run_solve(const DesignSettings& settings);

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
  std::string design;                      ///< optional design to open
  std::vector<std::string> part_files;     ///< hacks part files to offer
  std::vector<std::string> allowed_hosts;  ///< more names the server answers to (Host header)
};
int run_serve(const ServeSettings& settings);

struct PartsSettings {
  std::string name;                     ///< one part in detail, or all when empty
  std::vector<std::string> part_files;  ///< extra part libraries (YAML)
};
int run_parts(const PartsSettings& settings);

struct TemplatesSettings {
  std::string action;  ///< "list" or "show"
  std::string name;    ///< show: a template ("design" or "design/path")
};
/// `fabkit templates list | show NAME`: browse the bundled template database.
int run_templates(const TemplatesSettings& settings);

/// Prints one diagnostic to stderr ("file:line:col: error: ...").
void print_diagnostic(const Diagnostic& d);
void print_diagnostics(const Diagnostics& ds);

}  // namespace fabkit::cli
