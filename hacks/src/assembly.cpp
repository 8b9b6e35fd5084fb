#include "fabkit/hacks/assembly.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <set>

#include "constraints.h"
#include "cycle_closure.h"
#include "distance_bounds.h"
#include "fabkit/hacks/diagnostic_codes.h"

namespace fabkit::hacks {
namespace {

std::string join_types(const std::vector<PrimitiveType>& types) {
  std::string out;
  for (std::size_t i = 0; i < types.size(); ++i) {
    if (i > 0) out += (i + 1 == types.size()) ? " or " : ", ";
    out += to_string(types[i]);
  }
  return out.empty() ? "nothing" : out;
}

// "t (DoubleHook)" for a named instance, "DoubleHook" otherwise.
std::string describe_part(const Part& p) {
  return p.instance_name.empty() ? p.type_name
                                 : fmt::format("{} ({})", p.instance_name, p.type_name);
}

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
      .count();
}

}  // namespace

PrimitiveRef::PrimitiveRef(std::shared_ptr<Part> p, std::string_view name)
    : part(std::move(p)), requested(name) {
  index = part ? part->find_primitive(name) : -1;
}

bool PrimitiveRef::valid() const {
  return part && index >= 0 && index < static_cast<int>(part->primitives.size());
}

std::optional<PartId> Assembly::find(const Part* part) const {
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    if (parts_[i].part.get() == part) return PartId{static_cast<int>(i)};
  }
  return std::nullopt;
}

std::string Assembly::label(PartId id) const {
  const Part& p = *parts_.at(static_cast<std::size_t>(id.value)).part;
  if (!p.instance_name.empty()) return p.instance_name;
  int rank = 0;
  int count = 0;
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    const Part& q = *parts_[i].part;
    if (q.type_name != p.type_name || !q.instance_name.empty()) continue;
    ++count;
    if (static_cast<int>(i) <= id.value) ++rank;
  }
  return count > 1 ? fmt::format("{}#{}", p.type_name, rank) : p.type_name;
}

std::string Assembly::label(PartId id, int primitive) const {
  const Part& p = *parts_.at(static_cast<std::size_t>(id.value)).part;
  return fmt::format("{}.{}", label(id), p.primitives.at(static_cast<std::size_t>(primitive)).name);
}

PartId Assembly::insert_part(std::shared_ptr<Part> part, bool environment, const Frame& frame) {
  PartNode n;
  n.part = std::move(part);
  n.environment = environment;
  n.frame = frame;
  n.placement = Rigid<double>::from_matrix(frame.matrix());
  parts_.push_back(n);
  std::vector<PrimitiveState> states;
  for (const Primitive& prim : parts_.back().part->primitives) {
    states.push_back({prim.critical_dim(), 0});
  }
  primitive_state_.push_back(std::move(states));
  return PartId{static_cast<int>(parts_.size()) - 1};
}

Connector Assembly::make_connector(PartId part, int primitive, std::vector<ParamSpec> params) {
  Connector c;
  c.part = part;
  c.primitive = primitive;
  c.offset = static_cast<int>(values_.size());
  c.params = std::move(params);
  c.base = Rigid<double>::from_matrix(parts_[static_cast<std::size_t>(part.value)]
                                          .part->primitives[static_cast<std::size_t>(primitive)]
                                          .frame.matrix());
  return c;
}

ConnectReport Assembly::add(std::shared_ptr<Part> environment,
                            const Frame& frame,
                            const SourceLocation& where) {
  ConnectReport report;
  if (!environment) {
    report.diagnostics.error(codes::kUnknownPart, "add: no environment part given", where);
    return report;
  }
  report.description = fmt::format("add {}", environment->type_name);
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(frame.pos[i]) || !std::isfinite(frame.rot[i])) {
      report.diagnostics.error(
          codes::kInvalidValue,
          fmt::format(
              "add {}: frame {} has a non-finite value", environment->type_name, frame.to_string()),
          where);
      return report;
    }
  }
  if (find(environment.get())) {
    report.diagnostics.error(
        codes::kDuplicateName,
        fmt::format("add: {} is already in the assembly", environment->type_name),
        where);
    return report;
  }
  const PartId id = insert_part(std::move(environment), true, frame);
  report.description = fmt::format("add {} at {}", label(id), frame.to_string());
  report.accepted = true;
  return report;
}

