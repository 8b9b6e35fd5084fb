// The templates kit's API (design and fabrication by example, docs/templates-editor.md): the
// bundled database as a library, composing a model file, the controls of a node, one drag step
// solved by the library's QP, and the build's outputs for download.
//
//   GET  /api/templates/library               designs with their sub-templates (tree)
//   GET  /api/templates/library/{design}/mesh  ?node=path: the parts of a (sub-)template
//   POST /api/templates/compose               body: a model (YAML) → the composed model
//   POST /api/templates/controls              {"model", "node"} → six controls, hidden or not
//   POST /api/templates/drag                  {"model", "node", "control", "delta", "bom"}
//   POST /api/templates/build                 body: a model (YAML) → every output file
//
// Composing (snapping, connecting) costs up to a second; a drag step a millisecond. So composed
// models are kept per model text (a few, least recently used first out), and a drag session's
// Manipulator (its factorisation of the equality rows) with them: every drag step of one
// gesture starts from the same composed model and moves the control by the gesture's total δ.
#include "kit_api.h"

// clang-format off
#include "fabkit/templates/build.h"
#include "fabkit/templates/check.h"
#include "fabkit/templates/database.h"
#include "fabkit/templates/design_file.h"
#include "fabkit/templates/manipulate.h"
#include "fabkit/templates/scene.h"
#include "fabkit/core/file_io.h"
// clang-format on

#include <fmt/format.h>
#include <stdlib.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <list>
#include <map>
#include <memory>
#include <mutex>

