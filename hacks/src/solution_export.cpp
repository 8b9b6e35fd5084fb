#include "fabkit/hacks/solution_export.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <system_error>

#include "fabkit/core/export_formats.h"
#include "fabkit/core/file_io.h"
#include "fabkit/core/json.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/core/svg_preview.h"
#include "fabkit/hacks/diagnostic_codes.h"

namespace fabkit::hacks {
namespace {

using ordered_json = Json;

ordered_json pose_error_json(const PoseError& e) {
  return {{"pos_error_mm", tidy(e.position_mm)},
          {"rot_error_deg", tidy(e.rotation_deg)},
          {"tilt_deg", tidy(e.tilt_deg)},
          {"twist_deg", tidy(e.twist_deg)},
          {"twist_free", e.twist_free}};
}

// The parts' objects (the first part_count() of a solution scene) get their solids, each at a
// placement where it stays a solid in float32 files.
void use_solids(const Assembly& assembly,
                PartSolidCache& solids,
                std::vector<SceneObject>& scene,
                Diagnostics& diags) {
  // Warn once per part type, however many instances share its solid.
  std::vector<const PartSolid*> warned;
  for (int i = 0; i < assembly.part_count(); ++i) {
    SceneObject& object = scene[static_cast<std::size_t>(i)];
    const PartSolid& s = solids.solid(*assembly.node(PartId{i}).part);
    object.mesh = s.mesh;
    if (!s.diagnostics.empty() && std::find(warned.begin(), warned.end(), &s) == warned.end()) {
      diags.append(s.diagnostics);
      warned.push_back(&s);
    }
    if (!s.exact || s.mesh.empty()) continue;
    if (const std::optional<Mat4> safe = float32_safe_placement(s.mesh, object.transform)) {
      object.transform = *safe;
    } else {
      diags.warning(codes::kNotASolid,
                    fmt::format("{}: its solid intersects itself once its coordinates are "
                                "rounded to float32 at its pose (assembly.stl)",
                                object.name));
    }
  }
}

}  // namespace

std::string result_json(const Assembly& assembly,
                        const SolveResult& r,
                        std::string_view design_name) {
  ordered_json j;
  j["format"] = "fabkit-result/1";
  j["design"] = std::string(design_name);
  j["stable"] = r.stable;
  j["feasible"] = r.feasible;
  j["verdict"] = std::string(to_string(r.verdict()));
  j["termination"] = std::string(to_string(r.termination));
  j["message"] = r.message;
  ordered_json target = pose_error_json(r.target);
  target["step1"] = pose_error_json(r.target_step1);
  if (assembly.target()) {
    target["primitive"] = [&] {
      const auto id = assembly.find(assembly.target()->part.get());
      return id ? assembly.label(*id, assembly.target()->primitive) : std::string();
    }();
    target["goal"] = to_json(assembly.target()->frame);
  }
  j["target"] = target;
  ordered_json parts = ordered_json::array();
  for (const SolvedPart& p : r.parts) {
    parts.push_back({{"name", p.name},
                     {"type", p.type},
                     {"role", p.environment ? "environment" : (p.target ? "target" : "part")},
                     {"frame", to_json(p.frame)}});
  }
  j["parts"] = parts;
  ordered_json slipping = ordered_json::array();
  for (const Slip& s : r.slips) slipping.push_back(s.message);
  j["slipping"] = slipping;
  j["remedy"] = r.remedy;
  ordered_json params = ordered_json::array();
  for (int i = 0; i < assembly.parameter_count() && i < static_cast<int>(r.parameters.size());
       ++i) {
    const ParamInfo& p = assembly.parameters()[static_cast<std::size_t>(i)];
    params.push_back({{"primitive", assembly.label(p.part, p.primitive)},
                      {"name", p.spec.name},
                      {"value", tidy(r.parameters[static_cast<std::size_t>(i)])},
                      {"min", p.spec.lo},
                      {"max", p.spec.hi},
                      {"tag", std::string(to_string(p.spec.tag))}});
  }
  j["parameters"] = params;
  ordered_json neutral = ordered_json::array();
  for (const NeutralDirection& n : r.neutral_directions) {
    neutral.push_back({{"parameters", n.parameters}, {"description", n.description}});
  }
  ordered_json contacts = ordered_json::array();
  for (const PartContact& c : r.contacts) {
    contacts.push_back(
        {{"parts", {c.part_a, c.part_b}}, {"distance_mm", std::round(c.distance_mm * 1e4) / 1e4}});
  }
  j["contacts"] = contacts;
  j["checks"] = {{"max_connection_gap_mm", r.max_gap_mm},
                 {"max_penetration_mm", std::round(r.max_penetration_mm * 1e4) / 1e4},
                 {"max_connection_gap_deg", r.max_gap_deg},
                 {"equilibrium_residual", r.equilibrium_residual},
                 {"smallest_curvature", r.smallest_curvature},
                 {"neutral_directions", neutral},
                 {"escapes", r.escapes},
                 {"notes", r.stability_notes}};
  ordered_json timings = ordered_json::object();
  for (const StageTiming& t : r.timings)
    timings[t.stage] = std::round(t.milliseconds * 1000) / 1000;
  j["timings_ms"] = timings;
  // Names come from the user's file and may not be UTF-8: replace bad bytes, never fail.
  return dump_json(j, 2) + "\n";
}

std::vector<SceneObject> solution_scene(const Assembly& assembly, const SolveResult& r) {
  std::vector<SceneObject> out;
  const std::vector<Mat4> frames = assembly.part_frames(r.parameters);
  for (int i = 0; i < assembly.part_count(); ++i) {
    const PartNode& n = assembly.node(PartId{i});
    SceneObject o;
    o.name = assembly.label(PartId{i});
    o.mesh = n.part->mesh;
    o.transform = frames[static_cast<std::size_t>(i)];
    const bool is_target = assembly.target() && assembly.target()->part == n.part;
    if (n.environment) {
      o.color = {0.62f, 0.62f, 0.60f, 1.0f};
    } else if (is_target) {
      o.color = {0.95f, 0.55f, 0.12f, 1.0f};
    } else {
      o.color = {0.20f, 0.45f, 0.85f, 1.0f};
    }
    out.push_back(std::move(o));
  }
  for (const Slip& s : r.slips) {
    const auto [f1, f2] = assembly.connection_frames<double>(s.connection, r.parameters.data());
    SceneObject marker;
    marker.name = "slipping: " + s.message;
    marker.mesh = shapes::sphere(6.0);
    marker.transform = Mat4::Identity();
    marker.transform.topRightCorner<3, 1>() = f2.t;
    marker.color = {0.9f, 0.05f, 0.05f, 1.0f};
    out.push_back(std::move(marker));
  }
  return out;
}

std::vector<SceneObject> solid_scene(const Assembly& assembly,
                                     const SolveResult& result,
                                     PartSolidCache& solids,
                                     Diagnostics& diags) {
  std::vector<SceneObject> scene = solution_scene(assembly, result);
  use_solids(assembly, solids, scene, diags);
  scene.resize(static_cast<std::size_t>(assembly.part_count()));
  return scene;
}

TriangleMesh solution_mesh(const Assembly& assembly, const SolveResult& r) {
  TriangleMesh all;
  const std::vector<Mat4> frames = assembly.part_frames(r.parameters);
  for (int i = 0; i < assembly.part_count(); ++i) {
    all.append(
        assembly.node(PartId{i}).part->mesh.transformed(frames[static_cast<std::size_t>(i)]));
  }
  return all;
}

bool export_solution(const Assembly& assembly,
                     const SolveResult& result,
                     const std::filesystem::path& directory,
                     Diagnostics& diags,
                     const ExportOptions& options) {
  if (!make_output_directory(directory, diags)) return false;
  const std::array<std::filesystem::path, 5> files{directory / "result.json",
                                                   directory / "scene.glb",
                                                   directory / "preview.svg",
                                                   directory / (options.basename + ".stl"),
                                                   directory / (options.basename + ".obj")};
  if (!outputs_writable(files, diags)) return false;  // none written rather than some
  bool ok =
      write_file_atomically(files[0], result_json(assembly, result, options.design_name), diags);
  // The pictures show what slips (red markers); the files to build from hold the parts only.
  PartSolidCache local;
  std::vector<SceneObject> scene = solution_scene(assembly, result);
  use_solids(assembly, options.solids ? *options.solids : local, scene, diags);
  const std::vector<SceneObject> parts(scene.begin(), scene.begin() + assembly.part_count());
  ok = write_scene("glb", scene, files[1], diags) && ok;
  ok = write_scene("svg", scene, files[2], diags) && ok;
  ok = write_scene("stl", parts, files[3], diags) && ok;
  ok = write_scene("obj", parts, files[4], diags) && ok;
  return ok;
}

}  // namespace fabkit::hacks
