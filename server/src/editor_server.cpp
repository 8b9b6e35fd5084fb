// The web editor's server: cpp-httplib, JSON by nlohmann. The server owns what is common to
// every kit (who may ask, limits, the job queue, error handling, static files, the design it
// was started with); each kit adds its table of routes (kit_api.h). Nothing a client sends is
// ever used as a file name (docs/security.md).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <mutex>
#include <regex>
#include <thread>

#include "fabkit/core/file_io.h"
#include "fabkit/core/text.h"
#include "guarded_http_server.h"
#include "kit_api.h"
#include "request_policy.h"

namespace fabkit::server {

namespace {

std::mutex g_test_kits_mutex;
std::vector<std::function<KitApi(const ApiContext&)>> g_test_kits;

// The characters after which a '/' starts a path in a message ("cannot read '/home/...").
bool starts_path_after(char c) {
  return c == ' ' || c == '\'' || c == '"' || c == '(' || c == '[' || c == '=' || c == '\n' ||
         c == '\t' || c == '`';
}

bool path_char(char c) {
  return c != ' ' && c != '\'' && c != '"' && c != ')' && c != ']' && c != '\n' && c != '\t' &&
         c != ',' && c != '`' && c != '\\';
}

}  // namespace

std::string without_machine_paths(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == '/' && (i == 0 || starts_path_after(text[i - 1]))) {
      std::size_t end = i;
      while (end < text.size() && path_char(text[end])) ++end;
      const std::string_view token = text.substr(i, end - i);
      const std::size_t last = token.find_last_of('/');
      if (last != 0 && last + 1 < token.size()) {  // at least two components: a path
        out.append(token.substr(last + 1));
        i = end;
        continue;
      }
    }
    out.push_back(text[i++]);
  }
  return out;
}

void reply(httplib::Response& res, int status, const Json& body) {
  res.status = status;
  // Input echoed in messages may not be UTF-8: replace bad bytes rather than fail.
  // (Machine paths are cut as every route's handler returns: EditorServer::Impl::add.)
  res.set_content(dump_json(body), "application/json; charset=utf-8");
}

void reply(httplib::Response& res, const JobAnswer& answer) {
  res.status = answer.status;
  res.set_content(answer.body, answer.content_type);
}

void reply_error(httplib::Response& res,
                 int status,
                 const std::string& message,
                 const Json& diagnostics) {
  reply(res, error_answer(status, message, diagnostics));
}

JobAnswer json_answer(int status, const Json& body) {
  return {status, without_machine_paths(dump_json(body)), "application/json; charset=utf-8"};
}

JobAnswer error_answer(int status, const std::string& message, const Json& diagnostics) {
  return json_answer(status, Json{{"error", message}, {"diagnostics", diagnostics}});
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

void add_kit_for_tests(std::function<KitApi(const ApiContext&)> make) {
  std::lock_guard lock(g_test_kits_mutex);
  g_test_kits.push_back(std::move(make));
}

void clear_kits_for_tests() {
  std::lock_guard lock(g_test_kits_mutex);
  g_test_kits.clear();
}

void answer_from_job(const ApiContext& context, httplib::Response& res, JobQueue::Work work) {
  if (JobQueue::on_worker_thread()) {  // a heavy route's handler: it is on the queue already
    reply(res, work());
    return;
  }
  auto ticket = context.jobs->submit(std::move(work));
  if (!ticket) {
    reply_error(res,
                503,
                context.jobs->stopping()
                    ? "the server is stopping"
                    : fmt::format("the server is busy: {} checks and solves are waiting or "
                                  "running, its limit; try again",
                                  context.jobs->options().max_pending));
    res.set_header("Retry-After", "2");
    return;
  }
  using namespace std::chrono_literals;
  while (ticket->answer.wait_for(50ms) != std::future_status::ready) {
    if (GuardedHttpServer::client_gone() || GuardedHttpServer::server_stopping()) {
      *ticket->cancelled = true;  // nobody to answer: do not start it
      GuardedHttpServer::close_after_response();
      res.status = 499;
      return;
    }
  }
  const JobAnswer& a = ticket->answer.get();
  res.status = a.status;
  res.set_content(a.body, a.content_type);
  if (a.status == 503) res.set_header("Retry-After", "2");
}

namespace {

const char* media_type_of(const std::filesystem::path& file) {
  static constexpr std::array<std::pair<const char*, const char*>, 14> kTypes = {{
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".jpg", "image/jpeg"},
      {".ico", "image/x-icon"},
      {".wasm", "application/wasm"},
      {".glb", "model/gltf-binary"},
      {".woff2", "font/woff2"},
      {".txt", "text/plain; charset=utf-8"},
      {".map", "application/json"},
  }};
  const std::string ext = file.extension().string();
  for (const auto& [e, type] : kTypes) {
    if (ext == e) return type;
  }
  return "application/octet-stream";
}

}  // namespace

