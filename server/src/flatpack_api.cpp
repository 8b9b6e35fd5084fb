// The flatpack kit's API for the editor's Flat-pack workspace: the component registry, the
// assembled model of a posted design (pieces with their joints cut, joints, diagnostics with the
// pieces they concern, nested sheets) and its build outputs as downloads.
#include "kit_api.h"

// clang-format off
#include "fabkit/flatpack/build.h"
#include "fabkit/flatpack/check.h"
#include "fabkit/flatpack/component.h"
#include "fabkit/flatpack/design_file.h"
#include "fabkit/flatpack/diagnostic_codes.h"
#include "fabkit/core/file_io.h"
// clang-format on

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace fabkit::server {
namespace {

using json = Json;
using namespace fabkit::flatpack;

/// Unconnected groups are laid this far apart (mm) while a design is being put together.
constexpr double kGroupGap = 40;

Vec3 apply(const Mat4& m, const Vec3& p) {
  return (m * Eigen::Vector4d(p.x(), p.y(), p.z(), 1)).head<3>();
}

double r4(double v) {
  return std::round(v * 1e4) / 1e4 + 0.0;
}

json point(const Vec3& v) {
  return json::array({r4(v.x()), r4(v.y()), r4(v.z())});
}

json bound(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

json material_json(const Material& m) {
  return {{"name", m.name},
          {"thickness", m.thickness_mm},
          {"kerf", m.kerf_mm},
          {"interference", m.interference_mm}};
}

// Column-major, as three.js's Matrix4.fromArray reads it.
json matrix_json(const Mat4& m) {
  json out = json::array();
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) out.push_back(r4(m(row, col)));
  return out;
}

json ring_json(const Ring& ring) {
  json out = json::array();
  for (const Vec2& p : ring) out.push_back(json::array({r4(p.x()), r4(p.y())}));
  return out;
}

// A posted design: never `uses:` (that would read files), capped in size.
Design load(const ApiContext& context, const std::string& body, Diagnostics& diags) {
  DesignFileOptions o;
  o.allow_uses = false;
  o.max_depth = 1;
  (void)context;
  return load_design_text(body, "design.yaml", diags, {}, o);
}

CheckOptions check_options(const ApiContext& context) {
  CheckOptions o;
  o.max_components = context.options->max_parts;
  o.separate_groups_mm = kGroupGap;
  return o;
}

// The names of the components a diagnostic concerns: those it names, and those of the file
// line it points at (a component's or a connection's line).
json concerns(const Diagnostic& d,
              const Design& design,
              const Analysis& a,
              const std::map<std::string, std::string>& piece_of) {
  std::set<std::string> names;
  // A cycle that does not close concerns the component its two placements disagree on.
  if (d.code == flatpack::codes::kCycleMismatch) {
    for (const CycleResidual& r : a.residuals) {
      const auto k = static_cast<std::size_t>(r.connection);
      if (!r.closes && k < design.connections.size() &&
          design.connections[k].where.line == d.where.line && piece_of.count(r.component))
        names.insert(piece_of.at(r.component));
    }
    if (!names.empty()) return json(std::vector<std::string>(names.begin(), names.end()));
  }
  std::string token;
  auto flush = [&] {
    if (piece_of.count(token)) names.insert(piece_of.at(token));
    // "A.t" names A's edge: A.
    const auto dot = token.rfind('.');
    if (dot != std::string::npos && piece_of.count(token.substr(0, dot)))
      names.insert(piece_of.at(token.substr(0, dot)));
    token.clear();
  };
  // "not connected to A: B, C" concerns the stray ones, not the first component.
  std::string_view text = d.message;
  if (d.code == flatpack::codes::kNotConnected && text.find(": ") != std::string_view::npos)
    text = text.substr(text.find(": ") + 2);
  for (char c : text) {
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.') {
      token += c;
    } else {
      flush();
    }
  }
  flush();
  if (d.where.line > 0) {
    for (const ComponentUse& c : design.components) {
      if (c.where.line == d.where.line && piece_of.count(c.name)) names.insert(piece_of.at(c.name));
    }
    for (const Connection& c : design.connections) {
      if (c.where.line != d.where.line) continue;
      for (const std::string& n : {c.a_component, c.b_component}) {
        if (piece_of.count(n)) names.insert(piece_of.at(n));
      }
    }
  }
  return json(std::vector<std::string>(names.begin(), names.end()));
}

json assemble_json(const Design& design,
                   const Analysis& a,
                   const NestingResult* nesting,
                   const NestingOptions& sheet) {
  json out;
  out["name"] = design.name;
  out["placed"] = a.placed;
  json values = json::object();
  for (const auto& [k, v] : a.values) values[k] = r4(v);
  out["values"] = values;
  json meta = json::array();
  for (const std::string& m : a.meta_parameters) {
    const auto it = a.meta_drives.find(m);  // absent: cut by the deadline, null
    meta.push_back(
        {{"name", m}, {"drives", it == a.meta_drives.end() ? json() : json(it->second)}});
  }
  out["meta"] = meta;

  // Component and piece names → the piece's name (what the view and the lists key on).
  std::map<std::string, std::string> piece_of;
  json components = json::array();
  for (const PlacedComponent& c : a.components) {
    const std::string piece = c.piece >= 0 && c.piece < static_cast<int>(a.pieces.size())
                                  ? a.pieces[static_cast<std::size_t>(c.piece)].name
                                  : c.name;
    piece_of[c.name] = piece;
    json edges = json::array();
    const Ring& outer = c.shape.polygon.outer;
    for (const NamedEdge& e : c.shape.edges) {
      if (e.vertex < 0 || e.vertex >= static_cast<int>(outer.size())) continue;
      const Vec2& p = outer[static_cast<std::size_t>(e.vertex)];
      const Vec2& q = outer[(static_cast<std::size_t>(e.vertex) + 1) % outer.size()];
      edges.push_back({{"name", e.name},
                       {"start", point(apply(c.frame, Vec3(p.x(), p.y(), 0)))},
                       {"end", point(apply(c.frame, Vec3(q.x(), q.y(), 0)))}});
    }
    json vals = json::object();
    for (const auto& [k, v] : c.values) vals[k] = r4(v);
    const json frame = matrix_json(c.frame);
    components.push_back({{"name", c.name},
                          {"type", c.type},
                          {"frame", frame},
                          {"outline", ring_json(c.shape.polygon.outer)},
                          {"piece", piece},
                          {"values", vals},
                          {"material", material_json(c.material)},
                          {"normal", point(c.frame.block<3, 1>(0, 2))},
                          {"edges", edges}});
  }
  out["components"] = components;

  json pieces = json::array();
  if (a.placed) {
    const std::vector<TriangleMesh> meshes = piece_meshes(a);
    for (std::size_t i = 0; i < a.pieces.size(); ++i) {
      const Piece& p = a.pieces[i];
      piece_of[p.name] = p.name;
      json comps = json::array();
      for (int c : p.components) comps.push_back(a.components[static_cast<std::size_t>(c)].name);
      const Box2d box = bounds(p.cut);
      const TriangleMesh& m = meshes[i];
      Vec3 centre = Vec3::Zero();
      for (const Vec3& v : m.vertices) centre += v;
      if (!m.vertices.empty()) centre /= static_cast<double>(m.vertices.size());
      json pj = {{"name", p.name},
                 {"components", comps},
                 {"material", material_json(p.material)},
                 {"size_mm", json::array({r4(box.size().x()), r4(box.size().y())})},
                 {"area_mm2", std::round(area(p.cut) * 10) / 10},
                 {"centre", point(centre)},
                 {"normal", point(p.frame.block<3, 1>(0, 2))},
                 {"mesh", to_json(m)}};
      if (nesting && i < nesting->placements.size()) pj["sheet"] = nesting->placements[i].sheet + 1;
      pieces.push_back(pj);
    }
  }
  out["pieces"] = pieces;

  json joints = json::array();
  for (const Joint& j : a.joints) {
    joints.push_back({{"id", j.id},
                      {"kind", std::string(to_string(j.kind))},
                      {"pieces",
                       json::array({a.pieces[static_cast<std::size_t>(j.piece_a)].name,
                                    a.pieces[static_cast<std::size_t>(j.piece_b)].name})},
                      {"automatic", j.automatic()},
                      {"connection", j.connection},
                      {"start", point(j.start)},
                      {"end", point(j.end)},
                      {"length_mm", r4(j.length_mm)},
                      {"angle_deg", r4(j.angle_deg)},
                      {"fingers", j.fingers},
                      {"finger_width_mm", r4(j.finger_width_mm)}});
  }
  out["joints"] = joints;
  json merges = json::array();
  for (int c : a.merging_connections) merges.push_back(c);
  out["merging_connections"] = merges;
  json residuals = json::array();
  for (const CycleResidual& r : a.residuals) {
    residuals.push_back(
        {{"connection", r.connection},
         {"name", r.name},
         {"component", r.component},
         {"piece", piece_of.count(r.component) ? piece_of.at(r.component) : r.component},
         {"position_mm", r4(r.position_mm)},
         {"angle_deg", r4(r.angle_deg)},
         {"closes", r.closes},
         {"frame", matrix_json(r.frame)}});
  }
  out["residuals"] = residuals;
  json order = json::array();
  for (const AssemblyStep& s : a.assembly) {
    order.push_back({{"piece", a.pieces[static_cast<std::size_t>(s.piece)].name},
                     {"direction", point(s.direction)},
                     {"group", s.group}});
  }
  out["assembly_order"] = order;

  json diags = json::array();
  auto add_diags = [&](const Diagnostics& ds) {
    for (const Diagnostic& d : ds) {
      json dj = to_json(d);
      dj["pieces"] = concerns(d, design, a, piece_of);
      diags.push_back(dj);
    }
  };
  add_diags(a.diagnostics);

  json sheets = {{"count", 0},
                 {"width", sheet.sheet_width_mm},
                 {"height", sheet.sheet_height_mm},
                 {"utilisation", 0},
                 {"list", json::array()}};
  if (nesting) {
    add_diags(nesting->diagnostics);
    sheets["count"] = nesting->sheet_count;
    sheets["utilisation"] = r4(nesting->utilisation);
    const std::vector<CutSheet> cut = cut_sheets(a, *nesting, sheet, design.labels);
    json list = json::array();
    for (int s = 0; s < nesting->sheet_count; ++s) {
      json sj;
      sj["utilisation"] = s < static_cast<int>(nesting->sheet_utilisation.size())
                              ? r4(nesting->sheet_utilisation[static_cast<std::size_t>(s)])
                              : 0.0;
      json sp = json::array();
      for (std::size_t i = 0; i < a.pieces.size() && i < nesting->placements.size(); ++i) {
        const NestedPlacement& np = nesting->placements[i];
        if (np.sheet != s) continue;
        json rings = json::array();
        for (const Polygon2d& poly : a.pieces[i].cut) {
          const Polygon2d q = placed(poly, np);
          rings.push_back(ring_json(q.outer));
          for (const Ring& h : q.holes) rings.push_back(ring_json(h));
        }
        sp.push_back(
            {{"piece", a.pieces[i].name}, {"rotation_deg", np.rotation_deg}, {"rings", rings}});
      }
      sj["pieces"] = sp;
      json labels = json::array();
      if (s < static_cast<int>(cut.size())) {
        for (const SheetLabel& l : cut[static_cast<std::size_t>(s)].labels) {
          labels.push_back({{"text", l.text},
                            {"at", json::array({r4(l.position.x()), r4(l.position.y())})},
                            {"height", r4(l.height_mm)},
                            {"rotation", r4(l.rotation_deg)}});
        }
      }
      sj["labels"] = labels;
      list.push_back(sj);
    }
    sheets["list"] = list;
  }
  out["sheets"] = sheets;
  out["diagnostics"] = diags;
  json timings = json::object();
  for (const StageTiming& t : a.timings) timings[t.stage] = r4(t.milliseconds);
  if (nesting) timings["nest"] = r4(nesting->milliseconds);
  out["timings_ms"] = timings;
  return out;
}

// A fresh directory under the system's temporary directory, removed when it goes out of scope.
class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "fabkit-flatpack-XXXXXX");
    if (mkdtemp(pattern.data()) != nullptr) path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::string content_type(const std::string& file) {
  const auto ends = [&](std::string_view s) { return file.ends_with(s); };
  if (ends(".svg")) return "image/svg+xml";
  if (ends(".dxf")) return "application/dxf";
  if (ends(".stl")) return "model/stl";
  if (ends(".glb")) return "model/gltf-binary";
  return "application/json";
}

}  // namespace

