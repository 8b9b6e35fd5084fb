// build(): nest the cut pieces, write SVG/DXF sheets, the 3D model and report.json.
#include "fabkit/flatpack/build.h"

#include <fmt/format.h>

#include <chrono>

#include "fabkit/core/dxf.h"
#include "fabkit/core/file_io.h"
#include "fabkit/core/gltf.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/flatpack/diagnostic_codes.h"

namespace fabkit::flatpack {

std::string_view to_string(Termination t) {
  switch (t) {
    case Termination::kBuilt:
      return "built";
    case Termination::kInvalid:
      return "invalid";
    case Termination::kNotNested:
      return "not-nested";
    case Termination::kWriteFailed:
      return "write-failed";
    case Termination::kTimeout:
      return "timeout";
  }
  return "built";
}

std::vector<CutSheet> cut_sheets(const Analysis& analysis,
                                 const NestingResult& nesting,
                                 const NestingOptions& sheet,
                                 const LabelOptions& labels) {
  std::vector<CutSheet> sheets(static_cast<std::size_t>(nesting.sheet_count));
  for (std::size_t s = 0; s < sheets.size(); ++s) {
    sheets[s].name = fmt::format("{} — sheet {} of {}",
                                 analysis.name.empty() ? "design" : analysis.name,
                                 s + 1,
                                 sheets.size());
    sheets[s].width_mm = sheet.sheet_width_mm;
    sheets[s].height_mm = sheet.sheet_height_mm;
  }
  double max_t = 0;
  for (const Piece& p : analysis.pieces) max_t = std::max(max_t, p.material.thickness_mm);
  const double label_h = labels.height_mm > 0 ? labels.height_mm : std::max(3.0, 1.5 * max_t);
  for (std::size_t i = 0; i < analysis.pieces.size() && i < nesting.placements.size(); ++i) {
    const NestedPlacement& np = nesting.placements[i];
    if (np.sheet < 0) continue;
    const Piece& piece = analysis.pieces[i];
    CutSheet& s = sheets[static_cast<std::size_t>(np.sheet)];
    for (const Polygon2d& poly : piece.cut) s.add_cut(placed(poly, np));
    auto to_sheet = [&](const Vec2& p) {
      return transformed(Ring{p}, np.rotation_deg, np.translation)[0];
    };
    if (labels.piece_names && !piece.cut.empty()) {
      s.labels.push_back({piece.name, to_sheet(interior_point(piece.cut[0])), label_h, 0});
    }
    if (labels.assembly_marks) {
      for (const Piece::Mark& m : piece.marks) {
        double r = m.rotation_deg + np.rotation_deg;
        while (r > 90) r -= 180;
        while (r <= -90) r += 180;
        s.labels.push_back({"→ " + m.text, to_sheet(m.position), label_h * 0.7, r});
      }
    }
  }
  return sheets;
}

CutSheet for_dxf(CutSheet sheet) {
  for (SheetLabel& label : sheet.labels) {
    const std::string& in = label.text;
    std::string out;
    for (std::size_t i = 0; i < in.size();) {
      const auto c = static_cast<unsigned char>(in[i]);
      int n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
      if (n == 0 || i + static_cast<std::size_t>(n) > in.size()) {
        out += '?';  // not UTF-8 (labels are piece names, checked when read)
        ++i;
        continue;
      }
      if (n == 1) {
        out += in[i++];
        continue;
      }
      unsigned code = c & (0x7Fu >> n);
      for (int k = 1; k < n; ++k)
        code = (code << 6) | (static_cast<unsigned char>(in[i + k]) & 0x3Fu);
      out += code <= 0xFFFF ? fmt::format("\\U+{:04X}", code) : std::string("?");
      i += static_cast<std::size_t>(n);
    }
    label.text = std::move(out);
  }
  return sheet;
}

std::vector<TriangleMesh> piece_meshes(const Analysis& analysis) {
  std::vector<TriangleMesh> out;
  for (const Piece& p : analysis.pieces) {
    TriangleMesh m;
    const double h = p.material.thickness_mm / 2;
    for (const Polygon2d& poly : p.cut) m.append(extrude(poly, -h, h));
    m.transform(p.frame);
    out.push_back(std::move(m));
  }
  return out;
}

namespace {

Json vec(const Vec3& v) {
  return Json::array({std::round(v.x() * 1e4) / 1e4 + 0.0,
                      std::round(v.y() * 1e4) / 1e4 + 0.0,
                      std::round(v.z() * 1e4) / 1e4 + 0.0});
}

}  // namespace

Json report_json(const BuildSummary& summary) {
  const Analysis& a = summary.analysis;
  Json j;
  j["fabkit"] = "flatpack/1";
  j["name"] = a.name;
  j["termination"] = std::string(to_string(summary.termination));
  Json counts;
  counts["components"] = a.components.size();
  counts["pieces"] = a.pieces.size();
  counts["joints"] = a.graph_joints();
  counts["joints_from_connections"] = a.user_connection_joints();
  counts["automatic_joints"] = a.automatic_joints();
  counts["merges"] = a.merging_connections.size();
  counts["cut_joints"] = a.joints.size();
  Json by_kind;
  for (JointKind k : {JointKind::kFingerFinger, JointKind::kFingerHole, JointKind::kSlotSlot})
    by_kind[std::string(to_string(k))] = a.joints_of(k);
  counts["cut_joints_by_kind"] = by_kind;
  counts["dimensions"] = a.dimension_count;
  j["counts"] = counts;
  Json meta = Json::array();
  for (const std::string& m : a.meta_parameters) {
    const auto it = a.meta_drives.find(m);  // absent: cut by the deadline, null
    const auto value = a.values.find(m);
    meta.push_back({{"name", m},
                    {"value", value == a.values.end() ? 0.0 : value->second},
                    {"drives", it == a.meta_drives.end() ? Json() : Json(it->second)}});
  }
  j["meta_parameters"] = meta;
  Json values = Json::object();
  for (const auto& [k, v] : a.values) values[k] = std::round(v * 1e6) / 1e6 + 0.0;
  j["values"] = values;
  Json pieces = Json::array();
  for (std::size_t i = 0; i < a.pieces.size(); ++i) {
    const Piece& p = a.pieces[i];
    Json pj;
    pj["name"] = p.name;
    Json comps = Json::array();
    for (int c : p.components) comps.push_back(a.components[static_cast<std::size_t>(c)].name);
    pj["components"] = comps;
    pj["material"] = p.material.name;
    pj["thickness_mm"] = p.material.thickness_mm;
    const Box2d box = bounds(p.cut);
    pj["size_mm"] = Json::array(
        {std::round(box.size().x() * 100) / 100, std::round(box.size().y() * 100) / 100});
    pj["area_mm2"] = std::round(area(p.cut) * 10) / 10;
    pj["origin"] = vec(p.frame.topRightCorner<3, 1>());
    pj["normal"] = vec(p.frame.block<3, 1>(0, 2));
    if (i < summary.nesting.placements.size()) {
      const NestedPlacement& np = summary.nesting.placements[i];
      pj["sheet"] = np.sheet + 1;
      pj["sheet_position_mm"] = Json::array(
          {std::round(np.translation.x() * 100) / 100, std::round(np.translation.y() * 100) / 100});
      pj["sheet_rotation_deg"] = np.rotation_deg;
    }
    pieces.push_back(pj);
  }
  j["pieces"] = pieces;
  Json joints = Json::array();
  for (const Joint& jt : a.joints) {
    Json jj;
    jj["id"] = jt.id;
    jj["kind"] = std::string(to_string(jt.kind));
    jj["pieces"] = Json::array({a.pieces[static_cast<std::size_t>(jt.piece_a)].name,
                                a.pieces[static_cast<std::size_t>(jt.piece_b)].name});
    jj["automatic"] = jt.automatic();
    jj["length_mm"] = std::round(jt.length_mm * 100) / 100;
    jj["angle_deg"] = std::round(jt.angle_deg * 100) / 100;
    jj["fingers"] = jt.fingers;
    jj["finger_width_mm"] = std::round(jt.finger_width_mm * 1000) / 1000;
    jj["start"] = vec(jt.start);
    jj["end"] = vec(jt.end);
    joints.push_back(jj);
  }
  j["joints"] = joints;
  Json order = Json::array();
  for (const AssemblyStep& s : a.assembly) {
    order.push_back({{"piece", a.pieces[static_cast<std::size_t>(s.piece)].name},
                     {"direction", vec(s.direction)}});
  }
  j["assembly_order"] = order;
  Json stuck = Json::array();
  for (int p : a.not_insertable) stuck.push_back(a.pieces[static_cast<std::size_t>(p)].name);
  j["not_insertable"] = stuck;
  Json sheets;
  sheets["count"] = summary.nesting.sheet_count;
  sheets["utilisation"] = std::round(summary.nesting.utilisation * 1e4) / 1e4;
  Json per = Json::array();
  for (double u : summary.nesting.sheet_utilisation) per.push_back(std::round(u * 1e4) / 1e4);
  sheets["per_sheet"] = per;
  j["sheets"] = sheets;
  Json timings = Json::object();
  for (const StageTiming& t : summary.timings)
    timings[t.stage] = std::round(t.milliseconds * 1000) / 1000;
  j["timings_ms"] = timings;
  j["diagnostics"] = to_json(summary.diagnostics);
  return j;
}

BuildSummary build(const Design& design, const BuildOptions& options) {
  BuildSummary s;
  CheckOptions co = options.check;
  if (!co.deadline) co.deadline = options.deadline;
  s.analysis = check(design, co);
  s.timings = s.analysis.timings;
  s.diagnostics.append(s.analysis.diagnostics);
  // The deadline first: a check it stopped may not have placed the pieces yet.
  if (s.analysis.diagnostics.has_errors_of(DiagnosticClass::kTimeout)) {
    s.termination = Termination::kTimeout;  // nothing nested, nothing written
    return s;
  }
  if (!s.analysis.placed) {
    s.termination = Termination::kInvalid;
    return s;
  }
  auto t0 = std::chrono::steady_clock::now();
  auto lap = [&](std::string stage) {
    const auto now = std::chrono::steady_clock::now();
    s.timings.push_back(
        {std::move(stage), std::chrono::duration<double, std::milli>(now - t0).count()});
    t0 = now;
  };
  NestingOptions sheet = options.sheet.value_or(design.sheet);
  if (options.deadline) sheet.deadline = options.deadline;
  std::vector<Polygon2d> shapes;
  std::vector<std::string> names;
  for (const Piece& p : s.analysis.pieces) {
    shapes.push_back(p.cut.empty() ? Polygon2d{} : p.cut[0]);
    names.push_back(p.name);
  }
  s.nesting = nest(shapes, names, sheet);
  s.diagnostics.append(s.nesting.diagnostics);
  lap("nest");
  if (s.nesting.diagnostics.has_errors()) {
    s.termination = s.nesting.diagnostics.has_errors_of(DiagnosticClass::kTimeout)
                        ? Termination::kTimeout
                        : Termination::kNotNested;
  }
  // Sheets missing the pieces not yet nested would be cut as they are: nothing is written.
  if (s.termination == Termination::kTimeout) return s;

  Diagnostics io;
  if (!make_output_directory(options.output_dir, io)) {
    s.diagnostics.append(io);
    s.termination = Termination::kWriteFailed;
    return s;
  }
  auto wrote = [&](const std::filesystem::path& p, bool ok) {
    if (ok) s.files.push_back(p);
  };
  const std::vector<CutSheet> sheets = cut_sheets(s.analysis, s.nesting, sheet, design.labels);
  const std::filesystem::path& dir = options.output_dir;
  auto sheet_file = [&](std::size_t k, const char* ext) {
    return dir / fmt::format("sheet-{}.{}", k + 1, ext);
  };
  const std::filesystem::path stl_file = dir / "model.stl", glb_file = dir / "scene.glb",
                              report = dir / "report.json";
  {  // every destination checked before any is written: a refusal leaves no half-written set
    std::vector<std::filesystem::path> files;
    for (std::size_t k = 0; k < sheets.size(); ++k) {
      if (options.svg) files.push_back(sheet_file(k, "svg"));
      if (options.dxf) files.push_back(sheet_file(k, "dxf"));
    }
    if (options.stl) files.push_back(stl_file);
    if (options.glb) files.push_back(glb_file);
    files.push_back(report);
    if (!outputs_writable(files, io)) {
      s.diagnostics.append(io);
      s.termination = Termination::kWriteFailed;
      return s;
    }
  }
  for (std::size_t k = 0; k < sheets.size(); ++k) {
    if (options.svg)
      wrote(sheet_file(k, "svg"), write_svg_sheet(sheet_file(k, "svg"), sheets[k], io));
    if (options.dxf)
      wrote(sheet_file(k, "dxf"), write_dxf(sheet_file(k, "dxf"), for_dxf(sheets[k]), io));
  }
  const std::vector<TriangleMesh> meshes = piece_meshes(s.analysis);
  if (options.stl) {
    TriangleMesh all;
    for (const TriangleMesh& m : meshes) all.append(m);
    wrote(stl_file, write_stl(all, stl_file, io));
  }
  if (options.glb) {
    std::vector<SceneObject> objects;
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      const float shade = 0.55f + 0.35f * static_cast<float>(k % 4) / 3.0f;
      objects.push_back({s.analysis.pieces[k].name,
                         meshes[k],
                         Mat4::Identity(),
                         {0.85f * shade, 0.68f * shade, 0.45f * shade, 1.0f}});
    }
    GlbOptions g;
    g.root_name = design.name.empty() ? "flatpack" : design.name;
    wrote(glb_file, write_glb(objects, glb_file, io, g));
  }
  lap("write");
  s.diagnostics.append(io);
  if (io.has_errors()) s.termination = Termination::kWriteFailed;
  Diagnostics rio;
  if (write_file_atomically(report, dump_json(report_json(s), 2) + "\n", rio)) {
    s.files.push_back(report);
  } else {
    s.diagnostics.append(rio);
    s.termination = Termination::kWriteFailed;
  }
  return s;
}

}  // namespace fabkit::flatpack
