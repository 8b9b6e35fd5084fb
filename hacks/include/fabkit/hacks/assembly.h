#pragma once
/// FabHaL assemblies (paper §4.2): add / connect / end_with, in reduced coordinates.
///
/// Parts form a kinematic forest rooted at the environments. A connect() that brings a new
/// part in extends the tree; a connect() between two parts already in the assembly closes a
/// cycle and becomes a constraint. Every connect is verified before it is accepted; a
/// rejected connect leaves the assembly unchanged.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"
#include "fabkit/core/ids.h"
#include "fabkit/core/kinematic_graph.h"
#include "fabkit/hacks/connection_rules.h"
#include "fabkit/hacks/connector_frame.h"
#include "fabkit/hacks/part.h"

namespace fabkit::hacks {

/// A primitive of a part instance: what connect() takes. The shared_ptr identifies the
/// instance (two DoubleHook() calls are two parts).
struct PrimitiveRef {
  std::shared_ptr<Part> part;
  PrimitiveId index;
  std::string requested;  ///< the name asked for, kept for diagnostics when index is invalid

  PrimitiveRef() = default;
  PrimitiveRef(std::shared_ptr<Part> p, PrimitiveId i) : part(std::move(p)), index(i) {}
  /// Looks the primitive up by name ("hole" and "ring" alias); index invalid if unknown.
  PrimitiveRef(std::shared_ptr<Part> p, std::string_view name);
  bool valid() const;
  const Primitive& primitive() const { return part->primitive(index); }
};

/// Options of the verification run by every connect().
struct VerifyOptions {
  int restarts = 16;         ///< T: starts of the cycle-closure search (paper §4.3.2)
  std::uint64_t seed = 1;    ///< seeds the random starts (same input, same answer)
  double tolerance = 1e-6;   ///< closed when Σ‖f‖² is below this (mm², deg²)
  int max_iterations = 100;  ///< per start
  bool quick_reject = true;  ///< polygon-inequality check before the search
  /// When every start misses, a last one that pulls each chain out along the line between
  /// its two ends (nearly taut chains); off where a miss is cheap (step 1's restarts).
  bool stretch_start = true;
  /// Give up the search once this time has passed (servers); none: no limit.
  std::optional<std::chrono::steady_clock::time_point> deadline;
  /// False: a connect that closes a cycle is recorded with its cycle left open (no search; the
  /// distance-bound proof still runs). Only for Assembly::verified_in_canonical_order's input.
  bool close_cycles = true;
};

struct ConnectOptions {
  AlignmentChoice alignment = AlignmentChoice::kDefault;
  bool fixed = false;    ///< hold this connection's parameters during relaxation
  SourceLocation where;  ///< for diagnostics of design files
  VerifyOptions verify;
};

/// One side of a connection: a connector frame on a primitive and its parameters, which
/// live at [offset, offset + params.size()) of the assembly's parameter vector.
struct Connector {
  PartId part;
  PrimitiveId primitive;
  int offset = 0;
  std::vector<ParamSpec> params;
  Rigid<double> base;  ///< the primitive's base frame in its part (cached)
};

struct Connection {
  Connector first;   ///< the primitive already in the assembly (tree: the parent side)
  Connector second;  ///< the new primitive (tree: the child side)
  AlignmentChoice alignment = AlignmentChoice::kDefault;
  Mat4 offset = Mat4::Identity();  ///< C_first · offset = C_second when connected
  Rigid<double> offset_rigid;      ///< the same offset, for the solvers
  bool fixed = false;
  bool closes_cycle = false;
  SourceLocation where;
};

/// A part instance in the assembly.
struct PartNode {
  /// The assembly's own copy of the part (placing a primitive of a loose-primitive
  /// environment changes the copy, never the caller's part).
  std::shared_ptr<const Part> part;
  /// The caller's part: what identifies this instance in connect() and find() (held, so that
  /// its address cannot be reused by another part while the assembly lives).
  std::shared_ptr<const Part> source;
  bool environment = false;
  Frame frame;              ///< environments: fixed world frame
  Rigid<double> placement;  ///< `frame` as a transform (cached)
  /// Loose-primitive environments placed one primitive at a time (paper App. B.2): which
  /// primitives have been placed. Empty: the whole part is placed.
  std::vector<bool> placed;
};

/// A parameter of the assembly's vector with its owner, for messages and front ends.
struct ParamInfo {
  ParamSpec spec;
  ConnectionId connection;
  PartId part;
  PrimitiveId primitive;
};

/// Outcome of one add / connect.
struct ConnectReport {
  bool accepted = false;
  bool closes_cycle = false;
  std::string description;          ///< "eyehook2.hook ↔ basket.hook"
  std::vector<std::string> cycles;  ///< the cycles this connect closes
  Diagnostics diagnostics;
  int starts_used = 0;      ///< cycle-closure starts run
  double residual = 0;      ///< best Σ‖f‖² found by the closure search
  double milliseconds = 0;  ///< verification time
  /// Configuration with the smallest residual found (the whole parameter vector), also
  /// when the connect is rejected, so a front end can show how close it came.
  std::vector<double> best_parameters;
  /// World frame of every part (including a part this connect tried to bring in) at
  /// best_parameters, in the order the parts were (or would have been) added.
  std::vector<Frame> best_part_frames;
  ConnectionId connection;
};

/// The target of end_with: a primitive and where it should be.
struct Target {
  std::shared_ptr<Part> part;
  PrimitiveId primitive{0};
  Frame frame;  ///< world frame the target primitive should reach
};

class Assembly {
 public:
  /// Adds an environment part at a fixed world frame.
  ConnectReport add(std::shared_ptr<Part> environment,
                    const Frame& frame,
                    const SourceLocation& where = {});
  /// Adds an environment through one of its primitives (paper App. B.2): a one-primitive
  /// part is placed at `frame`; otherwise only that primitive's base frame is replaced.
  ConnectReport add(const PrimitiveRef& primitive,
                    const Frame& frame,
                    const SourceLocation& where = {});
  /// The paper's connect: verifies, then either brings a new part in or closes a cycle.
  ConnectReport connect(const PrimitiveRef& a,
                        const PrimitiveRef& b,
                        const ConnectOptions& options = {});
  /// Target: the part's first primitive should reach world frame `frame` (the paper's
  /// end_with(part, frame); its numbers are those of the first primitive, e.g. App. B.3).
  Diagnostics end_with(std::shared_ptr<Part> part,
                       const Frame& frame,
                       const SourceLocation& where = {});
  /// Target: the primitive's world frame should be `frame`.
  Diagnostics end_with(const PrimitiveRef& primitive,
                       const Frame& frame,
                       const SourceLocation& where = {});

