#include "fabkit/rods/outputs.h"

#include <fmt/format.h>

#include <cmath>

#include "fabkit/core/file_io.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/core/three_mf.h"
#include "fabkit/rods/joint_geometry.h"

namespace fabkit::rods {
namespace {

constexpr std::array<float, 4> kJointWhite{0.93f, 0.92f, 0.88f, 1.0f};
constexpr std::array<float, 4> kRodBrown{0.55f, 0.36f, 0.18f, 1.0f};
constexpr std::array<float, 4> kFindingRed{0.85f, 0.08f, 0.08f, 1.0f};

Json vec(const Vec3& v) {
  return to_json(v);
}

// The joint's angle (degrees) between a rod and the closest other rod at the same joint.
double angle_deg(const RodEnd& end) {
  return end.closest_rod < 0 ? 0.0 : std::acos(std::clamp(end.max_cosine, -1.0, 1.0)) * kRadToDeg;
}

std::string stl_name(const Structure& s, int node) {
  return fmt::format("joint_{}.stl", s.joint_label(node));
}

// Print poses laid out in rows on the plate, 5 mm apart.
std::vector<Mat4> plate_layout(const Summary& summary) {
  std::vector<Mat4> out;
  const int n = static_cast<int>(summary.joints.size());
  const int per_row = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n)))));
  double x = 0, y = 0, row_depth = 0;
  for (int k = 0; k < n; ++k) {
    const JointSolid& j = summary.joints[static_cast<std::size_t>(k)];
    const TriangleMesh posed = j.mesh.transformed(j.print_pose);
    const Vec3 lo = posed.bounds_min(), hi = posed.bounds_max();
    if (k > 0 && k % per_row == 0) {
      x = 0;
      y += row_depth + 5;
      row_depth = 0;
    }
    out.push_back(translation(x - lo.x(), y - lo.y(), 0.0) * j.print_pose);
    x += hi.x() - lo.x() + 5;
    row_depth = std::max(row_depth, hi.y() - lo.y());
  }
  return out;
}

}  // namespace

std::vector<SceneObject> scene_objects(const Design& design, const Summary& summary) {
  const Structure& s = design.structure;
  const Parameters& p = design.parameters;
  std::vector<SceneObject> out;
  const bool exact = summary.joints.size() == s.nodes.size();
  const Preview preview = exact ? Preview{} : make_preview(s, p, summary.layout);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    SceneObject o;
    o.name = s.joint_name(static_cast<int>(i));
    const Vec3& at = s.nodes[i].position;
    if (exact) {
      o.mesh = summary.joints[i].mesh;
      o.transform = translation(at.x(), at.y(), at.z());
    } else {
      o.mesh = preview.joints[i];
    }
    const bool red = i < summary.checks.red_joints.size() && summary.checks.red_joints[i];
    o.color = red ? kFindingRed : kJointWhite;
    out.push_back(std::move(o));
  }
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    if (summary.layout.rod_length[e] <= 0) continue;
    SceneObject o;
    o.name = s.rod_name(static_cast<int>(e));
    o.mesh = rod_mesh(s, p, summary.layout, static_cast<int>(e));
    const bool red = e < summary.checks.red_rods.size() && summary.checks.red_rods[e];
    o.color = red ? kFindingRed : kRodBrown;
    out.push_back(std::move(o));
  }
  return out;
}