struct EditorServer::Impl {
  ServerOptions options;
  std::unique_ptr<GuardedHttpServer> http;
  std::unique_ptr<JobQueue> jobs;
  HostPolicy host_policy;
  int port = -1;
  Diagnostics startup_errors;
  std::filesystem::path web_root;  // canonical; empty: API only

  ~Impl() {
    // Stop answering first (request threads end), then the jobs.
    if (http && http->is_running()) http->stop();
    if (jobs) jobs->stop();
  }

  // A route's handler as the server runs it: a heavy one on the job queue (with its own copy
  // of the request, which outlives a client that leaves), a light one as it is.
  ApiRoute::Handler placed(const std::string& pattern, const ApiRoute& route) {
    const bool heavy =
        route.load == ApiRoute::Load::kHeavy ||
        (route.load == ApiRoute::Load::kAuto && route.method == ApiRoute::Method::kPost);
    if (!heavy) return route.handler;
    const ApiContext context{&options, jobs.get()};
    auto regex = std::make_shared<const std::regex>(pattern);
    auto handler = route.handler;
    return [context, regex, handler](const httplib::Request& req, httplib::Response& res) {
      auto request = std::make_shared<httplib::Request>(req);
      answer_from_job(context, res, [request, regex, handler]() -> JobAnswer {
        // The copy's matches would point into the original request's path.
        std::regex_match(request->path, request->matches, *regex);
        httplib::Response out;
        try {
          handler(*request, out);
        } catch (...) {
          return error_answer(500,
                              fmt::format("internal error while answering {} {}",
                                          request->method,
                                          excerpt(request->path, 120)));
        }
        return {
            out.status == -1 ? 200 : out.status, out.body, out.get_header_value("Content-Type")};
      });
    };
  }

  void add(const std::string& prefix, const ApiRoute& route) {
    const std::string pattern = prefix + route.path;
    // Whatever a kit's handler answered: no absolute path of this machine in a JSON answer.
    // Done here, as the handler returns: httplib fixes the body's length (and used to
    // compress it) before any later hook, and a body rewritten there no longer matched them.
    auto handler = [inner = placed(pattern, route)](const httplib::Request& req,
                                                    httplib::Response& res) {
      inner(req, res);
      if (res.get_header_value("Content-Type").rfind("application/json", 0) == 0) {
        res.body = without_machine_paths(res.body);
      }
    };
    if (route.method == ApiRoute::Method::kGet) {
      http->Get(pattern, handler);
      return;
    }
    // POST bodies are read here, capped whatever their transfer encoding (httplib checks its
    // payload limit against Content-Length only, and read chunked bodies whole).
    const std::size_t cap = options.max_body_bytes;
    http->Post(pattern,
               [cap, handler](const httplib::Request& req,
                              httplib::Response& res,
                              const httplib::ContentReader& read) {
                 httplib::Request with_body = req;
                 bool too_large = false;
                 const bool whole = read([&](const char* data, std::size_t n) {
                   if (with_body.body.size() + n > cap) {
                     too_large = true;
                     return false;
                   }
                   with_body.body.append(data, n);
                   return true;
                 });
                 if (too_large || res.status == 413) {
                   GuardedHttpServer::close_after_response();
                   reply_error(res,
                               413,
                               fmt::format("the request is larger than the server accepts ({} "
                                           "bytes at most)",
                                           cap));
                   return;
                 }
                 if (!whole) {
                   GuardedHttpServer::close_after_response();
                   reply_error(res, 400, "the request body could not be read whole");
                   return;
                 }
                 handler(with_body, res);
               });
  }