  // ---- the model -------------------------------------------------------------------------
  int part_count() const { return static_cast<int>(parts_.size()); }
  const PartNode& node(PartId id) const { return parts_.at(id.index()); }
  const std::vector<PartNode>& nodes() const { return parts_; }
  std::optional<PartId> find(const Part* part) const;
  /// "eyehook1" (instance name), "Basket" (only one of its type) or "DoubleHook#2".
  std::string label(PartId id) const;
  /// "DoubleHook#2.hook1".
  std::string label(PartId id, PrimitiveId primitive) const;
  /// The parts and connections as a graph (tree edges and cycle edges).
  const KinematicGraph& graph() const { return graph_; }
  /// The tree edge above a part (invalid for environments).
  ConnectionId parent(PartId id) const { return graph_.parent_edge(id); }

  const std::vector<Connection>& connections() const { return connections_; }
  const Connection& connection(ConnectionId id) const { return connections_.at(id.index()); }
  /// Cycle-closing connections, in program order.
  std::vector<ConnectionId> cycle_connections() const;
  /// Parts on the cycle closed by `c`, as "Rods.rod1 – HookEye#1 – Basket – …".
  std::string describe_cycle(ConnectionId c) const;
  /// The loop closed by `c` as two tree paths (KinematicGraph::cycle_path).
  using CyclePath = KinematicGraph::CyclePath;
  CyclePath cycle_path(ConnectionId c) const { return graph_.cycle_path(c); }

  int parameter_count() const { return static_cast<int>(params_.size()); }
  const std::vector<ParamInfo>& parameters() const { return params_; }
  /// A name for every parameter that depends only on the design's structure (the path of
  /// part types and primitives from the environment), not on its place in the vector, the
  /// order of the connects or what the parts are called; seeds the random starts. All at once:
  /// each part's key extends its parent's, so one at a time a chain of n parts costs n³.
  std::vector<std::string> parameter_keys() const;
  /// The same for every part: its environment's type and the chain of connections down to it.
  std::vector<std::string> structural_keys() const;
  /// Current parameter values: the defaults, updated by every successful cycle check.
  const std::vector<double>& values() const { return values_; }
  void set_values(std::vector<double> x);

