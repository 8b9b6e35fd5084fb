#pragma once
/// The local HTTP server behind the web editor: static files plus a JSON API over the library.
///
///   GET  /api/kits                  the kits this server answers for
///   GET  /api/parts                 the parts library: names, descriptions, primitives
///   GET  /api/parts/{name}/mesh     display geometry of a part (query: its parameters)
///   GET  /api/design                the design the server was started with (YAML), or 404
///   POST /api/check                 body: a design (YAML) → every step's outcome, diagnostics
///   POST /api/solve                 body: a design (YAML) → result.json (?format=glb: scene.glb)
///   POST /api/compatible            body: {"a": primitive, "b": [primitive...]} → can each connect
///                                   to a (Table 1, closedness, sizes) and why not
///
///   GET  /api/flatpack/components   the flat-pack component registry (schemas, edges)
///   POST /api/flatpack/assemble     body: a flat-pack design (YAML) → pieces with joints cut,
///                                   joints, residuals, nested sheets, diagnostics per piece
///   POST /api/flatpack/build?file=F body: a design → one build output (sheet-N.svg, .dxf,
///                                   model.stl, scene.glb, report.json)
///
/// Each kit's routes live under /api/<kit>/ (/api/hacks/check, ...); the hacks kit's also at the
/// paths above.
///
/// Safe by default: loopback only unless another host is given, request bodies and designs are
/// capped, every input is validated (HTTP 400 with the diagnostic), solves stop at a deadline,
/// and no request can name a file: the only files served are the editor's own, under its root.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"

namespace fabkit::server {

struct ServerOptions {
  std::string host = "127.0.0.1";  ///< loopback unless the user asks otherwise
  int port = 8080;                 ///< 0: any free port
  std::filesystem::path web_root;  ///< the built editor (web/dist); empty: API only
  std::string initial_design;      ///< YAML text served at /api/design (may be empty)
  /// Extra hacks part files, loaded at start (a posted design may not name files).
  std::vector<std::filesystem::path> hacks_part_files;
  std::string initial_design_name;       ///< its file name, for diagnostics
  std::size_t max_body_bytes = 1 << 20;  ///< larger requests get 413
  int max_parts = 500;                   ///< larger designs get 400
  int max_connections = 2000;            ///< designs with more connections get 400
  double solve_timeout_s = 20;           ///< a solve that runs longer stops with 503
};

class EditorServer {
 public:
  explicit EditorServer(ServerOptions options);
  ~EditorServer();
  EditorServer(const EditorServer&) = delete;
  EditorServer& operator=(const EditorServer&) = delete;

  /// Binds the socket; returns false (with `error()`) if the address is taken or invalid.
  bool bind();
  /// The bound port (after bind()).
  int port() const;
  /// Serves until stop() is called (blocking).
  void listen();
  void stop();
  const std::string& error() const { return error_; }
  /// Problems with what the server was started with (part files); bind() refuses to start.
  const Diagnostics& startup_diagnostics() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string error_;
};

}  // namespace fabkit::server
