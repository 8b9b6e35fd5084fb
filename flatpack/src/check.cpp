// check(): solve, place, detect, cut, plan — each stage timed.
#include "fabkit/flatpack/check.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <set>
#include <type_traits>

#include "fabkit/core/yaml_reader.h"
#include "fabkit/flatpack/diagnostic_codes.h"
#include "flat_design.h"
#include "geometry.h"

namespace fabkit::flatpack {

std::string_view to_string(JointKind kind) {
  switch (kind) {
    case JointKind::kFingerFinger:
      return "finger-finger";
    case JointKind::kFingerHole:
      return "finger-hole";
    case JointKind::kSlotSlot:
      return "slot-slot";
  }
  return "finger-finger";
}

int Analysis::user_connection_joints() const {
  std::set<int> made(merging_connections.begin(), merging_connections.end());
  for (const Joint& j : joints) {
    if (j.connection >= 0) made.insert(j.connection);
  }
  return static_cast<int>(made.size());
}

int Analysis::automatic_joints() const {
  int n = 0;
  for (const Joint& j : joints) n += j.automatic() ? 1 : 0;
  return n;
}

int Analysis::joints_of(JointKind kind) const {
  int n = 0;
  for (const Joint& j : joints) n += j.kind == kind ? 1 : 0;
  return n;
}

namespace {

class Stopwatch {
 public:
  explicit Stopwatch(std::vector<StageTiming>& out) : out_(out) {}
  void lap(std::string stage) {
    const auto now = std::chrono::steady_clock::now();
    out_.push_back(
        {std::move(stage), std::chrono::duration<double, std::milli>(now - last_).count()});
    last_ = now;
  }

