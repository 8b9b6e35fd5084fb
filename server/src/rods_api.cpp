// The rods kit's API (RodSteward in the browser, issue 15):
//
//   POST preview       body: a design (YAML or JSON) → the preview geometry (hulls and prisms,
//                      no booleans), rod lengths, every check, balance, frame analysis and the
//                      assembly order: what the designer redraws on every edit
//   POST import-obj    body: an OBJ wireframe or mesh → nodes and edges (merged, validated)
//   POST build         body: a design → {"job": id}: the full build runs in the background
//   GET  build/<id>    its progress over joints, then its summary and the files it made
//   GET  build/<id>/files/<name>   one of those files (joint STLs, 3MF, cut plan, guide, ...)
//
// Files are kept in memory: a request names a job and a key of that job's file table, never a
// path. Posted designs may not name files (network:, reuse_joints_from:).
#include "kit_api.h"

// clang-format off
#include "fabkit/core/file_io.h"
#include "fabkit/rods/build.h"
#include "fabkit/rods/design_file.h"
#include "fabkit/rods/joint_geometry.h"
#include "fabkit/rods/outputs.h"
// clang-format on

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace fabkit::server {
namespace {

using json = Json;
using namespace fabkit::rods;
using Clock = std::chrono::steady_clock;

constexpr int kMaxNodes = 2000;
constexpr int kMaxEdges = 5000;
/// Finished builds kept for download; older ones are forgotten.
constexpr std::size_t kKeptBuilds = 6;
/// A build's time limit, in multiples of the server's solve limit (20 s × 6 = 2 min).
constexpr double kBuildTimeFactor = 6;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Millimetres to the micrometre: the preview is drawn, not printed, and the answer is a third
// the size of full precision.
double um(double v) {
  const double r = std::round(v * 1000) / 1000;
  return r == 0 ? 0 : r;
}

json mesh_json(const TriangleMesh& m) {
  json vertices = json::array();
  for (const Vec3& v : m.vertices) {
    vertices.push_back(um(v.x()));
    vertices.push_back(um(v.y()));
    vertices.push_back(um(v.z()));
  }
  json faces = json::array();
  for (const auto& f : m.faces) {
    faces.push_back(f[0]);
    faces.push_back(f[1]);
    faces.push_back(f[2]);
  }
  return {{"vertices", std::move(vertices)}, {"faces", std::move(faces)}};
}

json vec_json(const Vec3& v) {
  return json::array({um(v.x()), um(v.y()), um(v.z())});
}

Design load(const std::string& body) {
  DesignOptions o;
  o.files = FilePolicy::kRefuse;
  o.max_nodes = kMaxNodes;
  o.max_edges = kMaxEdges;
  return load_design_text(body, "design.yaml", {}, o);
}

// 400 for a design that cannot be read, with every diagnostic (file:line of the posted text).
bool reject_input(const Design& d, httplib::Response& res) {
  if (d.readable && !d.diagnostics.has_errors_of(DiagnosticClass::kInput)) return false;
  std::string first = "the design cannot be read";
  for (const Diagnostic& x : d.diagnostics) {
    if (x.severity == Severity::kError) {
      first = x.format();
      break;
    }
  }
  reply_error(res, 400, first, to_json(d.diagnostics));
  return true;
}

// Every error with its file:line:column ("import.obj:2:3: error: ..."), one per line.
std::string located_errors(const Diagnostics& d) {
  std::string out;
  for (const Diagnostic& x : d) {
    if (x.severity != Severity::kError) continue;
    if (!out.empty()) out += '\n';
    out += x.format();
  }
  return out;
}

// Which rods and joints a finding is about: the library names them in its messages ("rod
// 03-07", "joint 07"), with a fixed number of digits, so a name never prefixes another.
json named_parts(const Structure& s, const std::string& message) {
  json rods_named = json::array(), joints_named = json::array();
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    if (message.find(s.rod_name(static_cast<int>(e))) != std::string::npos) {
      rods_named.push_back(e);
    }
  }
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (message.find(s.joint_name(static_cast<int>(i))) != std::string::npos) {
      joints_named.push_back(i);
    }
  }
  return {{"rods", rods_named}, {"joints", joints_named}};
}

