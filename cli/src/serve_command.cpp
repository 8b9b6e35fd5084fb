// `fabkit serve`: the local server of the web editor (fabkit-all only: it serves every kit).
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "fabkit/core/file_io.h"
#include "fabkit/server/editor_server.h"

namespace fabkit::cli {

int run_serve(const ServeSettings& settings) {
  server::ServerOptions o;
  o.host = settings.host;
  o.port = settings.port;
  if (std::filesystem::is_directory(FABKIT_WEB_DIR)) o.web_root = FABKIT_WEB_DIR;
  for (const std::string& f : settings.part_files) o.hacks_part_files.emplace_back(f);
  o.allowed_hosts = settings.allowed_hosts;
  if (!settings.design.empty()) {
    Diagnostics d;
    const auto text = read_input_file(settings.design, "design file", d);
    if (!text) {
      print_diagnostics(d);
      return exit_code(d);
    }
    o.initial_design = *text;
    o.initial_design_name = settings.design;
  }
  server::EditorServer server(o);
  if (server.startup_diagnostics().has_errors()) {
    print_diagnostics(server.startup_diagnostics());
    return exit_code(server.startup_diagnostics());
  }
  if (!server.bind()) {
    std::fprintf(stderr, "error: %s\n", server.error().c_str());
    return kExitUsage;
  }
  std::printf("fabkit serve: http://%s:%d/  (API under /api; Ctrl-C to stop)\n",
              settings.host.c_str(),
              server.port());
  if (o.web_root.empty()) {
    std::printf("note: the web editor is not built (%s is missing); only the API is served\n",
                FABKIT_WEB_DIR);
  }
  if (settings.host != "127.0.0.1" && settings.host != "localhost") {
    std::printf("warning: listening on %s: other machines can reach this server\n",
                settings.host.c_str());
  }
  std::fflush(stdout);
  server.listen();
  return kExitOk;
}

}  // namespace fabkit::cli
