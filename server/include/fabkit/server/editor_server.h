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
/// Safe by default (docs/security.md): loopback only unless another host is given; answers only
/// requests addressed to it by its own name (Host) and, for POSTs, with a YAML or JSON body
/// type from its own page or no page (Origin); request bodies, designs, connections and the
/// time each takes are capped; checks and solves run on a bounded queue of their own, so the
/// parts library and meshes stay fast under load; no request can name a file: the only files
/// read after start are the editor's own, under its root; no answer holds a path of the machine.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
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
  std::size_t max_body_bytes = 1 << 20;  ///< larger requests get 413 (chunked ones too)
  int max_parts = 500;                   ///< larger designs get 400
  int max_connections = 2000;            ///< designs with more connections get 400
  double solve_timeout_s = 20;           ///< a check or solve that runs longer stops with 503
  /// Names besides the bound address the server answers to (Host header), e.g. "myhost.lan".
  std::vector<std::string> allowed_hosts;
  int max_open_connections = 96;  ///< connections served at once; more get 503 at once
  double read_timeout_s = 10;     ///< a request must arrive whole within this (slow clients)
  double write_timeout_s = 30;    ///< a client must take its answer within this
  double keep_alive_s = 5;        ///< idle keep-alive connections close after this
  int job_workers = 0;            ///< checks and solves run at once (0: one less than cores, ≥ 1)
  int max_queued_jobs = 64;       ///< checks and solves queued or running; more get 503
  double queue_timeout_s = 120;   ///< a check or solve that waited longer gets 503 unstarted
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
  /// Answers one raw HTTP request as if it came over a connection from 127.0.0.1, without
  /// sockets (for tests and fuzzing); returns the raw response bytes. The Host it must carry is
  /// the configured host and port (or the bound port after bind()).
  std::string answer_raw(std::string_view request);
  /// Problems with what the server was started with (part files); bind() refuses to start.
  const Diagnostics& startup_diagnostics() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string error_;
};

}  // namespace fabkit::server