ConnectReport Assembly::add(const PrimitiveRef& primitive,
                            const Frame& frame,
                            const SourceLocation& where) {
  if (!primitive.valid()) {
    ConnectReport report;
    report.diagnostics.error(codes::kUnknownPrimitive,
                             primitive.part
                                 ? fmt::format("add: {} has no primitive '{}' (it has {})",
                                               primitive.part->type_name,
                                               primitive.requested,
                                               primitive.part->primitive_list())
                                 : std::string("add: no environment part given"),
                             where);
    return report;
  }
  if (primitive.part->primitives.size() == 1) return add(primitive.part, frame, where);
  // Only this primitive moves: the environment part itself stays at the origin.
  primitive.part->primitives[static_cast<std::size_t>(primitive.index)].frame = frame;
  return add(primitive.part, Frame(), where);
}

Diagnostics Assembly::end_with(std::shared_ptr<Part> part,
                               const Frame& frame,
                               const SourceLocation& where) {
  Diagnostics diags;
  if (!part || part->primitives.empty()) {
    diags.error(codes::kTargetMissing, "end_with: the target has no primitives", where);
    return diags;
  }
  // The paper's programs give the frame of the part's first primitive (App. B.3, Fig. 8:
  // the soap bottle's rod, the basket's handle), as the reference's examples do.
  return end_with(PrimitiveRef(part, 0), frame, where);
}

Diagnostics Assembly::end_with(const PrimitiveRef& primitive,
                               const Frame& frame,
                               const SourceLocation& where) {
  Diagnostics diags;
  if (!primitive.valid()) {
    diags.error(codes::kUnknownPrimitive,
                primitive.part ? fmt::format("end_with: {} has no primitive '{}' (it has {})",
                                             primitive.part->type_name,
                                             primitive.requested,
                                             primitive.part->primitive_list())
                               : std::string("end_with: no target part given"),
                where);
    return diags;
  }
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(frame.pos[i]) || !std::isfinite(frame.rot[i])) {
      diags.error(
          codes::kInvalidValue,
          fmt::format("end_with: target frame {} has a non-finite value", frame.to_string()),
          where);
      return diags;
    }
  }
  if (auto id = find(primitive.part.get());
      id && parts_[static_cast<std::size_t>(id->value)].environment) {
    diags.error(codes::kTargetMissing,
                fmt::format("end_with: {} is an environment; the target must be a part the hack "
                            "holds",
                            label(*id)),
                where);
    return diags;
  }
  target_ = Target{primitive.part, primitive.index, frame};
  return diags;
}