  /// World frame of every part for parameter vector `x` (forward propagation).
  std::vector<Mat4> part_frames(const std::vector<double>& x) const;

  /// World frame of a part, differentiable in x.
  template <class T>
  Rigid<T> part_frame(PartId id, const T* x) const;
  /// World frames of every part at once (parents before children), differentiable in x.
  template <class T>
  std::vector<Rigid<T>> all_part_frames(const T* x) const;
  /// Which parts move when the parameters `varied` (indices into x) change: the child of every
  /// tree connection with a varied parameter, and everything below it.
  std::vector<char> parts_moved_by(const std::vector<int>& varied) const;
  /// all_part_frames(x), recomputing only the parts `moving` marks and taking the others from
  /// `fixed` (frames computed where x agrees with it on every parameter not varied): a solve
  /// of one of several independent groups then costs what the group costs.
  template <class T>
  std::vector<Rigid<T>> all_part_frames(const T* x,
                                        const std::vector<char>& moving,
                                        const std::vector<Rigid<double>>& fixed) const;
  /// World frame of connector `c` on a part at `part_frame`.
  template <class T>
  Rigid<T> connector_world(const Connector& c, const Rigid<T>& part_frame, const T* x) const;
  /// World frame of the part below tree connection `up`, whose parent part is at `parent`.
  template <class T>
  Rigid<T> child_frame(ConnectionId up, const Rigid<T>& parent, const T* x) const;
  /// World frames of a connection's two connector frames, the first including the
  /// alignment offset; equal when the connection is closed.
  template <class T>
  std::pair<Rigid<T>, Rigid<T>> connection_frames(ConnectionId id, const T* x) const;
  /// Same, from part frames computed by all_part_frames().
  template <class T>
  std::pair<Rigid<T>, Rigid<T>> connection_frames(ConnectionId id,
                                                  const std::vector<Rigid<T>>& frames,
                                                  const T* x) const;

  /// Available critical dimension of a primitive (§4.3); empty if it has none.
  std::vector<double> available_critical_dim(PartId id, PrimitiveId primitive) const;

  const std::optional<Target>& target() const { return target_; }
  /// The same design in its own placement, where it is verified and solved: the centre of its
  /// environments at the origin, the heading of the first of them (by name) along x, every
  /// environment's frame and the target's goal on a fine grid (the parameters, all relative
  /// to the parts, mean the same there). A design moved and turned as a whole about the
  /// vertical has the same own placement, number for number, so the solver's round-off, and
  /// with it which of several rest states a solve reaches, no longer follows where the world
  /// is. A one-rod environment spun about its rod's axis is spun back to where its frame's y
  /// axis (ψ = 0) points up, the angles ψ of the contacts on it read from there; every
  /// parameter's value is on a grid too. `centre` (optional) receives the world point placed at
  /// the origin, `shift` what was added to each parameter (ψ of those contacts; 0 elsewhere):
  /// the parameters there are the caller's plus `shift`, to the grid.
  Assembly in_own_placement(Vec3* centre = nullptr, std::vector<double>* shift = nullptr) const;
  /// Connections involving a primitive.
  std::vector<ConnectionId> connections_of(PartId id, PrimitiveId primitive) const;