Json assembly_json(const Design& design, const Summary& summary) {
  const Structure& s = design.structure;
  Json steps = Json::array();
  int k = 0;
  for (const AssemblyStep& step : summary.assembly) {
    Json j;
    j["step"] = ++k;
    if (step.kind == AssemblyStep::Kind::kJoint) {
      j["kind"] = "joint";
      j["joint"] = s.nodes[static_cast<std::size_t>(step.joint)].id;
      j["label"] = s.joint_label(step.joint);
    } else {
      j["kind"] = "rod";
      j["rod"] = s.rod_name(step.rod);
      j["into"] = s.nodes[static_cast<std::size_t>(step.from_joint)].id;
      j["towards"] = s.nodes[static_cast<std::size_t>(step.to_joint)].id;
      j["length_mm"] = tidy(step.rod_length);
    }
    j["text"] = step.text;
    steps.push_back(std::move(j));
  }
  Json out;
  out["fabkit"] = "rods/1";
  out["name"] = design.name;
  out["order"] =
      "depth-first from " +
      (summary.assembly.empty() ? std::string("-") : s.joint_name(summary.assembly.front().joint));
  out["steps"] = std::move(steps);
  return out;
}

Json report_json(const Design& design, const Summary& summary) {
  const Structure& s = design.structure;
  const Parameters& p = design.parameters;
  const Layout& l = summary.layout;
  Json r;
  r["fabkit"] = "rods/1";
  r["name"] = design.name;
  r["termination"] = std::string(to_string(summary.termination));
  r["message"] = summary.message;
  Json params;
  params["radius_mm"] = tidy(p.radius);
  params["profile"] =
      p.circular() ? Json(fmt::format("circle ({} sides)", p.circle_sides)) : Json(p.sides);
  params["wall_mm"] = tidy(p.wall);
  params["socket_mm"] = tidy(p.socket);
  params["tolerance_mm"] = tidy(p.tolerance);
  params["leaf_offset_mm"] = tidy(p.leaf_offset);
  params["rod_material"] = {{"name", p.rod_material.name},
                            {"density_kg_m3", p.rod_material.density},
                            {"youngs_modulus_mpa", p.rod_material.youngs_modulus},
                            {"strength_mpa", p.rod_material.strength}};
  params["joint_material"] = {{"name", p.joint_material.name},
                              {"density_kg_m3", p.joint_material.density}};
  params["stock"] = {{"length_mm", tidy(p.stock.length)},
                     {"end_padding_mm", tidy(p.stock.end_padding)},
                     {"kerf_mm", tidy(p.stock.kerf)}};
  r["parameters"] = std::move(params);

  const bool exact = summary.joints.size() == s.nodes.size();
  Json joints = Json::array();
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    Json j;
    j["id"] = s.nodes[i].id;
    j["label"] = s.joint_label(static_cast<int>(i));
    j["position_mm"] = vec(s.nodes[i].position);
    Json rods = Json::array();
    for (const RodEnd* end : l.ends_at(static_cast<int>(i))) rods.push_back(s.rod_name(end->rod));
    j["rods"] = std::move(rods);
    if (exact) {
      const JointSolid& js = summary.joints[i];
      j["file"] = stl_name(s, static_cast<int>(i));
      j["volume_mm3"] = tidy(js.volume);
      j["mass_g"] = tidy(js.volume * p.joint_material.density * 1e-6);
      j["watertight"] = js.solid.valid_solid();
      j["triangles"] = js.mesh.faces.size();
      Json pose = Json::array();
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 4; ++col) pose.push_back(tidy(js.print_pose(row, col)));
      }
      j["print_pose"] = std::move(pose);
      if (js.engraving) {
        j["engraving"] = {{"text", js.label},
                          {"position_mm", vec(js.engraving->position)},
                          {"normal", vec(js.engraving->normal)},
                          {"text_height_mm", tidy(js.text_height)},
                          {"flat_radius_mm", tidy(js.engraving->radius)},
                          {"curvature_rad", tidy(js.engraving->curvature)},
                          {"occlusion", tidy(js.engraving->occlusion)},
                          {"removed_mm3", tidy(js.engraved_volume)}};
      }
      j["build_ms"] = tidy(js.milliseconds);
    }
    for (const JointMatch& m : summary.reused) {
      if (m.node == static_cast<int>(i)) j["same_as_printed"] = m.printed + 1;
    }
    joints.push_back(std::move(j));
  }
  r["joints"] = std::move(joints);

  Json rods = Json::array();
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    Json j;
    j["name"] = s.rod_name(static_cast<int>(e));
    j["joints"] = {s.nodes[static_cast<std::size_t>(s.rods[e].a)].id,
                   s.nodes[static_cast<std::size_t>(s.rods[e].b)].id};
    j["edge_length_mm"] = tidy(l.edge_length[e]);
    j["length_mm"] = tidy(l.rod_length[e]);
    j["offsets_mm"] = {tidy(l.ends[e][0].offset), tidy(l.ends[e][1].offset)};
    j["smallest_angles_deg"] = {tidy(angle_deg(l.ends[e][0])), tidy(angle_deg(l.ends[e][1]))};
    if (e < summary.frame.rods.size() && summary.frame.solved) {
      const RodStress& st = summary.frame.rods[e];
      j["axial_n"] = tidy(st.axial);
      j["moment_nmm"] = tidy(st.moment);
      j["stress_mpa"] = tidy(st.stress);
      j["buckling_load_n"] = tidy(st.buckling_load);
      j["utilisation"] = tidy(st.utilisation);
      j["governing"] = std::string(st.governing);
    }
    j["red"] = e < summary.checks.red_rods.size() && summary.checks.red_rods[e];
    rods.push_back(std::move(j));
  }
  r["rods"] = std::move(rods);

  if (summary.cut_plan) {
    const CutPlan& c = *summary.cut_plan;
    Json cp;
    cp["stock_count"] = c.stock_count();
    cp["lower_bound"] = c.lower_bound;
    cp["sum_lower_bound"] = c.sum_lower_bound;
    cp["proven_optimal"] = c.proven_optimal;
    cp["method"] = std::string(to_string(c.method));
    cp["summary"] = c.summary;
    cp["waste_mm"] = tidy(c.waste(p.stock));
    Json stock = Json::array();
    for (const StockCut& sc : c.stock) {
      Json pieces = Json::array();
      for (const PlacedPiece& pp : sc.pieces) {
        pieces.push_back({{"rod", summary.cut_pieces[static_cast<std::size_t>(pp.piece)].label},
                          {"start_mm", tidy(pp.start)},
                          {"length_mm", tidy(pp.length)}});
      }
      stock.push_back({{"pieces", std::move(pieces)}, {"remainder_mm", tidy(sc.remainder)}});
    }
    cp["stock"] = std::move(stock);
    cp["first_fit_ms"] = tidy(c.first_fit_ms);
    cp["integer_program_ms"] = tidy(c.integer_program_ms);
    r["cut_plan"] = std::move(cp);
  }

  const Balance& b = summary.checks.balance;
  Json poly = Json::array();
  for (const auto& q : b.support_polygon) poly.push_back({tidy(q.x()), tidy(q.y())});
  Json ground = Json::array();
  for (const int i : b.ground_nodes) ground.push_back(s.nodes[static_cast<std::size_t>(i)].id);
  r["balance"] = {{"stands", b.stands},
                  {"margin_mm", tidy(b.margin)},
                  {"mass_kg", tidy(b.mass)},
                  {"center_of_mass_mm", vec(b.center_of_mass)},
                  {"ground_z_mm", tidy(b.ground_z)},
                  {"ground_joints", std::move(ground)},
                  {"support_polygon_mm", std::move(poly)}};

  const FrameResult& f = summary.frame;
  Json structure;
  structure["solved"] = f.solved;
  if (f.solved) {
    structure["max_deflection_mm"] = tidy(f.max_deflection);
    structure["max_deflection_joint"] =
        f.max_deflection_node >= 0 ? s.nodes[static_cast<std::size_t>(f.max_deflection_node)].id
                                   : 0;
    structure["max_utilisation"] = tidy(f.max_utilisation);
    structure["critical_rod"] = f.critical_rod >= 0 ? s.rod_name(f.critical_rod) : "";
    structure["total_vertical_load_n"] = tidy(f.total_load);
  }
  r["structure"] = std::move(structure);
  r["findings"] = to_json(summary.diagnostics);
  Json timings;
  for (const auto& [stage, ms] : summary.timings) timings[stage] = tidy(ms);
  r["timings_ms"] = std::move(timings);
  return r;
}