namespace fabkit::server {
namespace {

using json = Json;
using namespace fabkit::templates;
using Clock = std::chrono::steady_clock;

constexpr std::size_t kCachedModels = 6;
constexpr double kMaxDragMm = 20000;  // a drag step larger than 20 m is not a user's gesture
constexpr int kMaxCompositions = 24;  // each one snaps and connects (up to ~1 s)

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

double round_to(double v, double step) {
  return std::round(v / step) * step;
}

// Meshes rounded to 0.01 mm: a third of the JSON, far below what a screen shows.
json mesh_json(const TriangleMesh& m) {
  json v = json::array();
  for (const Vec3& x : m.vertices) {
    for (int i = 0; i < 3; ++i) v.push_back(round_to(x[i], 0.01));
  }
  json f = json::array();
  for (const auto& t : m.faces) {
    for (int i = 0; i < 3; ++i) f.push_back(t[static_cast<std::size_t>(i)]);
  }
  return {{"vertices", v}, {"faces", f}};
}

json box_json(const Box& b) {
  json lo = json::array(), hi = json::array();
  for (int i = 0; i < 3; ++i) {
    lo.push_back(round_to(b.min()[i], 0.001));
    hi.push_back(round_to(b.max()[i], 0.001));
  }
  return {{"min", lo}, {"max", hi}};
}

std::string node_path(const Template& t, NodeId n) {
  return n == t.root() ? std::string() : t.path(n);
}

// Every part with its display mesh and colour (the library's materials), its element and node.
json parts_json(const Template& t, const ItemCatalog& catalog, const std::vector<char>& stable) {
  SceneOptions so;
  so.element_stable = stable;
  const std::vector<SceneObject> scene = model_scene(t, catalog, so);
  const std::vector<PlacedPart> placed = t.placed_parts();
  json out = json::array();
  for (std::size_t i = 0; i < placed.size() && i < scene.size(); ++i) {
    const PlacedPart& p = placed[i];
    const Element& e = t.element(p.element);
    const bool ok = stable.empty() || (p.element.value < static_cast<int>(stable.size()) &&
                                       stable[static_cast<std::size_t>(p.element.value)]);
    json color = json::array();
    for (int c = 0; c < 3; ++c) color.push_back(round_to(scene[i].color[c], 0.001));
    out.push_back({{"name", p.name},
                   {"element", e.name},
                   {"node", node_path(t, e.node)},
                   {"item", p.item},
                   {"role", p.role == PartRole::kPrincipal ? "principal" : "connecting"},
                   {"stable", ok},
                   {"color", color},
                   {"box", box_json(p.box)},
                   {"mesh", mesh_json(scene[i].mesh.transformed(scene[i].transform))}});
  }
  return out;
}

json nodes_json(const Template& t) {
  json out = json::array();
  for (std::size_t i = 0; i < t.nodes.size(); ++i) {
    const NodeId n(static_cast<int>(i));
    const Node& node = t.node(n);
    json children = json::array();
    for (NodeId c : node.children) children.push_back(node_path(t, c));
    out.push_back({{"path", node_path(t, n)},
                   {"name", node.name},
                   {"parent", node.parent.valid() ? json(node_path(t, node.parent)) : json()},
                   {"children", children},
                   {"element", node.element ? json(t.element(*node.element).name) : json()},
                   {"principal", node.element && t.element(*node.element).is_principal()},
                   {"connection", node.connection_node},
                   {"box", box_json(t.node_box(n))}});
  }
  return out;
}

json connections_json(const Template& t) {
  json out = json::array();
  for (const Connection& c : t.connections) {
    json principal = json::array(), connecting = json::array();
    for (ElementId e : c.principal) principal.push_back(t.element(e).name);
    for (ElementId e : c.connecting) connecting.push_back(t.element(e).name);
    out.push_back({{"name", c.name},
                   {"principal", principal},
                   {"connecting", connecting},
                   {"source", c.source}});
  }
  return out;
}

json stability_json(const Template& t, const StabilityResult& s) {
  json bodies = json::array();
  for (const Body& b : s.bodies) {
    json elements = json::array();
    for (ElementId e : b.elements) elements.push_back(t.element(e).name);
    bodies.push_back({{"elements", elements},
                      {"verdict", b.verdict},
                      {"stable", b.stable},
                      {"anchored", b.anchored},
                      {"mass_kg", round_to(b.mass_kg, 0.001)}});
  }
  return {{"stable", s.stable},
          {"bodies", bodies},
          {"milliseconds", s.milliseconds},
          {"diagnostics", to_json(s.diagnostics)}};
}

json bom_json_of(const std::optional<BillOfMaterials>& bom, const Diagnostics& diags) {
  if (!bom) return {{"lines", json::array()}, {"total", nullptr}, {"diagnostics", to_json(diags)}};
  json lines = json::array();
  for (const BomLine& l : bom->lines) {
    lines.push_back({{"item", l.item},
                     {"name", l.name},
                     {"category", std::string(to_string(l.category))},
                     {"parts", l.parts},
                     {"units", l.units},
                     {"unit", l.unit},
                     {"unit_price", l.unit_price},
                     {"total", l.total},
                     {"buy", l.buy},
                     {"sizes", l.sizes},
                     {"supplier", l.supplier},
                     {"part_number", l.part_number}});
  }
  return {{"lines", lines},
          {"total", bom->total},
          {"parts", bom->parts},
          {"milliseconds", bom->milliseconds},
          {"diagnostics", to_json(diags)}};
}

// The model at parameters `t.q`: geometry, stability per part and (optionally) the bill.
// Without `with_stability` (drag steps of a model with loads, whose contact-force QP takes
// ~100 ms) "stability" is null and every part is reported as its last check found it.
json state_json(const Template& t,
                const TemplateDatabase& db,
                const ComposedModel& cm,
                bool with_bom,
                bool with_stability = true) {
  StabilityOptions so;
  so.friction = cm.friction;
  so.loads = cm.loads;
  std::optional<StabilityResult> stability;
  if (with_stability) stability = check_stability(t, db.catalog(), so);
  json out = {
      {"parts",
       parts_json(t, db.catalog(), stability ? stability->element_stable : std::vector<char>())},
      {"nodes", nodes_json(t)},
      {"stability", stability ? stability_json(t, *stability) : json()},
      {"max_violation", t.max_violation()}};
  if (with_bom) {
    Diagnostics d;
    const auto bom = bill_of_materials(t, db.catalog(), d);
    out["bom"] = bom_json_of(bom, d);
  }
  return out;
}

json link_json(const Template& t, const Link& l) {
  json tried = json::array();
  for (const ConnectionCandidate& c : l.tried) {
    tried.push_back(
        {{"source", c.source},
         {"transferred", c.transferred},
         {"feasible", c.feasible},
         {"accepted", c.accepted},
         {"error_mm", std::isfinite(c.error_mm) ? json(c.error_mm) : json()},
         {"descriptor_distance",
          std::isfinite(c.descriptor_distance) ? json(c.descriptor_distance) : json()}});
  }
  auto name_of = [&](ElementId e) {
    return e.valid() && e.value < t.element_count() ? t.element(e).name : std::string("?");
  };
  return {{"added", name_of(l.added)},
          {"existing", name_of(l.existing)},
          {"connected", l.connection.has_value()},
          {"message", l.message},
          {"tried", tried}};
}

// A composed model and the drag sessions on it.
struct Session {
  ComposedModel composed;
  json answer;  // the compose answer (steps, state, check), computed once
  std::map<std::string, std::unique_ptr<Manipulator>, std::less<>> manipulators;
};

class Api {
 public:
  explicit Api(const ApiContext& context) : context_(context) {}