  /// The order of connects says nothing physical, but it decides the model a solve works on
  /// (which connection closes each cycle, the configuration the verification closes them in)
  /// and so which of several rest states it reaches. This is the same design with its
  /// connects made again in one canonical order, whatever order they were made in: outwards
  /// from the environments, level by level (a connect is ready once one of its sides is in),
  /// and within a level by what the connect joins — each side by its part's type, primitive
  /// and the path from its environment down to it (environments by their type and
  /// primitives), with what the part coming in holds further down; connects that cannot be
  /// told apart that way go by the names their parts were given, and without names keep the
  /// order they were made in. A connect that closes a cycle has its sides in a canonical
  /// order too. Returns a copy of this assembly when it is in that
  /// order already, and also when a connect does not verify in the canonical order (a closure
  /// search that misses): then the order they were made in stands. `deadline` bounds the
  /// verification of the connects made again.
  Assembly in_canonical_order(
      std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt) const;
  /// The same connects made again in the canonical order and verified there, or none if a
  /// connect does not verify that way or `deadline` passes before the last. For connects that did
  /// not all verify in the order they were given (a closure search that missed): this assembly may
  /// then have been made with VerifyOptions::close_cycles off, its cycles open; the result's are
  /// closed. A chain between two rods, for one, is closed in its middle in the canonical order,
  /// from both rods at once. `reports`, when given, gets each connect's report from the canonical
  /// order, one per connect in the order they were made here.
  std::optional<Assembly> verified_in_canonical_order(
      std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt,
      std::vector<ConnectReport>* reports = nullptr) const;
  /// A connect as it was asked for.
  struct ConnectRequest {
    PrimitiveRef a, b;
    ConnectOptions options;
  };
  /// Whether the only errors in `why` are closure searches that missed their cycle
  /// (codes::kCycleNotClosable): what closed_in_canonical_order() may mend.
  static bool only_closure_misses(const Diagnostics& why);
  /// For connects whose closure search missed their cycle in the order they were given (and
  /// nothing else went wrong): this assembly with `missed` made too, their cycles left open,
  /// then every connect made again in the canonical order and verified there. Which order a
  /// file or a program makes its connects in, or which end of a cycle it builds first, must
  /// not decide whether a design holds together. None if a missed connect cannot be made even
  /// open, or the cycles do not close in the canonical order either.
  std::optional<Assembly> closed_in_canonical_order(
      const std::vector<ConnectRequest>& missed,
      std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt) const;
  /// Whether connection `id` has another way round (its alignment can flip).
  bool alignment_can_turn(ConnectionId id) const;
  /// This assembly with connection `id` made the other way round (its alignment turned:
  /// default ↔ flip; two hooks hung through each other the other way, a hook facing the other
  /// way on a rod), every connect made again in the order it was made and verified. None if
  /// that connection has no other way (its alignment cannot flip) or the design does not
  /// verify with it turned.
  std::optional<Assembly> with_alignment_turned(
      ConnectionId id,
      std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt) const;
  /// One connect of the canonical order: which (an index into connections()), and whether
  /// its two sides are given the other way round from how they were made (a connect that
  /// closes a cycle is made with its sides in a canonical order too: which comes first
  /// decides how the closure is parametrised, not what it means).
  struct CanonicalConnect {
    std::size_t index = 0;
    bool swapped = false;
  };
  /// The canonical order (above) of the connects made so far.
  std::vector<CanonicalConnect> canonical_connect_order() const;

 private:
  // connect(), step by step: which side is in, the rules, recording, the cycle checks.
  struct ConnectPlan {
    PrimitiveRef first;   ///< the primitive already in the assembly
    PrimitiveRef second;  ///< the new primitive (or the other end of a closing connect)
    PartId first_part;
    PartId second_part;  ///< for a new part: set once it joins the trial copy
    bool closes_cycle = false;
  };
  std::optional<ConnectPlan> plan_connect(const PrimitiveRef& a,
                                          const PrimitiveRef& b,
                                          const SourceLocation& where,
                                          Diagnostics& diags) const;
  bool check_connect_rules(const ConnectPlan& plan,
                           const std::string& l1,
                           const std::string& l2,
                           const SourceLocation& where,
                           Diagnostics& diags) const;
  ConnectionId record_connection(ConnectPlan& plan, const ConnectOptions& options);
  bool verify_closure(ConnectionId id, const ConnectOptions& options, ConnectReport& report);
  /// The adds, every connect in `order` (verified, cycles closed) and the target, made again;
  /// none if one of them is refused. `reports` (if given) gets each connect's report at its
  /// index among connects_made_.
  std::optional<Assembly> made_in(const std::vector<CanonicalConnect>& order,
                                  std::optional<std::chrono::steady_clock::time_point> deadline,
                                  std::vector<ConnectReport>* reports = nullptr) const;

  struct PrimitiveState {
    std::vector<double> available;  ///< available critical dimension
    int connections = 0;
  };