ConnectReport Assembly::connect(const PrimitiveRef& a,
                                const PrimitiveRef& b,
                                const ConnectOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  ConnectReport report;
  Diagnostics& diags = report.diagnostics;
  const SourceLocation& where = options.where;

  for (const PrimitiveRef* r : {&a, &b}) {
    if (!r->part) {
      diags.error(codes::kUnknownPart, "connect: a primitive without a part was given", where);
    } else if (!r->valid()) {
      diags.error(codes::kUnknownPrimitive,
                  fmt::format("connect: {} has no primitive '{}' (it has {})",
                              describe_part(*r->part),
                              r->requested,
                              r->part->primitive_list()),
                  where);
    }
  }
  if (diags.has_errors()) return report;

  if (a.part == b.part) {
    diags.error(codes::kPairNotAllowed,
                fmt::format("connect: {}.{} and {}.{} are on the same part; a part cannot be "
                            "connected to itself",
                            a.part->type_name,
                            a.primitive().name,
                            b.part->type_name,
                            b.primitive().name),
                where);
    return report;
  }
  const bool has_environment =
      std::any_of(parts_.begin(), parts_.end(), [](const PartNode& n) { return n.environment; });
  if (!has_environment) {
    diags.error(codes::kNoEnvironment,
                "connect: the assembly has no environment yet; add() one first",
                where);
    return report;
  }
  const std::optional<PartId> a_in = find(a.part.get());
  const std::optional<PartId> b_in = find(b.part.get());
  if (!a_in && !b_in) {
    diags.error(codes::kNotInAssembly,
                fmt::format("connect: neither {} nor {} is in the assembly yet; connect each new "
                            "part to something already in it",
                            describe_part(*a.part),
                            describe_part(*b.part)),
                where);
    return report;
  }

  // Work on a copy: a rejected connect must leave the assembly exactly as it was.
  Assembly trial = *this;
  const bool closes_cycle = a_in && b_in;
  const PrimitiveRef& first_ref = (a_in) ? a : b;
  const PrimitiveRef& second_ref = (a_in) ? b : a;
  const PartId first_part = a_in ? *a_in : *b_in;
  const PartId second_part =
      closes_cycle ? *b_in : trial.insert_part(second_ref.part, false, Frame());
  const int first_prim = first_ref.index;
  const int second_prim = second_ref.index;
  const Primitive& p1 = first_ref.primitive();
  const Primitive& p2 = second_ref.primitive();
  const std::string l1 = trial.label(first_part, first_prim);
  const std::string l2 = trial.label(second_part, second_prim);
  report.description = fmt::format("{} {} {}", l1, closes_cycle ? "↔" : "→", l2);
  report.closes_cycle = closes_cycle;

  // (a) the pair is allowed at all.
  if (!pair_allowed(p1.type, p2.type)) {
    diags.error(codes::kPairNotAllowed,
                fmt::format("{} ({}) cannot connect to {} ({}): a {} connects only to a {}",
                            l2,
                            to_string(p2.type),
                            l1,
                            to_string(p1.type),
                            to_string(p2.type),
                            join_types(allowed_partners(p2.type))),
                where);
    return report;
  }
  // Single-connection primitives and repeated connections.
  for (auto [part, prim, lbl] :
       {std::tuple{first_part, first_prim, l1}, std::tuple{second_part, second_prim, l2}}) {
    const Primitive& p = trial.node(part).part->primitives[static_cast<std::size_t>(prim)];
    const std::vector<ConnectionId> existing = trial.connections_of(part, prim);
    if (p.single_connection() && !existing.empty()) {
      const Connection& c = trial.connection(existing.front());
      const Connector& other =
          (c.first.part == part && c.first.primitive == prim) ? c.second : c.first;
      diags.error(codes::kSingleConnection,
                  fmt::format("{} already holds {}; a {} holds one thing only",
                              lbl,
                              trial.label(other.part, other.primitive),
                              to_string(p.type)),
                  where);
    }
  }
  for (ConnectionId id : trial.connections_of(first_part, first_prim)) {
    const Connection& c = trial.connection(id);
    const bool same = (c.second.part == second_part && c.second.primitive == second_prim) ||
                      (c.first.part == second_part && c.first.primitive == second_prim);
    if (same) {
      diags.error(
          codes::kAlreadyConnected, fmt::format("{} and {} are already connected", l1, l2), where);
    }
  }
  if (diags.has_errors()) return report;

  // (b) + (c): closedness, sizes, available critical dimension.
  PrimitiveInUse u1{&p1, l1, trial.available_critical_dim(first_part, first_prim)};
  PrimitiveInUse u2{&p2, l2, trial.available_critical_dim(second_part, second_prim)};
  if (!check_compatibility(u1, u2, diags, where)) return report;

  // Connector parameters (reference §3.4).
  std::vector<ParamSpec> params1 = p1.connector_params();
  std::vector<ParamSpec> params2 = p2.connector_params();
  const ConnectorKind k1 = p1.connector_kind();
  const ConnectorKind k2 = p2.connector_kind();
  auto pin = [](std::vector<ParamSpec>& ps, bool keep_angles_free) {
    for (ParamSpec& s : ps) {
      if (keep_angles_free && s.tag == ParamTag::kUnbounded) continue;
      s.constant = true;
      s.lo = s.hi = s.init;
    }
  };
  if (p1.type == PrimitiveType::kSurface && p2.type == PrimitiveType::kSurface) {
    // The smaller surface rests at its centre; the larger keeps it fully on.
    const bool first_smaller = p1.shape.width < p2.shape.width;
    std::vector<ParamSpec>& small = first_smaller ? params1 : params2;
    std::vector<ParamSpec>& large = first_smaller ? params2 : params1;
    const Primitive& ps = first_smaller ? p1 : p2;
    const Primitive& pl = first_smaller ? p2 : p1;
    pin(small, false);
    const double mw = ps.shape.width / (2 * pl.shape.width);
    const double ml = ps.shape.length / (2 * pl.shape.length);
    large[0].lo = mw;
    large[0].hi = 1 - mw;
    large[1].lo = ml;
    large[1].hi = 1 - ml;
  } else if (!closes_cycle &&
             ((k1 == ConnectorKind::kTube && k2 == ConnectorKind::kTubeCenterline) ||
              (k1 == ConnectorKind::kTubeCenterline && k2 == ConnectorKind::kTube) ||
              (k1 == ConnectorKind::kRod && k2 == ConnectorKind::kTubeCenterline) ||
              (k1 == ConnectorKind::kTubeCenterline && k2 == ConnectorKind::kRod))) {
    // A roll on a rod or tube: the shorter one sits centred, the longer keeps it fully on.
    const bool first_shorter = p1.shape.length < p2.shape.length;
    std::vector<ParamSpec>& shorter = first_shorter ? params1 : params2;
    std::vector<ParamSpec>& longer = first_shorter ? params2 : params1;
    const double ls = (first_shorter ? p1 : p2).shape.length;
    const double ll = (first_shorter ? p2 : p1).shape.length;
    pin(shorter, /*keep_angles_free=*/true);
    const double half = (ll - ls) / (2 * ll);
    longer[0].lo = 0.5 - half;
    longer[0].hi = 0.5 + half;
    if (longer.size() > 1 && (p1.type == PrimitiveType::kRod || p2.type == PrimitiveType::kRod)) {
      longer[1].lo = longer[1].hi = longer[1].init = 90;
      longer[1].constant = true;
    }
  }
  const bool has_clip = p1.type == PrimitiveType::kClip || p2.type == PrimitiveType::kClip;
  for (auto* ps : {&params1, &params2}) {
    for (ParamSpec& s : *ps) {
      if (options.fixed || has_clip) s.fixed_under_physics = true;
    }
  }
  // Friction keeps a resting object where it stands: a surface contact does not slide or spin
  // under gravity (tipping over a hemisphere's rim still can happen).
  for (auto [prim, ps] : {std::pair{&p1, &params1}, std::pair{&p2, &params2}}) {
    if (prim->type != PrimitiveType::kSurface) continue;
    for (ParamSpec& s : *ps) s.fixed_under_physics = true;
  }

  const AlignmentOffset align = alignment_offset(k1, k2);
  if (options.alignment == AlignmentChoice::kFlip && !align.flippable()) {
    diags.warning(codes::kUnknownName,
                  fmt::format("alignment \"flip\" has no effect on a {}–{} connection ({} and {})",
                              to_string(k1),
                              to_string(k2),
                              l1,
                              l2),
                  where);
  }

  Connection conn;
  conn.alignment = options.alignment;
  conn.offset = align.matrix(options.alignment);
  conn.offset_rigid = Rigid<double>::from_matrix(conn.offset);
  conn.fixed = options.fixed;
  conn.closes_cycle = closes_cycle;
  conn.where = where;
  const ConnectionId id{static_cast<int>(trial.connections_.size())};
  conn.first = trial.make_connector(first_part, first_prim, params1);
  for (const ParamSpec& s : params1) {
    trial.params_.push_back({s, id, first_part, first_prim});
    trial.values_.push_back(s.init);
  }
  conn.second = trial.make_connector(second_part, second_prim, params2);
  for (const ParamSpec& s : params2) {
    trial.params_.push_back({s, id, second_part, second_prim});
    trial.values_.push_back(s.init);
  }
  trial.connections_.push_back(conn);
  if (!closes_cycle) trial.parts_[static_cast<std::size_t>(second_part.value)].parent = id;

  // (c) bookkeeping of the available critical dimension (§4.3).
  auto& s1 = trial.primitive_state_[static_cast<std::size_t>(first_part.value)]
                                   [static_cast<std::size_t>(first_prim)];
  auto& s2 = trial.primitive_state_[static_cast<std::size_t>(second_part.value)]
                                   [static_cast<std::size_t>(second_prim)];
  const std::vector<double> before1 = s1.available;
  s1.available = consume_critical_dim(p1, s1.available, p2, s2.available);
  s2.available = consume_critical_dim(p2, s2.available, p1, before1);
  ++s1.connections;
  ++s2.connections;
  report.connection = id;

  // (d) + (e): cycles and multi-connection spacing must be satisfiable together.
  const bool new_multi = s1.connections > 1 || s2.connections > 1;
  const bool has_cycles = !trial.cycle_connections().empty();
  if (closes_cycle) {
    report.cycles.push_back(trial.describe_cycle(id));
    if (options.verify.quick_reject) {
      const detail::PolygonVerdict v = detail::check_cycle_polygon(trial, id);
      if (!v.feasible) {
        const detail::CycleSegment& s = v.segments[static_cast<std::size_t>(v.failing)];
        diags.error(codes::kCycleTooLong,
                    fmt::format("cannot close cycle {}: {:.0f} mm {} exceeds the {:.0f} mm the "
                                "other parts can span",
                                report.cycles.back(),
                                s.range.lo,
                                s.description,
                                v.others_span),
                    where);
        report.best_parameters = trial.values_;
        report.best_part_frames.clear();
        for (const Mat4& m : trial.part_frames(trial.values_)) {
          report.best_part_frames.push_back(Frame::from_matrix(m));
        }
        report.milliseconds = elapsed_ms(started);
        return report;
      }
    }
  }
  if (closes_cycle || (new_multi && has_cycles)) {
    const detail::ClosureResult r = detail::close_cycles(trial, trial.values_, options.verify);
    report.starts_used = r.starts;
    report.residual = r.cost;
    report.best_parameters = r.x;
    for (std::size_t i = 0; i < report.best_parameters.size(); ++i) {
      if (trial.params_[i].spec.tag == ParamTag::kUnbounded) {
        report.best_parameters[i] = wrap_360(report.best_parameters[i]);
      }
    }
    for (const Mat4& m : trial.part_frames(report.best_parameters)) {
      report.best_part_frames.push_back(Frame::from_matrix(m));
    }
    if (!r.closed) {
      std::string gap;
      for (const detail::ClosureGap& g : detail::closure_gaps(trial, r.x)) {
        if (g.position_mm < 1e-3 && g.rotation_deg < 1e-3) continue;
        const Connection& c = trial.connection(g.connection);
        gap += fmt::format("{}a gap of {:.1f} mm and {:.1f}° at {} ↔ {}",
                           gap.empty() ? "" : "; ",
                           g.position_mm,
                           g.rotation_deg,
                           trial.label(c.first.part, c.first.primitive),
                           trial.label(c.second.part, c.second.primitive));
      }
      std::string overlap;
      for (const detail::MultiConnectionPair& m : detail::multi_connection_pairs(trial)) {
        const double f = detail::multi_connection_value<double>(m, r.x.data());
        if (f < -1e-3) {
          overlap += fmt::format(
              "{}{} overlap by {:.1f} mm", overlap.empty() ? "" : "; ", m.description, -f);
        }
      }
      const std::string best =
          fmt::format("the best of {} start{} leaves {}",
                      r.starts,
                      r.starts == 1 ? "" : "s",
                      gap.empty() ? overlap : (overlap.empty() ? gap : gap + "; " + overlap));
      if (closes_cycle) {
        diags.error(codes::kCycleNotClosable,
                    fmt::format("cannot close cycle {}: {}", report.cycles.back(), best),
                    where);
      } else {
        diags.error(
            codes::kMultiConnection,
            fmt::format("{} leaves no room on a shared primitive: {}", report.description, best),
            where);
      }
      report.milliseconds = elapsed_ms(started);
      return report;
    }
    trial.values_ = report.best_parameters;
  }

  report.accepted = true;
  report.milliseconds = elapsed_ms(started);
  *this = std::move(trial);
  return report;
}