json findings_json(const Structure& s, const Diagnostics& findings) {
  json out = json::array();
  for (const Diagnostic& d : findings) {
    json j = to_json(d);
    json parts = named_parts(s, d.message);
    j["rods"] = parts["rods"];
    j["joints"] = parts["joints"];
    out.push_back(j);
  }
  return out;
}

json steps_json(const Structure& s, const std::vector<AssemblyStep>& steps) {
  json out = json::array();
  for (const AssemblyStep& st : steps) {
    if (st.kind == AssemblyStep::Kind::kJoint) {
      out.push_back({{"kind", "joint"},
                     {"joint", st.joint},
                     {"label", s.joint_label(st.joint)},
                     {"text", st.text}});
    } else {
      out.push_back({{"kind", "rod"},
                     {"rod", st.rod},
                     {"from", st.from_joint},
                     {"to", st.to_joint},
                     {"length", um(st.rod_length)},
                     {"text", st.text}});
    }
  }
  return out;
}

// Everything the designer draws for one state of the design; library calls only.
json preview_json(const Design& d) {
  const auto t0 = Clock::now();
  const Structure& s = d.structure;
  const Parameters& p = d.parameters;
  json timings = json::object();
  const Layout layout = compute_layout(s, p);
  const Preview preview = make_preview(s, p, layout);
  timings["layout_preview_ms"] = ms_since(t0);
  auto t1 = Clock::now();
  CheckOptions co;
  co.loads = d.loads;
  co.balance = d.supports.empty();  // a design with supports is mounted: balance is moot
  const CheckReport report = check(s, p, layout, co, preview.joint_masses);
  timings["checks_ms"] = ms_since(t1);
  t1 = Clock::now();
  FrameOptions fo;
  fo.loads = d.loads;
  fo.supports = d.supports;
  const FrameResult frame = analyse_frame(s, p, layout, fo, preview.joint_masses);
  timings["frame_ms"] = ms_since(t1);
  t1 = Clock::now();
  const std::vector<AssemblyStep> steps = assembly_order(s, layout, d.assembly_start);
  timings["assembly_ms"] = ms_since(t1);
  timings["library_ms"] = ms_since(t0);  // the library's calls; the rest is writing the answer
  t1 = Clock::now();

  json joints = json::array();
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const int node = static_cast<int>(i);
    double max_offset = 0, max_cosine = -1;
    for (const RodEnd* end : layout.ends_at(node)) {
      max_offset = std::max(max_offset, end->offset);
      max_cosine = std::max(max_cosine, end->max_cosine);
    }
    const double smallest_angle = layout.rods_at[i].size() > 1
                                      ? std::acos(std::clamp(max_cosine, -1.0, 1.0)) * 180 / M_PI
                                      : 180.0;
    joints.push_back({{"name", s.joint_name(node)},
                      {"label", s.joint_label(node)},
                      {"position", vec_json(s.nodes[i].position)},
                      {"rods", layout.rods_at[i]},
                      {"max_offset", um(max_offset)},
                      {"smallest_angle", um(smallest_angle)},
                      {"mass", preview.joint_masses.size() > i ? preview.joint_masses[i].mass : 0},
                      {"red", static_cast<bool>(report.red_joints[i])},
                      {"mesh", mesh_json(preview.joints[i])}});
  }
  json rods_out = json::array();
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    json rod = {
        {"name", s.rod_name(static_cast<int>(e))},
        {"a", s.rods[e].a},
        {"b", s.rods[e].b},
        {"edge_length", um(layout.edge_length[e])},
        {"length", um(layout.rod_length[e])},
        {"offsets", json::array({um(layout.ends[e][0].offset), um(layout.ends[e][1].offset)})},
        {"red", static_cast<bool>(report.red_rods[e])},
        {"mesh", mesh_json(preview.rods[e])}};
    if (frame.solved && e < frame.rods.size()) {
      const RodStress& st = frame.rods[e];
      rod["utilisation"] = st.utilisation;
      rod["axial"] = st.axial;
      rod["moment"] = st.moment;
      rod["stress"] = st.stress;
      rod["governing"] = std::string(st.governing);
    }
    rods_out.push_back(rod);
  }
  json intersections = json::array();
  for (const RodPair& pair : report.intersections) {
    intersections.push_back({{"rods", json::array({pair.rod_a, pair.rod_b})},
                             {"distance", um(pair.distance)},
                             {"clearance", um(pair.clearance)},
                             {"point", vec_json(pair.point)}});
  }
  const Balance& b = report.balance;
  json polygon = json::array();
  for (const Eigen::Vector2d& q : b.support_polygon) polygon.push_back({um(q.x()), um(q.y())});
  json balance = {{"checked", co.balance},
                  {"mass", b.mass},
                  {"center_of_mass", vec_json(b.center_of_mass)},
                  {"ground_z", um(b.ground_z)},
                  {"ground_nodes", b.ground_nodes},
                  {"support_polygon", polygon},
                  {"margin", um(b.margin)},
                  {"stands", b.stands}};
  json frame_out = {{"solved", frame.solved},
                    {"max_utilisation", frame.max_utilisation},
                    {"critical_rod", frame.critical_rod},
                    {"max_deflection", frame.max_deflection},
                    {"max_deflection_node", frame.max_deflection_node},
                    {"total_load", frame.total_load}};
  Diagnostics findings = d.diagnostics;
  findings.append(report.findings);
  findings.append(frame.findings);
  json findings_out = findings_json(s, findings);
  // The joints a finding is about where its message names them by label only: a swallowed or
  // missing rod is its two joints' doing (their offsets), a tipping design its floor contacts'.
  for (json& f : findings_out) {
    const std::string code = f["code"].get<std::string>();
    if (f["severity"] != "error") continue;
    std::set<int> named(f["joints"].begin(), f["joints"].end());
    if (code == "joint-swallows-rod" || code == "no-rod-left") {
      for (const json& e : f["rods"]) {
        named.insert(s.rods[e.get<std::size_t>()].a);
        named.insert(s.rods[e.get<std::size_t>()].b);
      }
    } else if (code == "unbalanced") {
      named.insert(b.ground_nodes.begin(), b.ground_nodes.end());
    }
    f["joints"] = named;
  }
  timings["json_ms"] = ms_since(t1);
  return {{"name", d.name},
          {"parameters",
           {{"radius", p.radius},
            {"sides", p.sides},
            {"wall", p.wall},
            {"socket", p.socket},
            {"tolerance", p.tolerance}}},
          {"joints", std::move(joints)},
          {"rods", std::move(rods_out)},
          {"intersections", intersections},
          {"balance", balance},
          {"frame", frame_out},
          {"assembly", steps_json(s, steps)},
          {"passed", !findings.has_errors()},
          {"findings", std::move(findings_out)},
          {"timings", timings}};
}