  // Who may ask: requests addressed to this server, POSTs with a design's media type from no
  // page or its own page. Runs before the body is read.
  httplib::Server::HandlerResponse admit(const httplib::Request& req, httplib::Response& res) {
    // Nothing is compressed: over loopback it saves nothing, and httplib compresses with brotli
    // at its slowest quality — 1.7 s for the editor's 920 kB script on every page load, 40–100
    // ms for a 25 kB JSON answer. httplib decides from the request's Accept-Encoding, later
    // and with no option to turn it off; the request is httplib's own non-const object, handed
    // to this hook as const.
    const_cast<httplib::Request&>(req).headers.erase("Accept-Encoding");
    auto refuse = [&](int status, const std::string& why) {
      GuardedHttpServer::close_after_response();  // its body, if any, is never read
      reply_error(res, status, why);
      return httplib::Server::HandlerResponse::Handled;
    };
    if (auto why = refuse_host(host_policy, req.get_header_value("Host"))) return refuse(403, *why);
    if (req.method != "POST") return httplib::Server::HandlerResponse::Unhandled;
    if (auto why = refuse_origin(host_policy, req.get_header_value("Origin"))) {
      return refuse(403, *why);
    }
    const std::string type = req.get_header_value("Content-Type");
    if (!is_design_media_type(type)) {
      return refuse(415,
                    fmt::format("a request body must be YAML (Content-Type: application/x-yaml) "
                                "or JSON (application/json), not '{}'",
                                excerpt(type.empty() ? "none" : type, 80)));
    }
    if (req.has_header("Content-Encoding") &&
        req.get_header_value("Content-Encoding") != "identity") {
      return refuse(415, "compressed request bodies are not accepted");
    }
    const std::string transfer = req.get_header_value("Transfer-Encoding");
    if (!transfer.empty()) {
      if (transfer != "chunked") {
        return refuse(400, fmt::format("unsupported Transfer-Encoding '{}'", excerpt(transfer)));
      }
      if (req.has_header("Content-Length")) {
        return refuse(400, "a request may not have both a Content-Length and chunked encoding");
      }
      return httplib::Server::HandlerResponse::Unhandled;  // capped as it is read
    }
    if (!req.has_header("Content-Length")) {
      return refuse(411, "a request body needs a Content-Length (or chunked encoding)");
    }
    const std::string length = req.get_header_value("Content-Length");
    if (length.empty() || length.size() > 18 ||
        length.find_first_not_of("0123456789") != std::string::npos) {
      return refuse(400, fmt::format("Content-Length '{}' is not a number", excerpt(length)));
    }
    if (std::stoull(length) > options.max_body_bytes) {
      return refuse(413,
                    fmt::format("the request is larger than the server accepts ({} bytes at most)",
                                options.max_body_bytes));
    }
    return httplib::Server::HandlerResponse::Unhandled;
  }

  // The editor's own files, under its root only: regular files, no links out of it.
  void serve_file(const httplib::Request& req, httplib::Response& res) {
    std::string rel = req.path.substr(1);
    if (rel.empty() || rel.back() == '/') rel += "index.html";
    const std::filesystem::path wanted(rel);
    bool plain = !web_root.empty() && rel.find('\0') == std::string::npos &&
                 rel.find('\\') == std::string::npos && wanted.is_relative();
    for (const auto& part : wanted) plain = plain && part != ".." && part != ".";
    std::error_code ec;
    const std::filesystem::path file =
        plain ? std::filesystem::canonical(web_root / wanted, ec) : std::filesystem::path();
    const auto [root_end, file_at] =
        std::mismatch(web_root.begin(), web_root.end(), file.begin(), file.end());
    if (!plain || ec || root_end != web_root.end() || file_at == file.end()) {
      reply_error(res, 404, fmt::format("GET {}: not found", excerpt(req.path, 120)));
      return;
    }
    Diagnostics d;
    const auto bytes = read_input_file(file, "file", d);
    if (!bytes) {
      reply_error(res, 404, fmt::format("GET {}: not found", excerpt(req.path, 120)));
      return;
    }
    res.status = 200;
    res.set_content(*bytes, media_type_of(file));
  }

