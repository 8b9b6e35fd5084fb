#pragma once
// The seam between the server and a kit: each kit contributes a table of routes, registered
// under /api/<kit>/... (the hacks kit also at its original /api/... paths). Handlers validate
// their input and answer JSON; none may take a file name from a request.

// The library (Eigen) before httplib: httplib pulls in <resolv.h>, whose `_res` macro breaks
// Eigen's headers when they come after it. Kept out of include sorting for that reason.
// clang-format off
#include "fabkit/core/json.h"
#include "fabkit/server/editor_server.h"
#include "job_queue.h"

#include <httplib.h>
// clang-format on

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace fabkit::server {

/// What every kit's handlers may use: the server's options, its deadlines and its job queue.
struct ApiContext {
  const ServerOptions* options = nullptr;
  JobQueue* jobs = nullptr;
  /// When work started now must be finished (options.solve_timeout_s).
  std::chrono::steady_clock::time_point deadline() const {
    return std::chrono::steady_clock::now() +
           std::chrono::milliseconds(static_cast<long long>(options->solve_timeout_s * 1000));
  }
};

struct ApiRoute {
  enum class Method { kGet, kPost };
  Method method = Method::kGet;
  /// Path after "/api/<kit>/": plain ("parts") or a regular expression
  /// ("parts/([A-Za-z0-9_]{1,64})/mesh").
  std::string path;
  std::function<void(const httplib::Request&, httplib::Response&)> handler;
};

struct KitApi {
  std::string kit;            ///< "hacks"
  bool also_at_root = false;  ///< registered at /api/<path> too (the hacks kit, for old clients)
  std::vector<ApiRoute> routes;
  /// Problems with what the kit was started with (part files): the server refuses to start.
  Diagnostics startup_errors;
};

/// The hacks kit's routes (server/src/hacks_api.cpp).
KitApi hacks_api(const ApiContext& context);

// ---- answering ------------------------------------------------------------------------------

/// A JSON answer.
void reply(httplib::Response& res, int status, const Json& body);
/// {"error": message, "diagnostics": [...]} with `status`.
void reply_error(httplib::Response& res,
                 int status,
                 const std::string& message,
                 const Json& diagnostics = Json::array());
/// The HTTP status for a failed request, from the class that decides it: 400 for input, 422
/// for infeasible designs, 503 for time limits, 500 otherwise.
int http_status(const Diagnostics& diags);
/// The error messages of `d`, one per line (for the "error" field).
std::string messages_of(const Diagnostics& d);
/// `text` with every absolute path of two or more components cut to its last one
/// ("cannot read '/home/me/parts/x.yaml'" → "cannot read 'x.yaml'"): no answer tells a page
/// where files are on this machine.
std::string without_machine_paths(std::string_view text);
/// A JSON job answer (paths removed), and one for errors ({"error": message, "diagnostics":
/// [...]}).
JobAnswer json_answer(int status, const Json& body);
JobAnswer error_answer(int status,
                       const std::string& message,
                       const Json& diagnostics = Json::array());

/// Runs `work` on the job queue (heavy work: checks, solves) and answers with its result; 503
/// when the queue is full. The request's thread only waits, and stops waiting (the job is then
/// not started) when its client leaves.
void answer_from_job(const ApiContext& context, httplib::Response& res, JobQueue::Work work);

}  // namespace fabkit::server
