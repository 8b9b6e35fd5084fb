// The web editor's server: cpp-httplib, JSON by nlohmann. The server owns what is common to
// every kit (limits, error handling, static files, the design it was started with); each kit
// adds its table of routes (kit_api.h). Nothing a client sends is ever used as a file name.
#include <fmt/format.h>

#include "kit_api.h"

namespace fabkit::server {

void reply(httplib::Response& res, int status, const Json& body) {
  res.status = status;
  // Input echoed in messages may not be UTF-8: replace bad bytes rather than fail.
  // With the charset, httplib does not compress the answer: browsers ask for brotli, which
  // httplib runs at its slowest quality (40–100 ms for a flat-pack model of 25 kB, more than the
  // model takes to compute); over loopback compression saves nothing.
  res.set_content(dump_json(body), "application/json; charset=utf-8");
}

void reply_error(httplib::Response& res,
                 int status,
                 const std::string& message,
                 const Json& diagnostics) {
  reply(res, status, Json{{"error", message}, {"diagnostics", diagnostics}});
}

int http_status(const Diagnostics& diags) {
  switch (diags.deciding_class().value_or(DiagnosticClass::kInternal)) {
    case DiagnosticClass::kInput:
      return 400;
    case DiagnosticClass::kInfeasible:
    case DiagnosticClass::kFallsApart:
    case DiagnosticClass::kCheck:
      return 422;
    case DiagnosticClass::kTimeout:
      return 503;
    case DiagnosticClass::kIo:
    case DiagnosticClass::kInternal:
      return 500;
  }
  return 500;
}

std::string messages_of(const Diagnostics& d) {
  std::string out;
  for (const Diagnostic& x : d) {
    if (x.severity == Severity::kError) out += (out.empty() ? "" : "\n") + x.message;
  }
  return out;
}

struct EditorServer::Impl {
  ServerOptions options;
  httplib::Server http;
  int port = -1;
  Diagnostics startup_errors;

  void add(const std::string& prefix, const ApiRoute& route) {
    const std::string pattern = prefix + route.path;
    if (route.method == ApiRoute::Method::kGet) {
      http.Get(pattern, route.handler);
    } else {
      http.Post(pattern, route.handler);
    }
  }

  void routes() {
    http.set_payload_max_length(options.max_body_bytes);
    // Small JSON answers: no Nagle delay (it added ~40 ms to every round trip).
    http.set_tcp_nodelay(true);

    const ApiContext context{&options};
    std::vector<KitApi> kits;
    kits.push_back(hacks_api(context));
    kits.push_back(rods_api(context));
    kits.push_back(templates_api(context));
    kits.push_back(flatpack_api(context));
    Json kit_names = Json::array();
    for (const KitApi& kit : kits) {
      startup_errors.append(kit.startup_errors);
      kit_names.push_back(kit.kit);
      for (const ApiRoute& route : kit.routes) {
        add("/api/" + kit.kit + "/", route);
        if (kit.also_at_root) add("/api/", route);
      }
    }

    http.Get("/api/kits", [kit_names](const httplib::Request&, httplib::Response& res) {
      reply(res, 200, Json{{"kits", kit_names}});
    });

    http.Get("/api/design", [this](const httplib::Request&, httplib::Response& res) {
      if (options.initial_design.empty()) {
        reply_error(res, 404, "the server was started without a design");
        return;
      }
      res.set_content(options.initial_design, "application/x-yaml");
    });

    // Errors thrown by a handler become a 500 with a message, never a dead server.
    http.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
          std::string what = "internal error";
          try {
            std::rethrow_exception(ep);
          } catch (const std::exception& e) {
            what = e.what();
          } catch (...) {
          }
          reply_error(res, 500, what);
        });
    http.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return;  // a handler already explained itself
      const std::string msg = res.status == 413
                                  ? "the request is larger than the server accepts"
                                  : fmt::format("{} {}: not found", req.method, req.path);
      reply_error(res, res.status, msg);
    });

    if (!options.web_root.empty() && std::filesystem::is_directory(options.web_root)) {
      // httplib refuses paths with ".." (and decodes %2e first), so only files under the
      // root are ever served.
      http.set_mount_point("/", options.web_root.string());
    }
  }
};

EditorServer::EditorServer(ServerOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  impl_->routes();
}

EditorServer::~EditorServer() {
  stop();
}

bool EditorServer::bind() {
  if (impl_->startup_errors.has_errors()) {
    error_ = impl_->startup_errors.format();
    if (!error_.empty() && error_.back() == '\n') error_.pop_back();
    return false;
  }
  if (impl_->options.port == 0) {
    impl_->port = impl_->http.bind_to_any_port(impl_->options.host);
  } else if (impl_->http.bind_to_port(impl_->options.host, impl_->options.port)) {
    impl_->port = impl_->options.port;
  } else {
    impl_->port = -1;
  }
  if (impl_->port < 0) {
    error_ = fmt::format("cannot listen on {}:{} (in use, or not an address of this machine)",
                         impl_->options.host,
                         impl_->options.port);
    return false;
  }
  return true;
}

const Diagnostics& EditorServer::startup_diagnostics() const {
  return impl_->startup_errors;
}

int EditorServer::port() const {
  return impl_->port;
}

void EditorServer::listen() {
  impl_->http.listen_after_bind();
}

void EditorServer::stop() {
  if (impl_ && impl_->http.is_running()) impl_->http.stop();
}

}  // namespace fabkit::server