KitApi flatpack_api(const ApiContext& context) {
  KitApi api;
  api.kit = "flatpack";
  using M = ApiRoute::Method;

  // The component registry: each type's parameter schema, its own constraints and its edges.
  api.routes.push_back({M::kGet, "components", [](const httplib::Request&, httplib::Response& res) {
                          const ComponentLibrary& lib = ComponentLibrary::builtin();
                          json types = json::array();
                          for (const std::string& name : lib.names()) {
                            const ComponentType* t = lib.find(name);
                            json params = json::array();
                            for (const ParamSpec& p : t->params) {
                              params.push_back(
                                  {{"name", p.name},
                                   {"kind", std::string(to_string(p.kind))},
                                   {"description", p.description},
                                   {"default", p.default_value ? json(*p.default_value) : json()},
                                   {"min", bound(p.min)},
                                   {"exclusive_min", p.exclusive_min},
                                   {"max", bound(p.max)}});
                            }
                            json own = json::array();
                            for (const auto& [l, r] : t->constraints) own.push_back(l + " = " + r);
                            types.push_back({{"name", t->name},
                                             {"description", t->description},
                                             {"params", params},
                                             {"constraints", own},
                                             {"edges", t->edge_names},
                                             {"takes_points", t->takes_points}});
                          }
                          reply(res, 200, types);
                        }});

  // The assembled model of a posted design (YAML): 400 when it cannot be read; otherwise 200
  // with `placed` saying whether placement succeeded and every diagnostic, each with the pieces
  // it concerns.
  api.routes.push_back(
      {M::kPost, "assemble", [context](const httplib::Request& req, httplib::Response& res) {
         const auto deadline = context.deadline();
         Diagnostics read;
         const Design design = load(context, req.body, read);
         if (read.has_errors()) {
           reply_error(res, 400, messages_of(read), to_json(read));
           return;
         }
         const Analysis a = check(design, check_options(context));
         NestingOptions sheet = design.sheet;
         sheet.deadline = deadline;
         std::optional<NestingResult> nesting;
         if (a.placed) {
           std::vector<Polygon2d> shapes;
           std::vector<std::string> names;
           for (const Piece& p : a.pieces) {
             shapes.push_back(p.cut.empty() ? Polygon2d{} : p.cut[0]);
             names.push_back(p.name);
           }
           nesting = nest(shapes, names, sheet);
         }
         json out = assemble_json(design, a, nesting ? &*nesting : nullptr, sheet);
         Json reading = to_json(read);  // warnings of the reader
         for (Json& d : reading) {
           d["pieces"] = json::array();
           out["diagnostics"].push_back(d);
         }
         reply(res, 200, out);
       }});

  // The build outputs of a posted design, one file per request: ?file=sheet-N.svg, sheet-N.dxf,
  // model.stl, scene.glb or report.json. Built into a scratch directory the server makes; the
  // request only chooses among the files the build wrote.
  api.routes.push_back(
      {M::kPost, "build", [context](const httplib::Request& req, httplib::Response& res) {
         const std::string wanted = req.has_param("file") ? req.get_param_value("file") : "";
         Diagnostics read;
         const Design design = load(context, req.body, read);
         if (read.has_errors()) {
           reply_error(res, 400, messages_of(read), to_json(read));
           return;
         }
         ScratchDir dir;
         if (dir.path().empty()) {
           reply_error(res, 500, "cannot make a scratch directory for the build");
           return;
         }
         BuildOptions o;
         o.check = check_options(context);
         o.check.separate_groups_mm = kGroupGap;
         o.output_dir = dir.path() / "out";
         o.deadline = context.deadline();
         const BuildSummary s = build(design, o);
         if (s.termination == Termination::kInvalid || s.termination == Termination::kTimeout ||
             s.termination == Termination::kWriteFailed) {
           reply_error(res,
                       http_status(s.diagnostics),
                       fmt::format("the design could not be built ({}): {}",
                                   to_string(s.termination),
                                   messages_of(s.diagnostics)),
                       to_json(s.diagnostics));
           return;
         }
         std::vector<std::string> names;
         for (const std::filesystem::path& f : s.files) {
           names.push_back(f.filename().string());
           if (f.filename().string() != wanted) continue;
           std::ifstream in(f, std::ios::binary);
           std::ostringstream bytes;
           bytes << in.rdbuf();
           res.set_header("Content-Disposition",
                          fmt::format("attachment; filename=\"{}\"", wanted));
           res.set_content(bytes.str(), content_type(wanted));
           return;
         }
         reply_error(
             res,
             400,
             fmt::format(
                 "the build has no file '{}'; it wrote {}", wanted, fmt::join(names, ", ")));
       }});
  return api;
}

}  // namespace fabkit::server