 private:
  std::vector<StageTiming>& out_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

Analysis check(const Design& design, const CheckOptions& options) {
  Analysis a;
  a.name = design.name;
  Stopwatch clock(a.timings);
  // Checked between steps of a fraction of a millisecond each (a meta-parameter's re-solve, a
  // component's shape), so a deadline of a few milliseconds holds.
  // `stage` is text or a function making it, called only once the deadline has passed.
  auto stopped_after = [&](const auto& stage, const char* left) {
    if (!options.deadline || std::chrono::steady_clock::now() <= *options.deadline) return false;
    std::string done;
    if constexpr (std::is_invocable_v<decltype(stage)>) {
      done = stage();
    } else {
      done = stage;
    }
    a.diagnostics.error(codes::kTimeLimit,
                        fmt::format("stopped at the deadline after {}; {} not done", done, left));
    return true;
  };
  detail::FlatDesign flat;
  if (!detail::flatten(design, flat, a.diagnostics, options.max_components)) return a;
  if (flat.components.empty()) {
    a.diagnostics.error(codes::kMalformedInput, "the design has no components");
    return a;
  }
  std::vector<double> values(flat.quantities.size(), 0.0);
  detail::Expressions ex(flat, values);
  if (!detail::solve_quantities(flat, ex, values, a.diagnostics, options.deadline)) return a;
  if (stopped_after("solving the dimensions",
                    "what the meta-parameters drive, the shapes, placement, joints and the "
                    "assembly order were")) {
    return a;
  }
  for (std::size_t q = 0; q < flat.quantities.size(); ++q) {
    a.values[flat.quantities[q].name] = values[q];
    if (flat.quantities[q].meta) a.meta_parameters.push_back(flat.quantities[q].name);
    if (flat.quantities[q].component >= 0) ++a.dimension_count;
  }
  // What each meta-parameter drives: solve again with it changed and see which dimensions move.
  const std::vector<double> solved_values = values;
  int metas_done = 0;
  for (std::size_t q = 0; q < flat.quantities.size(); ++q) {
    if (!flat.quantities[q].meta) continue;
    if (stopped_after(
            [&] {
              return fmt::format("solving the dimensions and the effects of {} meta-parameter{}",
                                 metas_done,
                                 metas_done == 1 ? "" : "s");
            },
            "the remaining meta-parameters' effects, the shapes, placement, joints "
            "and the assembly order were")) {
      return a;
    }
    ++metas_done;
    detail::FlatDesign moved = flat;
    const double v = values[q];
    moved.quantities[q].default_value = flat.quantities[q].kind == ParamKind::kCount
                                            ? v + 1
                                            : v + std::max(1.0, 0.05 * std::abs(v));
    // Solved in the same value slots, so the expressions compiled above are reused; the
    // design's own values are put back afterwards.
    Diagnostics ignored;  // a change that breaks the design drives what it broke: nothing listed
    std::vector<std::string>& drives = a.meta_drives[flat.quantities[q].name];
    const bool solved = detail::solve_quantities(moved, ex, values, ignored);
    for (std::size_t k = 0; solved && k < flat.quantities.size(); ++k) {
      if (flat.quantities[k].component < 0) continue;
      if (std::abs(values[k] - solved_values[k]) > 1e-9 * std::max(1.0, std::abs(solved_values[k])))
        drives.push_back(flat.quantities[k].name);
    }
    std::copy(solved_values.begin(), solved_values.end(), values.begin());
  }
  clock.lap("solve");

  // Shapes, with their cut-outs.
  bool ok = true;
  for (const detail::FlatComponent& fc : flat.components) {
    if (stopped_after(
            [&] {
              return fmt::format(
                  "the shapes of {} of {} components", a.components.size(), flat.components.size());
            },
            "the other shapes, placement, joints and the assembly order were")) {
      return a;
    }
    PlacedComponent pc;
    pc.name = fc.name;
    pc.type = fc.type->name;
    pc.material = fc.material;
    for (const auto& [param, q] : fc.params) pc.values[param] = values[static_cast<std::size_t>(q)];
    std::string error;
    std::optional<ComponentShape> shape = fc.type->generate(pc.values, fc.use->points, error);
    if (!shape) {
      a.diagnostics.error(codes::kBadShape,
                          fmt::format("{} ({}): {}", fc.name, fc.type->name, error),
                          fc.use->where);
      ok = false;
      continue;
    }
    if (!fc.use->edge_names.empty()) {
      for (std::size_t e = 0; e < shape->edges.size() && e < fc.use->edge_names.size(); ++e) {
        shape->edges[e].name = fc.use->edge_names[e];
      }
    }
    Region2d holes;
    for (const Cutout& cut : fc.use->cutouts) {
      double v[4];
      const Expression* es[4] = {&cut.at[0], &cut.at[1], &cut.size[0], &cut.size[1]};
      bool good = true;
      for (int k = 0; k < 4; ++k) {
        if (k == 3 && cut.shape == Cutout::Shape::kCircle) {
          v[3] = 0;
          continue;
        }
        const int id = ex.compile(*es[k], fc.scope, a.diagnostics);
        v[k] = id >= 0 ? ex.evaluate(id) : std::nan("");
        good = good && std::isfinite(v[k]);
      }
      if (!good || v[2] <= 0 || (cut.shape == Cutout::Shape::kRectangle && v[3] <= 0)) {
        a.diagnostics.error(codes::kBadShape,
                            fmt::format("{}: a cut-out needs a positive size", fc.name),
                            cut.where);
        ok = false;
        continue;
      }
      holes.push_back(cut.shape == Cutout::Shape::kCircle
                          ? circle(Vec2(v[0], v[1]), v[2] / 2, 48)
                          : rectangle(v[0], v[1], v[0] + v[2], v[1] + v[3]));
    }
    if (!holes.empty()) {
      const Region2d r = subtract({shape->polygon}, holes);
      if (r.size() != 1) {
        a.diagnostics.error(
            codes::kBadShape,
            fmt::format("{}: its cut-outs split it into {} parts", fc.name, r.size()),
            fc.use->where);
        ok = false;
        continue;
      }
      // Keep the named edges: booleans may renumber the outer ring, so only holes are taken.
      shape->polygon.holes = r[0].holes;
      const double area_before = std::abs(signed_area(shape->polygon.outer));
      if (std::abs(r[0].area() - (area_before - area(holes))) > 1e-3 * area_before) {
        a.diagnostics.error(
            codes::kBadShape,
            fmt::format("{}: a cut-out reaches past its edge; cut-outs must lie inside", fc.name),
            fc.use->where);
        ok = false;
        continue;
      }
    }
    pc.shape = std::move(*shape);
    a.components.push_back(std::move(pc));
  }
  if (!ok) return a;

  // Connections: evaluate their offsets and rotations, check their edges exist.
  std::vector<detail::ResolvedConnection> resolved;
  for (const detail::FlatConnection& fc : flat.connections) {
    Vec3 offset, rotation;
    for (int k = 0; k < 3; ++k) {
      for (int which = 0; which < 2; ++which) {
        const Expression& e = which == 0 ? fc.spec->offset[static_cast<std::size_t>(k)]
                                         : fc.spec->rotation[static_cast<std::size_t>(k)];
        double v = 0;
        if (!e.text.empty()) {
          const int id = ex.compile(e, fc.scope, a.diagnostics);
          v = id >= 0 ? ex.evaluate(id) : std::nan("");
          if (!std::isfinite(v)) {
            a.diagnostics.error(codes::kInvalidValue,
                                fmt::format("{}: '{}' is not a finite number", fc.name, e.text),
                                e.where);
            ok = false;
          }
        }
        (which == 0 ? offset : rotation)[k] = v;
      }
    }
    const ComponentShape& sa = a.components[static_cast<std::size_t>(fc.a)].shape;
    const ComponentShape& sb = a.components[static_cast<std::size_t>(fc.b)].shape;
    bool found_a = false, found_b = false;
    detail::edge_frame(sa, fc.a_edge, &found_a);
    detail::edge_frame(sb, fc.b_edge, &found_b);
    if (!found_a || !found_b) {
      const PlacedComponent& c = a.components[static_cast<std::size_t>(found_a ? fc.b : fc.a)];
      std::vector<std::string> names;
      for (const NamedEdge& e : c.shape.edges) names.push_back(e.name);
      const std::string& edge = found_a ? fc.b_edge : fc.a_edge;
      a.diagnostics.error(
          codes::kUnknownEdge,
          fmt::format(
              "{}: {} has no edge '{}'{}", fc.name, c.name, edge, did_you_mean(edge, names)),
          fc.spec->where);
      ok = false;
      continue;
    }
    resolved.push_back({fc.a,
                        fc.b,
                        detail::relative_transform(
                            sa, fc.a_edge, sb, fc.b_edge, fc.spec->alignment, offset, rotation),
                        fc.name,
                        fc.spec->text(),
                        fc.spec->where,
                        fc.spec->places_only});
  }
  if (!ok) return a;
  if (stopped_after("the shapes and connections", "placement, joints and the assembly order were"))
    return a;
  detail::place(a.components, resolved, options, a.diagnostics, &a.residuals);
  if (a.diagnostics.has_errors()) return a;
  // Stand the furniture on the floor: the lowest mid-plane point at z = 0.
  double min_z = 1e300;
  for (const PlacedComponent& c : a.components) {
    for (const Vec2& v : c.shape.polygon.outer) {
      min_z = std::min(min_z, (c.frame * Eigen::Vector4d(v.x(), v.y(), 0, 1)).z());
    }
  }
  for (PlacedComponent& c : a.components) c.frame(2, 3) -= min_z;
  for (CycleResidual& r : a.residuals) r.frame(2, 3) -= min_z;
  a.placed = true;
  clock.lap("place");
  if (stopped_after("placing the pieces", "joints and the assembly order were")) return a;

  detail::detect_and_cut(a, resolved, design.joints, design.labels, options);
  clock.lap("detect+joints");
  if (options.assembly_order && stopped_after("cutting the joints", "the assembly order was")) {
    return a;
  }
  if (options.assembly_order) {
    detail::plan_assembly(a);
    clock.lap("assembly");
  }
  return a;
}

}  // namespace fabkit::flatpack
