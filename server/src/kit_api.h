#pragma once
// The seam between the server and a kit: each kit contributes a table of routes, registered
// under /api/<kit>/... (the hacks kit also at its original /api/... paths). Handlers validate
// their input and answer JSON; none may take a file name from a request.
//
// What the server does for every route of every kit, without the kit doing anything
// (editor_server.cpp, docs/security.md): it answers only requests addressed to it (Host) and
// POSTs with a YAML or JSON body from its own page or none (Origin); it caps bodies (chunked
// ones too), the time a request may take to arrive and the connections served at once; it runs
// heavy routes (every POST unless the route says kLight) on its bounded job queue; it turns a
// handler's exception into a 500 without its text, and cuts every absolute path of the machine
// out of JSON answers.

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
  using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;
  Handler handler;
  /// Where the handler runs. kHeavy: on the server's job queue (at most
  /// ServerOptions::job_workers at once, at a lower CPU priority, 503 "busy" beyond
  /// max_queued_jobs), never on a thread that reads requests, so light requests stay fast under
  /// any load; the handler's answer keeps its status, body and Content-Type (other headers are
  /// dropped). kLight: on the request's thread — it must answer in milliseconds. kAuto (the
  /// default): POST routes are heavy, GET routes light.
  enum class Load { kAuto, kLight, kHeavy };
  Load load = Load::kAuto;
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

/// For tests of the seam: a kit every EditorServer constructed afterwards registers after its
/// own kits (server/tests/kit_seam_test.cpp checks that the server's protections hold for a kit
/// that does nothing for them). Not for production kits: add those in editor_server.cpp.
void add_kit_for_tests(std::function<KitApi(const ApiContext&)> make);
/// Forgets the kits added by add_kit_for_tests.
void clear_kits_for_tests();

// ---- answering ------------------------------------------------------------------------------

/// A JSON answer.
void reply(httplib::Response& res, int status, const Json& body);
/// `answer` as the response (status, body, media type).
void reply(httplib::Response& res, const JobAnswer& answer);
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
/// not started) when its client leaves. (Heavy routes are already run on the queue, see
/// ApiRoute::load; called from a job, `work` runs at once.)
void answer_from_job(const ApiContext& context, httplib::Response& res, JobQueue::Work work);

}  // namespace fabkit::server
