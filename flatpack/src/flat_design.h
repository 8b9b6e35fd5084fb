#pragma once
// A design with its sub-designs expanded (paper §4.2.2 model reconstruction): every component,
// constraint and connection in one list, names prefixed by the instance path ("desk.top.l"),
// and every quantity (parameter or component dimension) numbered for the solver.
#include <muParser.h>

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/flatpack/design.h"

namespace fabkit::flatpack::detail {

struct FlatQuantity {
  std::string name;
  ParamKind kind = ParamKind::kLength;
  std::optional<double> default_value;
  double min = -1e300, max = 1e300;
  bool exclusive_min = false;
  int component = -1;  ///< the component it is a dimension of; -1 for a design parameter
  bool meta = false;
  /// The built-in `thickness` of a design's scope: its material's board thickness, read-only.
  bool material_thickness = false;
  SourceLocation where;
};

struct FlatComponent {
  std::string name;
  const ComponentType* type = nullptr;
  const ComponentUse* use = nullptr;
  std::string scope;  ///< "desk." for a component of the instance "desk"
  Material material;
  std::map<std::string, int> params;  ///< parameter → quantity index
};

struct FlatConstraint {
  Expression lhs, rhs;
  std::string scope;
  SourceLocation where;
  std::string text;
  bool own = false;  ///< a component type's own constraint (square: w = l)
};

struct FlatConnection {
  const Connection* spec = nullptr;
  std::string name;
  std::string scope;
  int a = -1, b = -1;
  std::string a_edge, b_edge;
  std::string text;
};

struct FlatDesign {
  std::vector<FlatQuantity> quantities;
  std::map<std::string, int> quantity_index;
  std::vector<FlatComponent> components;
  std::map<std::string, int> component_index;
  std::vector<FlatConstraint> constraints;
  std::vector<FlatConnection> connections;
};

/// Expands `design`; false (with diagnostics) on unknown types, names or cycles of `uses`.
bool flatten(const Design& design, FlatDesign& flat, Diagnostics& diags, int max_components);

/// Expressions over the quantities, each compiled once (muParser) and evaluated on `values`.
class Expressions {
 public:
  Expressions(const FlatDesign& flat, std::vector<double>& values);
  /// Compiles `e` in `scope`; -1 with a diagnostic (unknown name with did-you-mean, syntax).
  /// The same text in the same scope is compiled once (a muParser costs tens of microseconds
  /// to build, and check() solves the design again for every meta-parameter).
  int compile(const Expression& e, const std::string& scope, Diagnostics& diags);
  /// NaN if the evaluation fails (division by zero gives inf, also reported by callers).
  double evaluate(int id) const;
  const std::vector<int>& used(int id) const { return used_[id]; }

 private:
  const FlatDesign& flat_;
  std::vector<double>& values_;
  std::vector<std::unique_ptr<mu::Parser>> parsers_;
  std::vector<std::vector<int>> used_;
  std::unordered_map<std::string, int> compiled_;  ///< scope + '\n' + text → id
};

/// Solves every quantity (linear constraints by an Eigen rank-revealing solve, nonlinear ones by
/// Newton, defaults for what stays free); names free and conflicting quantities on failure.
/// Past `deadline` (checked per constraint compiled) it stops with a time-limit error.
bool solve_quantities(const FlatDesign& flat,
                      Expressions& expressions,
                      std::vector<double>& values,
                      Diagnostics& diags,
                      std::optional<std::chrono::steady_clock::time_point> deadline = {});

}  // namespace fabkit::flatpack::detail