  // The session of a model text, composed now when it is not cached. Call with mutex_ held.
  std::shared_ptr<Session> session(const std::string& yaml, json& error, int& status) {
    for (auto it = sessions_.begin(); it != sessions_.end(); ++it) {
      if (it->first != yaml) continue;
      sessions_.splice(sessions_.begin(), sessions_, it);
      return it->second;
    }
    Diagnostics pre;
    if (auto kind = templates_file_kind(yaml, "model.yaml", pre);
        kind && *kind == TemplatesFileKind::kModel) {
      if (auto file = read_model_file(yaml, "model.yaml", pre);
          file && static_cast<int>(file->steps.size()) > kMaxCompositions) {
        status = 400;
        error = fmt::format("a model may have at most {} compositions here (it has {})",
                            kMaxCompositions,
                            file->steps.size());
        return nullptr;
      }
    }
    const auto start = Clock::now();
    auto s = std::make_shared<Session>();
    s->composed = compose_model(yaml, "model.yaml", db());
    if (!s->composed.readable) {
      status = 400;
      std::string first = "the model cannot be read";
      for (const Diagnostic& d : s->composed.diagnostics) {
        if (d.severity == Severity::kError) {
          first = d.format();
          break;
        }
      }
      error = {{"error", first}, {"diagnostics", to_json(s->composed.diagnostics)}};
      return nullptr;
    }
    const ComposedModel& cm = s->composed;
    const Template& t = cm.model.model();
    const CheckResult check = templates::check(cm, db());
    json steps = json::array();
    for (const StepReport& r : cm.steps) {
      json step = {{"text", r.text}, {"line", r.where.line}, {"ok", r.ok}, {"outcome", r.outcome}};
      if (r.snap) {
        step["snap"] = {{"snapped", r.snap->snapped},
                        {"planes", r.snap->chosen.size()},
                        {"combinations", r.snap->combinations},
                        {"milliseconds", r.snap->milliseconds}};
      }
      if (r.connect) {
        json links = json::array();
        for (const Link& l : r.connect->links) links.push_back(link_json(t, l));
        step["links"] = links;
        step["all_connected"] = r.connect->all_connected;
      }
      steps.push_back(step);
    }
    json compositions = json::array();
    for (const Composition& c : cm.model.compositions()) {
      compositions.push_back(
          {{"name", c.name}, {"source", c.source}, {"node", node_path(t, c.node)}});
    }
    s->answer = state_json(t, db(), cm, false);
    s->answer["name"] = cm.name;
    s->answer["steps"] = steps;
    s->answer["compositions"] = compositions;
    s->answer["connections"] = connections_json(t);
    s->answer["bom"] = bom_json_of(check.bom, Diagnostics());
    s->answer["verdict"] = check.verdict;
    s->answer["diagnostics"] = to_json(check.diagnostics);
    s->answer["compose_milliseconds"] = cm.milliseconds;
    s->answer["milliseconds"] = ms_since(start);
    sessions_.emplace_front(yaml, s);
    while (sessions_.size() > kCachedModels) sessions_.pop_back();
    return s;
  }

