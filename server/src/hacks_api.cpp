// The hacks kit's API: the parts library, meshes, two-way filtering, check and solve.
#include "kit_api.h"

// clang-format off
#include "fabkit/hacks/deadline.h"
#include "fabkit/hacks/design_file.h"
#include "fabkit/hacks/parts_library.h"
#include "fabkit/hacks/solution_export.h"
#include "fabkit/hacks/solve.h"
#include "fabkit/core/gltf.h"
#include "fabkit/core/text.h"
// clang-format on

#include <fmt/format.h>

namespace fabkit::server {
namespace {

using json = Json;
using namespace fabkit::hacks;

json primitive_json(const Primitive& p) {
  json shape = json::object();
  for (std::string_view f : shape_field_names(p.type)) {
    shape[std::string(f)] = shape_field_value(p.shape, f);
  }
  json params = json::array();
  for (const ParamSpec& s : p.connector_params()) {
    params.push_back({{"name", s.name},
                      {"min", s.lo},
                      {"max", s.hi},
                      {"init", s.init},
                      {"tag", std::string(to_string(s.tag))}});
  }
  json partners = json::array();
  for (PrimitiveType t : allowed_partners(p.type)) partners.push_back(std::string(to_string(t)));
  return {{"name", p.name},
          {"type", std::string(to_string(p.type))},
          {"connector", std::string(to_string(p.connector_kind()))},
          {"description", p.describe()},
          {"shape", shape},
          {"frame", to_json(p.frame)},
          {"closed", p.closed_for_connect()},
          {"single_connection", p.single_connection()},
          {"critical_dim", p.critical_dim()},
          {"connects_to", partners},
          {"params", params}};
}

// Reads a posted design: no part files (a request may not name files), capped in size.
Design load(const ApiContext& context,
            const PartsLibrary& library,
            const std::string& body,
            std::chrono::steady_clock::time_point deadline) {
  DesignOptions o;
  o.max_parts = context.options->max_parts;
  o.max_connections = context.options->max_connections;
  o.part_files = PartFilePolicy::kRefuse;
  o.verify.deadline = deadline;
  return load_design_text(body, "design.yaml", library, o);
}

// 400 for input errors (the file cannot be understood), with every diagnostic.
std::optional<JobAnswer> reject_input(const Design& d) {
  if (d.readable && !d.diagnostics.has_errors_of(DiagnosticClass::kInput)) return std::nullopt;
  std::string first = "the design cannot be read";
  for (const Diagnostic& x : d.diagnostics) {
    if (x.severity == Severity::kError) {
      first = x.format();
      break;
    }
  }
  return error_answer(400, first, to_json(d.diagnostics));
}

// The parts library as the editor lists it; the library is fixed once the server runs, so it
// is made once.
std::string parts_json(const PartsLibrary& lib) {
  json parts = json::array();
  for (const PartGenerator& g : lib.generators()) {
    Diagnostics d;
    const auto part = lib.make(g.name, {}, d);
    if (!part) continue;
    json prims = json::array();
    for (const Primitive& p : part->primitives) prims.push_back(primitive_json(p));
    json params = json::array();
    for (const ParamSchema& s : g.params) {
      params.push_back({{"name", s.name},
                        {"default", s.default_value},
                        {"min", s.min},
                        {"max", s.max},
                        {"unit", s.unit},
                        {"doc", s.doc}});
    }
    parts.push_back({{"name", g.name},
                     {"aliases", g.aliases},
                     {"description", g.description},
                     {"category", std::string(to_string(g.category))},
                     {"mass", part->mass},
                     {"params", params},
                     {"primitives", prims}});
  }
  return dump_json(parts);
}

}  // namespace

KitApi hacks_api(const ApiContext& context) {
  KitApi api;
  api.kit = "hacks";
  // The built-in parts plus the part files the server was started with (never from a request).
  auto shared = std::make_shared<PartsLibrary>(PartsLibrary::builtin());
  for (const std::filesystem::path& file : context.options->hacks_part_files) {
    Diagnostics d;
    if (!shared->load_yaml(file, d)) api.startup_errors.append(d);
  }
  std::shared_ptr<const PartsLibrary> library = shared;
  api.also_at_root = true;
  using M = ApiRoute::Method;

  auto parts_answer = std::make_shared<std::string>(parts_json(*library));
  api.routes.push_back(
      {M::kGet, "parts", [parts_answer](const httplib::Request&, httplib::Response& res) {
         res.status = 200;
         res.set_content(*parts_answer, "application/json");
       }});

  api.routes.push_back(
      {M::kGet,
       R"(parts/([A-Za-z0-9_]{1,64})/mesh)",
       [library](const httplib::Request& req, httplib::Response& res) {
         const std::string name = req.matches[1];
         ParamValues values;
         for (const auto& [key, value] : req.params) {
           char* end = nullptr;
           const double v = std::strtod(value.c_str(), &end);
           if (end == value.c_str() || *end != '\0') {
             reply_error(
                 res,
                 400,
                 fmt::format(
                     "parameter {} must be a number, not '{}'", excerpt(key), excerpt(value)));
             return;
           }
           values[key] = v;
         }
         Diagnostics d;
         const auto part = library->make(name, values, d);
         if (!part) {
           const bool unknown = !library->find(name);
           reply_error(res, unknown ? 404 : 400, messages_of(d), to_json(d));
           return;
         }
         json prims = json::object();
         for (const Primitive& p : part->primitives) prims[p.name] = to_json(primitive_mesh(p));
         reply(res,
               200,
               {{"name", part->type_name}, {"body", to_json(part->mesh)}, {"primitives", prims}});
       }});

  // Two-way filtering: which of the candidate primitives can connect to the picked one
  // (paper Table 1, closedness, sizes), each with the reason when not.
  api.routes.push_back(
      {M::kPost,
       "compatible",
       [library](const httplib::Request& req, httplib::Response& res) {
         json body;
         try {
           body = json::parse(req.body);
         } catch (const json::exception& e) {
           reply_error(
               res, 400, fmt::format("the request is not JSON: {}", excerpt(e.what(), 200)));
           return;
         }
         auto primitive_of =
             [&](const json& j, std::shared_ptr<Part>& part, PrimitiveId& index, std::string& why) {
               if (!j.is_object() || !j.contains("part") || !j["part"].is_string() ||
                   !j.contains("primitive") || !j["primitive"].is_string()) {
                 why = "each primitive is {\"part\": name, \"primitive\": name, \"params\": {...}}";
                 return false;
               }
               ParamValues values;
               if (j.contains("params") && j["params"].is_object()) {
                 for (const auto& [k, v] : j["params"].items()) {
                   if (!v.is_number()) {
                     why = fmt::format("parameter {} must be a number", k);
                     return false;
                   }
                   values[k] = v.get<double>();
                 }
               }
               Diagnostics d;
               part = library->make(j["part"].get<std::string>(), values, d);
               if (!part) {
                 why = messages_of(d);
                 return false;
               }
               index = part->find_primitive(j["primitive"].get<std::string>());
               if (!index.valid()) {
                 why = fmt::format("{} has no primitive '{}' (it has {})",
                                   part->type_name,
                                   j["primitive"].get<std::string>(),
                                   part->primitive_list());
                 return false;
               }
               return true;
             };
         if (!body.is_object() || !body.contains("a") || !body.contains("b") ||
             !body["b"].is_array()) {
           reply_error(res, 400, "expected {\"a\": primitive, \"b\": [primitive, ...]}");
           return;
         }
         if (body["b"].size() > 5000) {
           reply_error(res, 400, "at most 5000 candidates per request");
           return;
         }
         std::shared_ptr<Part> pa;
         PrimitiveId ia;
         std::string why;
         if (!primitive_of(body["a"], pa, ia, why)) {
           reply_error(res, 400, why);
           return;
         }
         json out = json::array();
         for (const json& jb : body["b"]) {
           std::shared_ptr<Part> pb;
           PrimitiveId ib;
           if (!primitive_of(jb, pb, ib, why)) {
             out.push_back({{"ok", false}, {"reason", why}});
             continue;
           }
           const Primitive& a = pa->primitive(ia);
           const Primitive& b = pb->primitive(ib);
           const std::string la = fmt::format("{}.{}", pa->type_name, a.name);
           const std::string lb = fmt::format("{}.{}", pb->type_name, b.name);
           if (!pair_allowed(a.type, b.type)) {
             out.push_back({{"ok", false},
                            {"reason",
                             fmt::format("a {} cannot connect to a {} (paper Table 1)",
                                         to_string(a.type),
                                         to_string(b.type))}});
             continue;
           }
           Diagnostics d;
           const bool ok =
               check_compatibility({&a, la, a.critical_dim()}, {&b, lb, b.critical_dim()}, d);
           out.push_back({{"ok", ok}, {"reason", ok ? "" : messages_of(d)}});
         }
         reply(res, 200, out);
       },
       // Light: table lookups and size rules, answered on the request thread.
       ApiRoute::Load::kLight});

  // Geometry of a loose primitive (an environment made of primitives, e.g. a table
  // surface): the primitive's own coordinates, sizes from the query (mm, degrees).
  api.routes.push_back(
      {M::kGet,
       R"(primitives/([a-z]{3,12})/mesh)",
       [](const httplib::Request& req, httplib::Response& res) {
         const auto type = primitive_type_from_string(req.matches[1].str());
         if (!type) {
           reply_error(
               res, 404, fmt::format("unknown primitive type '{}'", excerpt(req.matches[1].str())));
           return;
         }
         Primitive p = Primitive::make(std::string(to_string(*type)), *type, {});
         for (const auto& [key, value] : req.params) {
           double* field = shape_field(p.shape, key);
           const auto names = shape_field_names(*type);
           if (!field || std::find(names.begin(), names.end(), key) == names.end()) {
             reply_error(
                 res, 400, fmt::format("a {} has no size '{}'", to_string(*type), excerpt(key)));
             return;
           }
           char* end = nullptr;
           *field = std::strtod(value.c_str(), &end);
           if (end == value.c_str() || *end != '\0') {
             reply_error(
                 res, 400, fmt::format("{} must be a number, not '{}'", key, excerpt(value)));
             return;
           }
         }
         Diagnostics d;
         p.validate(to_string(*type), d);
         if (d.has_errors()) {
           reply_error(res, 400, messages_of(d), to_json(d));
           return;
         }
         reply(res,
               200,
               {{"type", std::string(to_string(*type))}, {"mesh", to_json(primitive_mesh(p))}});
       }});

  api.routes.push_back(
      // Heavy (a POST): the server runs it on its job queue (kit_api.h, ApiRoute::load).
      {M::kPost, "check", [context, library](const httplib::Request& req, httplib::Response& res) {
         reply(res, [&]() -> JobAnswer {
           const Design d = load(context, *library, req.body, context.deadline());
           if (auto refused = reject_input(d)) return *refused;
           json steps = json::array();
           for (const DesignStep& s : d.steps) {
             json step = {{"text", s.text},
                          {"line", s.where.line},
                          {"accepted", s.accepted},
                          {"skipped", s.skipped},
                          {"closes_cycle", s.report.closes_cycle},
                          {"cycles", s.report.cycles},
                          {"milliseconds", s.report.milliseconds},
                          {"diagnostics", to_json(s.report.diagnostics)}};
             if (!s.accepted && !s.report.best_part_frames.empty()) {
               // How close a cycle came: the best configuration found, one frame per part.
               json frames = json::array();
               for (const Frame& f : s.report.best_part_frames) frames.push_back(to_json(f));
               step["best_part_frames"] = frames;
             }
             steps.push_back(step);
           }
           json parts = json::array();
           const std::vector<Mat4> frames = d.assembly.part_frames(d.assembly.values());
           for (int i = 0; i < d.assembly.part_count(); ++i) {
             parts.push_back(
                 {{"name", d.assembly.label(PartId{i})},
                  {"type", d.assembly.node(PartId{i}).part->type_name},
                  {"frame", to_json(Frame::from_matrix(frames[static_cast<std::size_t>(i)]))}});
           }
           return json_answer(
               200,
               {{"valid", d.feasible()},
                {"stopped_at_deadline", d.diagnostics.has_errors_of(DiagnosticClass::kTimeout)},
                {"steps", steps},
                {"parts", parts},
                {"diagnostics", to_json(d.diagnostics)}});
         }());
       }});

  api.routes.push_back(
      {M::kPost, "solve", [context, library](const httplib::Request& req, httplib::Response& res) {
         const bool glb = req.has_param("format") && req.get_param_value("format") == "glb";
         reply(res, [&]() -> JobAnswer {
           const auto limit = context.deadline();
           const Design d = load(context, *library, req.body, limit);
           if (auto refused = reject_input(d)) return *refused;
           if (!d.feasible()) {
             const int status = http_status(d.diagnostics);
             return error_answer(status,
                                 status == 503 ? messages_of(d.diagnostics)
                                               : std::string("the design cannot be built"),
                                 to_json(d.diagnostics));
           }
           SolveOptions so;
           so.deadline = limit;
           const SolveResult r = solve(d.assembly, so);
           if (r.termination == Termination::kTimeout) {
             return error_answer(503,
                                 fmt::format("the solve took longer than {:g} s: {}",
                                             context.options->solve_timeout_s,
                                             stopped_at_deadline(r, so)));
           }
           if (glb) {
             Diagnostics dg;
             std::optional<std::string> bytes = encode_glb(solution_scene(d.assembly, r), dg);
             if (!bytes) return error_answer(500, "cannot encode the scene", to_json(dg));
             return {200, std::move(*bytes), "model/gltf-binary"};
           }
           // result.json, plus for the editor every part's frame after step 1 (before gravity),
           // so it can show the assembly settling.
           json out = json::parse(result_json(d.assembly, r, d.name));
           json step1 = json::array();
           if (r.step1_parameters.size() == d.assembly.values().size()) {
             const std::vector<Mat4> frames = d.assembly.part_frames(r.step1_parameters);
             for (int i = 0; i < d.assembly.part_count(); ++i) {
               step1.push_back(
                   {{"name", d.assembly.label(PartId{i})},
                    {"frame", to_json(Frame::from_matrix(frames[static_cast<std::size_t>(i)]))}});
             }
           }
           out["step1_parts"] = step1;
           return json_answer(200, out);
         }());
       }});
  return api;
}

}  // namespace fabkit::server
