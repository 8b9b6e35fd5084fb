#pragma once
// The seam between the server and a kit: each kit contributes a table of routes, registered
// under /api/<kit>/... (the hacks kit also at its original /api/... paths). Handlers validate
// their input and answer JSON; none may take a file name from a request.

// The library (Eigen) before httplib: httplib pulls in <resolv.h>, whose `_res` macro breaks
// Eigen's headers when they come after it. Kept out of include sorting for that reason.
// clang-format off
#include "fabkit/core/json.h"
#include "fabkit/server/editor_server.h"

#include <httplib.h>
// clang-format on

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace fabkit::server {

/// What every kit's handlers may use: the server's options and its deadlines.
struct ApiContext {
  const ServerOptions* options = nullptr;
  /// When a request started now must be finished (options.solve_timeout_s).
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
/// The rods kit's routes (server/src/rods_api.cpp).
KitApi rods_api(const ApiContext& context);
/// The templates kit's routes (server/src/templates_api.cpp).
KitApi templates_api(const ApiContext& context);
/// The flatpack kit's routes (server/src/flatpack_api.cpp).
KitApi flatpack_api(const ApiContext& context);

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

}  // namespace fabkit::server