  PartId insert_part(const std::shared_ptr<Part>& part,
                     bool environment,
                     const Frame& frame,
                     PartId parent_part = {},
                     ConnectionId parent = {});
  Connector make_connector(PartId part, PrimitiveId primitive, std::vector<ParamSpec> params);

  std::vector<PartNode> parts_;
  KinematicGraph graph_;
  std::vector<std::vector<PrimitiveState>> primitive_state_;
  std::vector<Connection> connections_;
  std::vector<ParamInfo> params_;
  std::vector<double> values_;
  std::optional<Target> target_;
  // What was added and connected, as it was asked for, for in_canonical_order() to make
  // again: every accepted add(), and every accepted connect() (the i-th is connection i).
  struct AddCall {
    std::shared_ptr<Part> part;
    std::optional<PrimitiveRef> primitive;  ///< add(primitive, frame)
    Frame frame;
    SourceLocation where;
  };
  std::vector<AddCall> adds_;
  std::vector<ConnectRequest> connects_made_;
};

// ---- templates ---------------------------------------------------------------------------

template <class T>
Rigid<T> Assembly::connector_world(const Connector& c, const Rigid<T>& frame, const T* x) const {
  const Primitive& p = parts_[c.part.index()].part->primitive(c.primitive);
  Rigid<T> m = frame.then(c.base);
  apply_connector<T>(p.connector_kind(), p.shape, x + c.offset, m);
  return m;
}

template <class T>
Rigid<T> Assembly::child_frame(ConnectionId up, const Rigid<T>& parent, const T* x) const {
  const Connection& c = connections_[up.index()];
  const Primitive& child = parts_[c.second.part.index()].part->primitive(c.second.primitive);
  // Q = P · C_first · A · C_second⁻¹
  Rigid<T> child_connector = c.second.base.template cast<T>();
  apply_connector<T>(child.connector_kind(), child.shape, x + c.second.offset, child_connector);
  return connector_world<T>(c.first, parent, x).then(c.offset_rigid) * child_connector.inverse();
}

template <class T>
Rigid<T> Assembly::part_frame(PartId id, const T* x) const {
  const ConnectionId up = graph_.parent_edge(id);
  if (!up.valid()) return parts_[id.index()].placement.template cast<T>();
  return child_frame<T>(up, part_frame<T>(connections_[up.index()].first.part, x), x);
}

template <class T>
std::vector<Rigid<T>> Assembly::all_part_frames(const T* x) const {
  std::vector<Rigid<T>> out;
  out.reserve(parts_.size());
  // Parents always precede children in insertion order.
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    const ConnectionId up = graph_.parent_edge(PartId{static_cast<int>(i)});
    out.push_back(up.valid()
                      ? child_frame<T>(up, out[connections_[up.index()].first.part.index()], x)
                      : parts_[i].placement.template cast<T>());
  }
  return out;
}

template <class T>
std::vector<Rigid<T>> Assembly::all_part_frames(const T* x,
                                                const std::vector<char>& moving,
                                                const std::vector<Rigid<double>>& fixed) const {
  std::vector<Rigid<T>> out;
  out.reserve(parts_.size());
  // Parents always precede children in insertion order.
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    // A moving part always hangs from a tree connection (parts_moved_by).
    const ConnectionId up = graph_.parent_edge(PartId{static_cast<int>(i)});
    out.push_back(moving[i]
                      ? child_frame<T>(up, out[connections_[up.index()].first.part.index()], x)
                      : fixed[i].template cast<T>());
  }
  return out;
}

template <class T>
std::pair<Rigid<T>, Rigid<T>> Assembly::connection_frames(ConnectionId id,
                                                          const std::vector<Rigid<T>>& frames,
                                                          const T* x) const {
  const Connection& c = connections_[id.index()];
  return {connector_world<T>(c.first, frames[c.first.part.index()], x).then(c.offset_rigid),
          connector_world<T>(c.second, frames[c.second.part.index()], x)};
}

template <class T>
std::pair<Rigid<T>, Rigid<T>> Assembly::connection_frames(ConnectionId id, const T* x) const {
  const Connection& c = connections_[id.index()];
  const Rigid<T> first =
      connector_world<T>(c.first, part_frame<T>(c.first.part, x), x).then(c.offset_rigid);
  const Rigid<T> second = connector_world<T>(c.second, part_frame<T>(c.second.part, x), x);
  return {first, second};
}

}  // namespace fabkit::hacks
