// fabkit command line: parse, then hand over to run_<command>().
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "commands.h"
#include "fabkit/core/text.h"
#include "kits.h"

namespace {

using fabkit::cli::DesignSettings;

// Options shared by check, solve and build.
void add_design_options(CLI::App* cmd, DesignSettings& s) {
  cmd->add_option("design", s.design, "design file (YAML; its 'fabkit:' header names the kit)")
      ->required();
  cmd->add_option("--parts", s.part_files, "hacks: extra part library file(s) (YAML)");
  cmd->add_flag("-q,--quiet", s.quiet, "print diagnostics and the verdict only");
  cmd->add_option("--time-limit", s.time_limit_s, "stop after this many seconds (exit 6)")
      ->check(CLI::Range(0.001, 1e6));
  cmd->add_option("--seed", s.seed, "seed of every random start (same seed, same answer)");
}

std::string kit_list() {
  std::string out;
  for (const auto& k : fabkit::cli::kits()) {
    out += "\n  " + std::string(k.kit) + "/1  " + std::string(k.description);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace fabkit::cli;
  CLI::App app{"fabkit: design physical things from parts and get a plan you can build"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "fabkit 0.1.0");
  app.footer("Kits (the 'fabkit:' header of a design file):" + kit_list());

  DesignSettings check;
  CLI::App* check_cmd = app.add_subcommand(
      "check", "Check a design file of any kit and report every finding (exit codes: README)");
  add_design_options(check_cmd, check);
  check_cmd
      ->add_option("--restarts", check.restarts, "hacks: starts of the cycle-closure search (T)")
      ->check(CLI::Range(1, 1000));

  DesignSettings build;
  CLI::App* build_cmd = app.add_subcommand(
      "build", "Build every output of a design file of any kit into a directory");
  add_design_options(build_cmd, build);
  build_cmd->add_option("-o,--output", build.output_dir, "output directory")->required();

  DesignSettings solve;
  CLI::App* solve_cmd = app.add_subcommand(
      "solve",
      "Solve a hacks design: reach the target, relax under gravity, say if it falls apart");
  add_design_options(solve_cmd, solve);
  solve_cmd->add_option("-o,--output",
                        solve.output_dir,
                        "directory for result.json, scene.glb, assembly.stl, assembly.obj");

  DemoSettings demo;
  CLI::App* demo_cmd = app.add_subcommand(
      "demo", "Solve the bundled bird feeder hack (paper Fig. 1, left) and write its outputs");
  demo_cmd->add_option("-o,--output", demo.output_dir, "output directory")->capture_default_str();

  std::string script;
  std::vector<std::string> script_args;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "Run a fabkit program written in Python (from fabkit.hacks import *)");
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
  serve_cmd->add_option("--parts", serve.part_files, "hacks: extra part library file(s) (YAML)");
  serve_cmd->add_option("--port", serve.port, "port (0: any free one)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  serve_cmd
      ->add_option("--host",
                   serve.host,
                   "address to listen on; other than loopback, other machines can connect")
      ->capture_default_str();
  serve_cmd->add_option("--allow-host",
                        serve.allowed_hosts,
                        "another name this server may be reached under (e.g. myhost.lan); by "
                        "default it answers only to its address (and localhost)");

  BurnTestSettings burn;
  CLI::App* flatpack_cmd =
      app.add_subcommand("flatpack", "Flat-pack tools beyond check and build (see subcommands)");
  flatpack_cmd->require_subcommand(1);
  CLI::App* burn_cmd = flatpack_cmd->add_subcommand(
      "burn-test",
      "Write a sheet of test joints over ranges of kerf and interference (burn-test.svg/.dxf)");
  burn_cmd->add_option("-o,--output", burn.output_dir, "output directory")->required();
  burn_cmd->add_option("--thickness", burn.thickness_mm, "board thickness, mm")
      ->capture_default_str();
  burn_cmd->add_option("--material", burn.material, "material name for the labels")
      ->capture_default_str();
  burn_cmd
      ->add_option("--kerf",
                   burn.kerfs,
                   "kerf Δ per side, mm: a value, a list 0.1,0.15 or a range start:stop:step")
      ->capture_default_str();
  burn_cmd->add_option("--interference", burn.interferences, "interference δ, mm: likewise")
      ->capture_default_str();
  burn_cmd
      ->add_option(
          "--finger-width", burn.finger_width_mm, "nominal finger width, mm (0: 3 × thickness)")
      ->capture_default_str();

  PartsSettings parts;
  CLI::App* parts_cmd =
      app.add_subcommand("parts", "List the hacks parts library, or show one part");
  parts_cmd->add_option("name", parts.name, "part name");
  parts_cmd->add_option("--parts", parts.part_files, "extra part library file(s) (YAML)");

  TemplatesSettings templates_settings;
  CLI::App* templates_cmd =
      app.add_subcommand("templates", "Browse the template database: list, or show DESIGN[/PATH]");
  templates_cmd->require_subcommand(1);
  CLI::App* templates_list = templates_cmd->add_subcommand("list", "List the source designs");
  CLI::App* templates_show =
      templates_cmd->add_subcommand("show", "Show one template: tree, items, controls, joints");
  templates_show->add_option("name", templates_settings.name, "design or design/path/to/node")
      ->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  // The library answers bad input with diagnostics; an exception reaching here is a bug (or
  // the machine ran out of memory): say so in one line with the exit code for it, never abort.
  try {
    if (*check_cmd) return run_check(check);
    if (*build_cmd) return run_build(build);
    if (*solve_cmd) return run_solve(solve);
    if (*demo_cmd) return run_demo(demo);
    if (*parts_cmd) return run_parts(parts);
#ifdef FABKIT_CLI_HACKS_ONLY
    // fabkit-hacks holds the hacks kit alone; the fabkit launcher sends nothing else here.
    std::fprintf(stderr, "error: %s runs hacks commands only; run fabkit\n", argv[0]);
    return kExitUsage;
#else
    if (*burn_cmd) return flatpack_burn_test(burn);
    if (*templates_cmd) {
      templates_settings.action = *templates_list ? "list" : "show";
      return run_templates(templates_settings);
    }
    if (*run_cmd) {
      for (const std::string& extra : run_cmd->remaining()) script_args.push_back(extra);
      return run_python("run", script, script_args);
    }
    if (*sweep_cmd) return run_python("sweep", family, {});
    if (*serve_cmd) return run_serve(serve);
#endif
  } catch (const std::bad_alloc&) {
    std::fflush(stdout);
    std::fprintf(stderr, "error: out of memory\n");
    return kExitInternal;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr,
                 "error: internal error: %s (please report this with the input)\n",
                 fabkit::excerpt(e.what(), 300).c_str());
    return kExitInternal;
  }
  return kExitUsage;
}