// ---- builds in the background ----------------------------------------------------------------

struct BuildJob {
  int id = 0;
  std::atomic<int> done{0};
  std::atomic<int> total{0};
  std::mutex mutex;                          // guards what follows
  std::string state = "running";             // running, done, failed
  int status = 200;                          // the HTTP status a failure maps to
  json result;                               // summary, or the error
  std::map<std::string, std::string> files;  // name → bytes
  Clock::time_point started = Clock::now();
};

struct BuildJobs {
  std::mutex mutex;
  int next_id = 1;
  std::deque<std::shared_ptr<BuildJob>> jobs;

  std::shared_ptr<BuildJob> find(int id) {
    std::lock_guard lock(mutex);
    for (const auto& j : jobs) {
      if (j->id == id) return j;
    }
    return nullptr;
  }
};

std::string content_type(const std::string& name) {
  const auto ends = [&](std::string_view ext) {
    return name.size() >= ext.size() &&
           name.compare(name.size() - ext.size(), ext.size(), ext) == 0;
  };
  if (ends(".stl")) return "model/stl";
  if (ends(".3mf")) return "model/3mf";
  if (ends(".glb")) return "model/gltf-binary";
  if (ends(".svg")) return "image/svg+xml";
  if (ends(".csv")) return "text/csv";
  if (ends(".json")) return "application/json";
  return "application/octet-stream";
}

