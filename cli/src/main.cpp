// fabkit command line: parse, then hand over to run_<command>().
#include <CLI/CLI.hpp>
#include <cstdio>

#include "commands.h"

int main(int argc, char** argv) {
  using namespace fabkit::cli;
  CLI::App app{"fabkit: design physical things from parts and get a plan you can build"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "fabkit 0.1.0");

  CheckSettings check;
  CLI::App* check_cmd = app.add_subcommand(
      "check", "Verify every connect of a FabHaL design file and report each outcome");
  check_cmd->add_option("design", check.design, "design file (YAML)")->required();
  check_cmd->add_option("--parts", check.part_files, "extra part library file(s) (YAML)");
  check_cmd->add_flag("-q,--quiet", check.quiet, "print diagnostics only");
  check_cmd->add_option("--restarts", check.restarts, "starts of the cycle-closure search (T)")
      ->check(CLI::Range(1, 1000));
  check_cmd->add_option("--seed", check.seed, "seed of the random starts");

  SolveSettings solve;
  CLI::App* solve_cmd = app.add_subcommand(
      "solve", "Solve a design: reach the target, relax under gravity, say if it falls apart");
  solve_cmd->add_option("design", solve.design, "design file (YAML)")->required();
  solve_cmd->add_option("-o,--output",
                        solve.output_dir,
                        "directory for result.json, scene.glb, assembly.stl, assembly.obj");
  solve_cmd->add_option("--parts", solve.part_files, "extra part library file(s) (YAML)");
  solve_cmd->add_flag("-q,--quiet", solve.quiet, "print the verdict and diagnostics only");

  DemoSettings demo;
  CLI::App* demo_cmd = app.add_subcommand(
      "demo", "Solve the bundled bird feeder hack (paper Fig. 1, left) and write its outputs");
  demo_cmd->add_option("-o,--output", demo.output_dir, "output directory")->capture_default_str();

  std::string script;
  std::vector<std::string> script_args;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "Run a FabHaL program written in Python (from fabkit.hacks import *)");
  run_cmd->add_option("program", script, "Python file")->required();
  run_cmd->add_option("args", script_args, "arguments passed to the program");
  run_cmd->prefix_command();
  std::string family;
  CLI::App* sweep_cmd = app.add_subcommand(
      "sweep", "Solve a family of designs in parallel (a file defining build(**params) and grid)");
  sweep_cmd->add_option("family", family, "Python file")->required();

  ServeSettings serve;
  CLI::App* serve_cmd =
      app.add_subcommand("serve", "Start the local server of the web editor (JSON API under /api)");
  serve_cmd->add_option("design", serve.design, "design to open (YAML)");
  serve_cmd->add_option("--port", serve.port, "port (0: any free one)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  serve_cmd
      ->add_option("--host",
                   serve.host,
                   "address to listen on; other than loopback, other machines can connect")
      ->capture_default_str();

  PartsSettings parts;
  CLI::App* parts_cmd = app.add_subcommand("parts", "List the parts library, or show one part");
  parts_cmd->add_option("name", parts.name, "part name");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  if (*check_cmd) return run_check(check);
  if (*solve_cmd) return run_solve(solve);
  if (*demo_cmd) return run_demo(demo);
  if (*parts_cmd) return run_parts(parts);
  if (*run_cmd) {
    for (const std::string& extra : run_cmd->remaining()) script_args.push_back(extra);
    return run_python("run", script, script_args);
  }
  if (*sweep_cmd) return run_python("sweep", family, {});
  if (*serve_cmd) return run_serve(serve);
  return kExitUsage;
}