std::vector<ConnectionId> Assembly::cycle_connections() const {
  std::vector<ConnectionId> out;
  for (std::size_t i = 0; i < connections_.size(); ++i) {
    if (connections_[i].closes_cycle) out.push_back(ConnectionId{static_cast<int>(i)});
  }
  return out;
}

std::vector<ConnectionId> Assembly::connections_of(PartId id, int primitive) const {
  std::vector<ConnectionId> out;
  for (std::size_t i = 0; i < connections_.size(); ++i) {
    const Connection& c = connections_[i];
    if ((c.first.part == id && c.first.primitive == primitive) ||
        (c.second.part == id && c.second.primitive == primitive)) {
      out.push_back(ConnectionId{static_cast<int>(i)});
    }
  }
  return out;
}

std::vector<double> Assembly::available_critical_dim(PartId id, int primitive) const {
  return primitive_state_.at(static_cast<std::size_t>(id.value))
      .at(static_cast<std::size_t>(primitive))
      .available;
}

Assembly::CyclePath Assembly::cycle_path(ConnectionId closing) const {
  const Connection& c = connection(closing);
  auto root_path = [&](PartId p) {
    std::vector<PartId> path{p};
    while (node(path.back()).parent.valid()) {
      path.push_back(connection(node(path.back()).parent).first.part);
    }
    return path;
  };
  CyclePath out;
  out.first_side = root_path(c.first.part);
  out.second_side = root_path(c.second.part);
  std::vector<PartId>& a = out.first_side;
  std::vector<PartId>& b = out.second_side;
  // Drop the shared part above the lowest common ancestor.
  while (a.size() > 1 && b.size() > 1 && a.back() == b.back() &&
         a[a.size() - 2] == b[b.size() - 2]) {
    a.pop_back();
    b.pop_back();
  }
  out.common_ancestor = a.back() == b.back();
  return out;
}