// Runs the build and keeps what write_outputs makes: written into a private temporary
// directory (the library writes each file atomically), read back, the directory removed.
void run_build(const std::shared_ptr<BuildJob>& job,
               const Design& design,
               Clock::time_point deadline,
               double timeout_s) {
  BuildOptions options;
  options.deadline = deadline;
  options.cut_plan.time_limit_s = std::min(options.cut_plan.time_limit_s, timeout_s / 2);
  options.on_progress = [job](int done, int total) {
    job->done = done;
    job->total = total;
  };
  const Summary s = build(design, options);
  json result = {{"termination", std::string(to_string(s.termination))},
                 {"message", s.message},
                 {"diagnostics", findings_json(design.structure, s.diagnostics)}};
  json timings = json::object();
  for (const auto& [stage, ms] : s.timings) timings[stage] = ms;
  result["timings"] = timings;
  std::map<std::string, std::string> files;
  int status = 200;
  if (s.termination == Termination::kBuilt || s.termination == Termination::kBuiltWithFindings) {
    json joints = json::array();
    for (const JointSolid& j : s.joints) {
      joints.push_back({{"joint", j.node},
                        {"label", j.label},
                        {"closed", j.solid.closed},
                        {"manifold", j.solid.manifold},
                        {"self_intersecting", j.solid.self_intersecting},
                        {"volume", j.volume},
                        {"text_height", j.text_height}});
    }
    result["joints"] = joints;
    if (s.cut_plan) {
      json stock = json::array();
      for (const StockCut& cut : s.cut_plan->stock) {
        json pieces = json::array();
        for (const PlacedPiece& piece : cut.pieces) {
          const auto k = static_cast<std::size_t>(piece.piece);
          pieces.push_back({{"label", k < s.cut_pieces.size() ? s.cut_pieces[k].label : ""},
                            {"start", um(piece.start)},
                            {"length", um(piece.length)}});
        }
        stock.push_back({{"pieces", pieces}, {"remainder", um(cut.remainder)}});
      }
      result["cut_plan"] = {{"stock_count", s.cut_plan->stock_count()},
                            {"proven_optimal", s.cut_plan->proven_optimal},
                            {"summary", s.cut_plan->summary},
                            {"stock_length", design.parameters.stock.length},
                            {"end_padding", design.parameters.stock.end_padding},
                            {"stock", stock}};
    }
    // unique in the process too (several servers, e.g. in tests, number their jobs alike)
    static std::atomic<long> builds{0};
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() /
        fmt::format("fabkit-rods-build-{}-{}", static_cast<long>(getpid()), ++builds);
    Diagnostics io;
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    const auto written = write_outputs(design, s, dir, io);
    for (const auto& path : written) {
      std::ifstream in(path, std::ios::binary);
      std::ostringstream bytes;
      bytes << in.rdbuf();
      files[path.filename().string()] = bytes.str();
    }
    std::filesystem::remove_all(dir, ec);
    if (io.has_errors()) {
      status = 500;
      result = {{"error", messages_of(io)}, {"diagnostics", to_json(io)}};
      files.clear();
    }
  } else {
    status = http_status(s.diagnostics);
    if (s.termination == Termination::kTimeLimit) status = 503;
    result["error"] = s.termination == Termination::kTimeLimit
                          ? fmt::format(
                                "the build took longer than {:g} s and was stopped "
                                "(fabkit serve's time limit); nothing was made",
                                timeout_s)
                          : s.message;
  }
  json listing = json::array();
  for (const auto& [name, bytes] : files) {
    listing.push_back({{"name", name}, {"bytes", bytes.size()}});
  }
  result["files"] = listing;
  std::lock_guard lock(job->mutex);
  job->files = std::move(files);
  job->status = status;
  job->result = std::move(result);
  job->state = status == 200 ? "done" : "failed";
}

json job_json(BuildJob& job) {
  std::lock_guard lock(job.mutex);
  json out = {{"job", job.id},
              {"state", job.state},
              {"done", job.done.load()},
              {"total", job.total.load()},
              {"seconds", ms_since(job.started) / 1000}};
  if (job.state != "running") {
    out["status"] = job.status;
    out["result"] = job.result;
  }
  return out;
}

}  // namespace