  static const TemplateDatabase& db() { return TemplateDatabase::bundled(); }

  std::mutex mutex_;  // the library's objects are used by one request at a time
  std::list<std::pair<std::string, std::shared_ptr<Session>>> sessions_;
  ApiContext context_;
  json library_;  // built on first use
};

bool parse_json(const httplib::Request& req, httplib::Response& res, json& body) {
  try {
    body = json::parse(req.body);
  } catch (const json::exception& e) {
    reply_error(res, 400, fmt::format("the request is not JSON: {}", e.what()));
    return false;
  }
  if (!body.is_object() || !body.contains("model") || !body["model"].is_string()) {
    reply_error(res, 400, "expected {\"model\": \"<model YAML>\", ...}");
    return false;
  }
  return true;
}

void reply_session_error(httplib::Response& res, int status, const json& error) {
  if (error.is_object()) {
    reply_error(res, status, error.value("error", "error"), error.value("diagnostics", json()));
  } else {
    reply_error(res, status, error.get<std::string>());
  }
}

// The node a request names: a path from the model's root ("table/base/legs") or a unique name.
NodeId node_of(const Template& t, const json& body, httplib::Response& res) {
  if (!body.contains("node") || !body["node"].is_string() ||
      body["node"].get<std::string>().size() > 512) {
    reply_error(res, 400, "expected \"node\": a node's path in the model (\"table/base/legs\")");
    return NodeId();
  }
  const std::string name = body["node"].get<std::string>();
  NodeId n = name.empty() ? t.root() : t.find(name);
  if (!n.valid()) n = t.find_node_or_element(name);
  if (!n.valid()) reply_error(res, 400, fmt::format("the model has no node '{}'", name));
  return n;
}

json control_json(const Control& c) {
  return {{"control", std::string(to_string(c.kind))},
          {"value", c.value},
          {"hidden", c.hidden},
          {"axis", c.axis()},
          {"size", c.is_size()}};
}

std::string base64(std::string_view bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string mime_of(const std::filesystem::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".csv") return "text/csv";
  if (ext == ".html") return "text/html";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".json") return "application/json";
  if (ext == ".glb") return "model/gltf-binary";
  if (ext == ".stl") return "model/stl";
  return "application/octet-stream";
}

}  // namespace