std::string Assembly::describe_cycle(ConnectionId closing) const {
  const Connection& c = connection(closing);
  const CyclePath loop = cycle_path(closing);
  // The primitive on the top part that leads down towards the closing connection.
  auto top_primitive = [&](const std::vector<PartId>& path, int closing_prim) {
    if (path.size() == 1) return closing_prim;
    return connection(node(path[path.size() - 2]).parent).first.primitive;
  };
  std::vector<std::string> items;
  items.push_back(label(loop.first_side.back(), top_primitive(loop.first_side, c.first.primitive)));
  for (std::size_t k = loop.first_side.size() - 1; k-- > 0;)
    items.push_back(label(loop.first_side[k]));
  for (std::size_t k = 0; k + 1 < loop.second_side.size(); ++k) {
    items.push_back(label(loop.second_side[k]));
  }
  items.push_back(
      label(loop.second_side.back(), top_primitive(loop.second_side, c.second.primitive)));
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += " – ";
    out += items[i];
  }
  return out;
}

void Assembly::set_values(std::vector<double> x) {
  if (x.size() == values_.size()) values_ = std::move(x);
}

std::vector<Mat4> Assembly::part_frames(const std::vector<double>& x) const {
  std::vector<Mat4> out;
  out.reserve(parts_.size());
  // Parents always precede children, so one pass in insertion order suffices.
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    const PartNode& n = parts_[i];
    if (!n.parent.valid()) {
      out.push_back(n.frame.matrix());
      continue;
    }
    const Connection& c = connections_[static_cast<std::size_t>(n.parent.value)];
    const Rigid<double> parent =
        Rigid<double>::from_matrix(out[static_cast<std::size_t>(c.first.part.value)]);
    const Primitive& child = n.part->primitives[static_cast<std::size_t>(c.second.primitive)];
    Rigid<double> child_connector = c.second.base;
    apply_connector<double>(
        child.connector_kind(), child.shape, x.data() + c.second.offset, child_connector);
    out.push_back((connector_world<double>(c.first, parent, x.data()).then(c.offset_rigid) *
                   child_connector.inverse())
                      .matrix());
  }
  return out;
}

}  // namespace fabkit::hacks