std::vector<std::filesystem::path> write_outputs(const Design& design,
                                                 const Summary& summary,
                                                 const std::filesystem::path& directory,
                                                 Diagnostics& diags) {
  std::vector<std::filesystem::path> written;
  if (!make_output_directory(directory, diags)) return written;
  const Structure& s = design.structure;
  auto note = [&](bool ok, const std::filesystem::path& path) {
    if (ok) written.push_back(path);
    return ok;
  };
  const bool exact = summary.joints.size() == s.nodes.size() && !s.nodes.empty();
  {  // every destination checked before any is written: a refusal leaves no half-written set
    std::vector<std::filesystem::path> files;
    if (exact) {
      for (const JointSolid& j : summary.joints) files.push_back(directory / stl_name(s, j.node));
      files.push_back(directory / "joints.3mf");
    }
    files.push_back(directory / "scene.glb");
    if (summary.cut_plan) {
      files.push_back(directory / "cut_plan.svg");
      files.push_back(directory / "cut_list.csv");
    }
    files.push_back(directory / "assembly.json");
    if (summary.tolerance_board) files.push_back(directory / "tolerance_board.stl");
    files.push_back(directory / "report.json");
    if (!outputs_writable(files, diags)) return written;
  }
  if (exact) {
    std::vector<ThreeMfObject> plate;
    const std::vector<Mat4> slots = plate_layout(summary);
    for (std::size_t k = 0; k < summary.joints.size(); ++k) {
      const JointSolid& j = summary.joints[k];
      const auto path = directory / stl_name(s, j.node);
      if (!note(write_stl(j.mesh.transformed(j.print_pose), path, diags), path)) return written;
      plate.push_back(ThreeMfObject{s.joint_name(j.node), j.mesh, slots[k]});
    }
    const auto path = directory / "joints.3mf";
    if (!note(write_3mf(plate, path, diags), path)) return written;
  }
  {
    const auto path = directory / "scene.glb";
    GlbOptions o;
    o.root_name = design.name.empty() ? "rods" : design.name;
    if (!note(write_glb(scene_objects(design, summary), path, diags, o), path)) return written;
  }
  if (summary.cut_plan) {
    CutPlanSvgOptions svg;
    svg.stock_width = std::max(3.0, 2 * design.parameters.radius);
    svg.label_size = std::clamp(svg.stock_width * 0.45, 2.0, 4.0);
    const auto svg_path = directory / "cut_plan.svg";
    if (!note(write_file_atomically(
                  svg_path,
                  cut_plan_svg(*summary.cut_plan, summary.cut_pieces, design.parameters.stock, svg),
                  diags),
              svg_path)) {
      return written;
    }
    const auto csv_path = directory / "cut_list.csv";
    if (!note(write_file_atomically(
                  csv_path, cut_plan_csv(*summary.cut_plan, summary.cut_pieces), diags),
              csv_path)) {
      return written;
    }
  }
  {
    const auto path = directory / "assembly.json";
    if (!note(
            write_file_atomically(path, dump_json(assembly_json(design, summary), 2) + "\n", diags),
            path)) {
      return written;
    }
  }
  if (summary.tolerance_board) {
    const auto path = directory / "tolerance_board.stl";
    if (!note(write_stl(summary.tolerance_board->mesh, path, diags), path)) return written;
  }
  {
    const auto path = directory / "report.json";
    note(write_file_atomically(path, dump_json(report_json(design, summary), 2) + "\n", diags),
         path);
  }
  return written;
}

}  // namespace fabkit::rods