KitApi templates_api(const ApiContext& context) {
  KitApi api;
  api.kit = "templates";
  auto state = std::make_shared<Api>(context);
  using M = ApiRoute::Method;

  api.routes.push_back(
      {M::kGet, "library", [state](const httplib::Request&, httplib::Response& res) {
         const std::lock_guard lock(state->mutex_);
         if (state->library_.is_null()) {
           const TemplateDatabase& db = Api::db();
           json designs = json::array();
           json categories = json::array();
           for (const std::string& name : db.names()) {
             const SourceDesign* d = db.design(name);
             const Template* t = db.source_template(name);
             if (!d || !t) continue;
             json nodes = json::array();
             for (std::size_t i = 0; i < t->nodes.size(); ++i) {
               const NodeId n(static_cast<int>(i));
               const Node& node = t->node(n);
               if (node.connection_node) continue;
               if (node.parent.valid() && t->node(node.parent).connection_node) continue;
               const std::vector<ElementId> under = t->elements_under(n);
               int principal = 0;
               for (ElementId e : under) principal += t->element(e).is_principal();
               if (principal == 0) continue;  // connectors alone are not a template to add
               nodes.push_back({{"path", node_path(*t, n)},
                                {"name", node.name},
                                {"depth", t->depth(n)},
                                {"elements", under.size()},
                                {"box", box_json(t->node_box(n))},
                                {"leaf", node.element.has_value()}});
             }
             if (std::find(categories.begin(), categories.end(), d->category) == categories.end())
               categories.push_back(d->category);
             designs.push_back({{"name", name},
                                {"title", d->title},
                                {"category", d->category},
                                {"description", d->description},
                                {"parts", t->part_count()},
                                {"box", box_json(t->node_box(t->root()))},
                                {"nodes", nodes}});
           }
           state->library_ = {{"designs", designs}, {"categories", categories}};
         }
         reply(res, 200, state->library_);
       }});

  api.routes.push_back(
      {M::kGet,
       R"(library/([a-z0-9_]{1,64})/mesh)",
       [state](const httplib::Request& req, httplib::Response& res) {
         const std::lock_guard lock(state->mutex_);
         const TemplateDatabase& db = Api::db();
         const std::string name = req.matches[1];
         const Template* t = db.source_template(name);
         if (!t) {
           reply_error(res, 404, fmt::format("no design '{}'", name));
           return;
         }
         const std::string path = req.has_param("node") ? req.get_param_value("node") : "";
         const NodeId n = path.empty() ? t->root() : t->find(path);
         if (!n.valid()) {
           reply_error(res, 404, fmt::format("design '{}' has no node '{}'", name, path));
           return;
         }
         const Template sub = n == t->root() ? *t : t->subtree(n);
         reply(res,
               200,
               {{"template", sub.name},
                {"box", box_json(sub.node_box(sub.root()))},
                {"parts", parts_json(sub, db.catalog(), {})}});
       }});

  api.routes.push_back(
      {M::kPost, "compose", [state](const httplib::Request& req, httplib::Response& res) {
         const std::lock_guard lock(state->mutex_);
         const auto start = Clock::now();
         json error;
         int status = 400;
         const auto s = state->session(req.body, error, status);
         if (!s) {
           reply_session_error(res, status, error);
           return;
         }
         json out = s->answer;
         out["request_milliseconds"] = ms_since(start);
         reply(res, 200, out);
       }});

  api.routes.push_back(
      {M::kPost, "controls", [state](const httplib::Request& req, httplib::Response& res) {
         const std::lock_guard lock(state->mutex_);
         json body;
         if (!parse_json(req, res, body)) return;
         json error;
         int status = 400;
         const auto s = state->session(body["model"].get<std::string>(), error, status);
         if (!s) {
           reply_session_error(res, status, error);
           return;
         }
         const Template& t = s->composed.model.model();
         const NodeId n = node_of(t, body, res);
         if (!n.valid()) return;
         const Manipulator m(t, {}, &Api::db().catalog());
         json controls = json::array();
         for (const Control& c : m.controls(n)) controls.push_back(control_json(c));
         reply(
             res,
             200,
             {{"node", node_path(t, n)}, {"box", box_json(t.node_box(n))}, {"controls", controls}});
       }});

  api.routes.push_back(
      {M::kPost, "drag", [state](const httplib::Request& req, httplib::Response& res) {
         const std::lock_guard lock(state->mutex_);
         const auto start = Clock::now();
         json body;
         if (!parse_json(req, res, body)) return;
         if (!body.contains("control") || !body["control"].is_string() || !body.contains("delta") ||
             !body["delta"].is_number()) {
           reply_error(res, 400, "expected \"control\" (size_x, center_z, ...) and \"delta\" (mm)");
           return;
         }
         const auto kind = control_from_string(body["control"].get<std::string>());
         if (!kind) {
           reply_error(res,
                       400,
                       fmt::format("unknown control '{}' (controls: center_x, center_y, "
                                   "center_z, size_x, size_y, size_z)",
                                   body["control"].get<std::string>()));
           return;
         }
         const double delta = body["delta"].get<double>();
         if (!std::isfinite(delta) || std::abs(delta) > kMaxDragMm) {
           reply_error(
               res,
               400,
               fmt::format(
                   "a drag moves at most {:g} mm (asked {})", kMaxDragMm, body["delta"].dump()));
           return;
         }
         json error;
         int status = 400;
         const auto s = state->session(body["model"].get<std::string>(), error, status);
         if (!s) {
           reply_session_error(res, status, error);
           return;
         }
         const double compose_ms = ms_since(start);
         const Template& t = s->composed.model.model();
         const NodeId n = node_of(t, body, res);
         if (!n.valid()) return;
         const std::string key = node_path(t, n);
         auto& m = s->manipulators[key];
         if (!m) m = std::make_unique<Manipulator>(t, ManipulateOptions{}, &Api::db().catalog());
         const Control c = m->control(n, *kind);
         if (c.hidden) {
           reply_error(res,
                       422,
                       fmt::format("{} of '{}' cannot change: the template's constraints fix it "
                                   "at {:g} mm",
                                   to_string(*kind),
                                   t.node(n).name,
                                   c.value),
                       to_json(Diagnostics()));
           return;
         }
         const auto qp_start = Clock::now();
         const DragResult r = m->drag(c, delta);
         const double qp_ms = ms_since(qp_start);
         if (r.diagnostics.has_errors()) {
           reply_error(
               res, http_status(r.diagnostics), messages_of(r.diagnostics), to_json(r.diagnostics));
           return;
         }
         Template moved = t;
         moved.q = r.q;
         const bool with_bom =
             body.contains("bom") && body["bom"].is_boolean() && body["bom"].get<bool>();
         const bool with_stability = !body.contains("stability") ||
                                     !body["stability"].is_boolean() ||
                                     body["stability"].get<bool>();
         json out = state_json(moved, Api::db(), s->composed, with_bom, with_stability);
         out["node"] = key;
         out["control"] = std::string(to_string(*kind));
         out["start"] = c.value;
         out["requested"] = r.requested;
         out["achieved"] = r.achieved;
         out["reached"] = r.reached;
         out["message"] = r.message;
         out["used_solver"] = r.used_solver;
         out["qp_milliseconds"] = qp_ms;
         out["lookup_milliseconds"] = compose_ms;
         out["milliseconds"] = ms_since(start);
         reply(res, 200, out);
       }});

  api.routes.push_back(
      {M::kPost, "build", [state](const httplib::Request& req, httplib::Response& res) {
         const std::lock_guard lock(state->mutex_);
         json error;
         int status = 400;
         const auto s = state->session(req.body, error, status);
         if (!s) {
           reply_session_error(res, status, error);
           return;
         }
         // Into a fresh private directory (never a name from the request), read back, removed.
         std::string pattern =
             (std::filesystem::temp_directory_path() / "fabkit-templates-XXXXXX").string();
         if (!mkdtemp(pattern.data())) {
           reply_error(res, 500, "cannot create a temporary directory for the build");
           return;
         }
         const std::filesystem::path dir = pattern;
         const BuildSummary b = templates::build(s->composed, Api::db(), dir);
         json files = json::array();
         for (const std::filesystem::path& p : b.written) {
           Diagnostics d;
           const auto text = read_input_file(p, p.filename().string(), d);
           if (!text) continue;
           const std::string mime = mime_of(p);
           const bool binary = mime.rfind("model/", 0) == 0;
           files.push_back({{"name", p.filename().string()},
                            {"type", mime},
                            {"bytes", text->size()},
                            {binary ? "base64" : "text", binary ? base64(*text) : *text}});
         }
         std::error_code ec;
         std::filesystem::remove_all(dir, ec);
         if (b.termination == BuildTermination::kNotBuilt) {
           reply_error(res,
                       http_status(b.diagnostics),
                       b.message.empty() ? messages_of(b.diagnostics) : b.message,
                       to_json(b.diagnostics));
           return;
         }
         reply(res,
               200,
               {{"message", b.message},
                {"termination", std::string(to_string(b.termination))},
                {"files", files},
                {"diagnostics", to_json(b.diagnostics)}});
       }});
  return api;
}

}  // namespace fabkit::server