  void routes() {
    ConnectionLimits limits;
    limits.max_open = options.max_open_connections;
    limits.request_read_s = options.read_timeout_s;
    limits.write_s = options.write_timeout_s;
    limits.keep_alive_s = options.keep_alive_s;
    // Room for the request line and headers besides the body.
    limits.max_request_bytes = options.max_body_bytes + (64 << 10);
    http = std::make_unique<GuardedHttpServer>(limits);

    JobQueue::Options jo;
    const int cores = static_cast<int>(std::thread::hardware_concurrency());
    jo.workers = options.job_workers > 0 ? options.job_workers : std::max(1, cores - 1);
    jo.max_pending = static_cast<std::size_t>(std::max(1, options.max_queued_jobs));
    jo.max_wait_s = options.queue_timeout_s;
    jobs = std::make_unique<JobQueue>(jo);

    // Small JSON answers: no Nagle delay (it added ~40 ms to every round trip).
    http->set_tcp_nodelay(true);
    http->set_payload_max_length(options.max_body_bytes);
    http->set_pre_routing_handler(
        [this](const httplib::Request& req, httplib::Response& res) { return admit(req, res); });
    // Clients that ask first (Expect: 100-continue) are told before they send a body.
    http->set_expect_100_continue_handler(
        [this](const httplib::Request& req, httplib::Response& res) {
          if (admit(req, res) == httplib::Server::HandlerResponse::Handled) return res.status;
          return 100;
        });
    // Headers only: by now httplib has set the body's length (add() cleans JSON bodies of
    // machine paths before that).
    http->set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
      res.set_header("X-Content-Type-Options", "nosniff");
      res.set_header("X-Frame-Options", "DENY");
      res.set_header("Referrer-Policy", "no-referrer");
    });

    const ApiContext context{&options, jobs.get()};
    std::vector<KitApi> kits;
    kits.push_back(hacks_api(context));
    kits.push_back(rods_api(context));
    kits.push_back(templates_api(context));
    kits.push_back(flatpack_api(context));
    {
      std::lock_guard lock(g_test_kits_mutex);
      for (const auto& make : g_test_kits) kits.push_back(make(context));
    }
    Json kit_names = Json::array();
    for (const KitApi& kit : kits) {
      startup_errors.append(kit.startup_errors);
      kit_names.push_back(kit.kit);
      for (const ApiRoute& route : kit.routes) {
        add("/api/" + kit.kit + "/", route);
        if (kit.also_at_root) add("/api/", route);
      }
    }

    http->Get("/api/kits", [kit_names](const httplib::Request&, httplib::Response& res) {
      reply(res, 200, Json{{"kits", kit_names}});
    });

    http->Get("/api/design", [this](const httplib::Request&, httplib::Response& res) {
      if (options.initial_design.empty()) {
        reply_error(res, 404, "the server was started without a design");
        return;
      }
      res.set_content(options.initial_design, "application/x-yaml");
    });

    // Errors thrown by a handler become a 500 without their text (it may name files of this
    // machine), never a dead server.
    http->set_exception_handler([](const httplib::Request& req,
                                   httplib::Response& res,
                                   std::exception_ptr) {
      reply_error(
          res,
          500,
          fmt::format("internal error while answering {} {}", req.method, excerpt(req.path, 120)));
    });
    http->set_error_handler([](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return;  // a handler already explained itself
      std::string msg;
      switch (res.status) {
        case 413:
          msg = "the request is larger than the server accepts";
          break;
        case 400:
          msg = "the request is not valid HTTP, or arrived too slowly";
          break;
        case 414:
          msg = "the request's address is too long";
          break;
        default:
          msg = fmt::format("{} {}: not found", excerpt(req.method, 10), excerpt(req.path, 120));
      }
      reply_error(res, res.status, msg);
    });

    std::error_code ec;
    if (!options.web_root.empty() && std::filesystem::is_directory(options.web_root, ec)) {
      web_root = std::filesystem::canonical(options.web_root, ec);
      if (ec) web_root.clear();
    }
    http->Get("/api/.*", [](const httplib::Request& req, httplib::Response& res) {
      reply_error(res, 404, fmt::format("GET {}: not found", excerpt(req.path, 120)));
    });
    http->Get("/.*", [this](const httplib::Request& req, httplib::Response& res) {
      serve_file(req, res);
    });
  }
};

EditorServer::EditorServer(ServerOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  impl_->host_policy = {impl_->options.host, impl_->options.port, impl_->options.allowed_hosts};
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
    impl_->port = impl_->http->bind_to_any_port(impl_->options.host);
  } else if (impl_->http->bind_to_port(impl_->options.host, impl_->options.port)) {
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
  impl_->host_policy.port = impl_->port;
  impl_->http->widen_listen_backlog();
  return true;
}

const Diagnostics& EditorServer::startup_diagnostics() const {
  return impl_->startup_errors;
}

int EditorServer::port() const {
  return impl_->port;
}

void EditorServer::listen() {
  impl_->http->listen_after_bind();
}

void EditorServer::stop() {
  if (impl_ && impl_->http && impl_->http->is_running()) impl_->http->stop();
}

std::string EditorServer::answer_raw(std::string_view request) {
  return impl_->http->answer_raw(request);
}

}  // namespace fabkit::server