KitApi rods_api(const ApiContext& context) {
  KitApi api;
  api.kit = "rods";
  using M = ApiRoute::Method;
  auto jobs = std::make_shared<BuildJobs>();

  api.routes.push_back(
      {M::kPost, "preview", [](const httplib::Request& req, httplib::Response& res) {
         const auto t0 = Clock::now();
         const Design d = load(req.body);
         if (reject_input(d, res)) return;
         json out = preview_json(d);
         out["timings"]["server_ms"] = ms_since(t0);
         reply(res, 200, out);
       }});

  api.routes.push_back(
      {M::kPost, "import-obj", [](const httplib::Request& req, httplib::Response& res) {
         std::vector<NodeInput> nodes;
         std::vector<EdgeInput> edges;
         Diagnostics d;
         if (!read_network_obj(req.body, "import.obj", nodes, edges, d) || d.has_errors()) {
           reply_error(res, 400, located_errors(d), to_json(d));
           return;
         }
         if (nodes.size() > static_cast<std::size_t>(kMaxNodes) ||
             edges.size() > static_cast<std::size_t>(kMaxEdges)) {
           reply_error(res,
                       400,
                       fmt::format("the OBJ has {} vertices and {} edges; the editor takes at "
                                   "most {} and {}",
                                   nodes.size(),
                                   edges.size(),
                                   kMaxNodes,
                                   kMaxEdges));
           return;
         }
         const Parameters defaults;
         const auto s = build_structure(nodes, edges, 1, defaults.merge_tolerance, d);
         if (!s) {
           reply_error(res, 400, located_errors(d), to_json(d));
           return;
         }
         json out_nodes = json::array(), out_edges = json::array();
         for (const Node& n : s->nodes) out_nodes.push_back(vec_json(n.position));
         for (const Rod& r : s->rods) out_edges.push_back({r.a, r.b});
         reply(res, 200, {{"nodes", out_nodes}, {"edges", out_edges}, {"diagnostics", to_json(d)}});
       }});

  api.routes.push_back(
      {M::kPost, "build", [context, jobs](const httplib::Request& req, httplib::Response& res) {
         Design d = load(req.body);
         if (reject_input(d, res)) return;
         std::shared_ptr<BuildJob> job;
         {
           std::lock_guard lock(jobs->mutex);
           for (const auto& j : jobs->jobs) {
             std::lock_guard jl(j->mutex);
             if (j->state == "running") {
               reply_error(res,
                           429,
                           fmt::format("a build is already running (job {}); wait for it", j->id));
               return;
             }
           }
           job = std::make_shared<BuildJob>();
           job->id = jobs->next_id++;
           job->total = static_cast<int>(d.structure.nodes.size());
           jobs->jobs.push_back(job);
           while (jobs->jobs.size() > kKeptBuilds) jobs->jobs.pop_front();
         }
         // A build runs in the background, not inside the request: it may take several times
         // a solve's limit (28 engraved joints take ~9 s on two idle cores, more when busy).
         const double timeout_s = context.options->solve_timeout_s * kBuildTimeFactor;
         const auto deadline =
             Clock::now() + std::chrono::milliseconds(static_cast<long long>(timeout_s * 1000));
         std::thread([job, design = std::move(d), deadline, timeout_s] {
           run_build(job, design, deadline, timeout_s);
         }).detach();
         reply(res, 202, job_json(*job));
       }});

  api.routes.push_back(
      {M::kGet,
       R"(build/([0-9]{1,9}))",
       [jobs](const httplib::Request& req, httplib::Response& res) {
         const auto job = jobs->find(std::stoi(req.matches[1].str()));
         if (!job) {
           reply_error(res, 404, "no such build (finished builds are kept for the last 6)");
           return;
         }
         reply(res, 200, job_json(*job));
       }});

  api.routes.push_back(
      {M::kGet,
       R"(build/([0-9]{1,9})/files/([A-Za-z0-9_.-]{1,64}))",
       [jobs](const httplib::Request& req, httplib::Response& res) {
         const auto job = jobs->find(std::stoi(req.matches[1].str()));
         const std::string name = req.matches[2].str();
         if (!job) {
           reply_error(res, 404, "no such build (finished builds are kept for the last 6)");
           return;
         }
         std::lock_guard lock(job->mutex);
         const auto it = job->files.find(name);
         if (it == job->files.end()) {
           reply_error(res, 404, fmt::format("build {} made no file '{}'", job->id, name));
           return;
         }
         res.set_header("Content-Disposition", fmt::format("attachment; filename=\"{}\"", name));
         res.set_content(it->second, content_type(name));
       }});
  return api;
}

}  // namespace fabkit::server
