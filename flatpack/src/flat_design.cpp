// Expanding sub-designs, compiling expressions (muParser) and solving the constraints: linear
// ones with Eigen (rank-revealing, so free and conflicting quantities can be named), nonlinear
// ones with one unknown by Newton.
#include "flat_design.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>

#include "fabkit/core/stop_clock.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/flatpack/diagnostic_codes.h"

namespace fabkit::flatpack::detail {
namespace {

struct Flattener {
  FlatDesign& flat;
  Diagnostics& diags;
  int max_components;
  std::vector<const Design*> stack;

  int add_quantity(FlatQuantity q) {
    const auto it = flat.quantity_index.find(q.name);
    if (it != flat.quantity_index.end()) return it->second;
    const int id = static_cast<int>(flat.quantities.size());
    flat.quantity_index[q.name] = id;
    flat.quantities.push_back(std::move(q));
    return id;
  }

  static const Material* find_material(const Design& d, const std::string& name) {
    if (d.material.name == name) return &d.material;
    for (const Material& m : d.materials) {
      if (m.name == name) return &m;
    }
    return nullptr;
  }

  // Resolves "comp.edge" in `scope` of design `d` through exported interfaces of sub-designs.
  bool resolve_edge(const Design& d,
                    const std::string& scope,
                    const std::string& component,
                    const std::string& edge,
                    const SourceLocation& where,
                    int& out_component,
                    std::string& out_edge) {
    const std::string full = scope + component;
    const auto it = flat.component_index.find(full);
    if (it != flat.component_index.end()) {
      const FlatComponent& c = flat.components[it->second];
      const std::vector<std::string>& names = c.type->takes_points && !c.use->edge_names.empty()
                                                  ? c.use->edge_names
                                                  : c.type->edge_names;
      if (!c.type->takes_points && c.type->name != "RegularPolygon" && c.type->name != "Disc" &&
          std::find(names.begin(), names.end(), edge) == names.end()) {
        diags.error(codes::kUnknownEdge,
                    fmt::format("{} ({}) has no edge '{}'{}; its edges are {}",
                                full,
                                c.type->name,
                                edge,
                                did_you_mean(edge, names),
                                fmt::join(names, ", ")),
                    where);
        return false;
      }
      out_component = it->second;
      out_edge = edge;
      return true;
    }
    // A sub-design: follow its exported interface.
    for (const ComponentUse& use : d.components) {
      if (use.name != component) continue;
      const auto sub = d.library.find(use.type);
      if (sub == d.library.end()) break;
      const auto iface = sub->second->interfaces.find(edge);
      if (iface == sub->second->interfaces.end()) {
        std::vector<std::string> names;
        for (const auto& [n, _] : sub->second->interfaces) names.push_back(n);
        diags.error(codes::kUnknownEdge,
                    fmt::format("{} ({}) exports no interface '{}'{}; it exports {}",
                                full,
                                use.type,
                                edge,
                                did_you_mean(edge, names),
                                names.empty() ? std::string("none (add interfaces: to it)")
                                              : fmt::format("{}", fmt::join(names, ", "))),
                    where);
        return false;
      }
      const std::string& target = iface->second;
      const auto dot = target.rfind('.');
      return resolve_edge(*sub->second,
                          full + ".",
                          target.substr(0, dot),
                          target.substr(dot + 1),
                          where,
                          out_component,
                          out_edge);
    }
    std::vector<std::string> names;
    for (const ComponentUse& use : d.components) names.push_back(use.name);
    diags.error(codes::kUnknownComponent,
                fmt::format("no component '{}'{} in {}",
                            component,
                            did_you_mean(component, names),
                            d.name.empty() ? "the design" : d.name),
                where);
    return false;
  }

  bool expand(const Design& d, const std::string& scope, const Material& inherited) {
    if (std::find(stack.begin(), stack.end(), &d) != stack.end()) {
      diags.error(codes::kInvalidValue, fmt::format("design '{}' uses itself", d.name));
      return false;
    }
    stack.push_back(&d);
    bool ok = true;
    // `thickness` in expressions is the board thickness of this design's material (a
    // parameter of that name takes precedence), so offsets can be written as "height +
    // thickness / 2" and stay right when the design is cut from another material.
    const bool own_thickness =
        std::any_of(d.parameters.begin(), d.parameters.end(), [](const DesignParameter& p) {
          return p.name == "thickness";
        });
    if (!own_thickness) {
      FlatQuantity t{scope + "thickness",
                     ParamKind::kLength,
                     inherited.thickness_mm,
                     0,
                     1e300,
                     true,
                     -1,
                     false,
                     true,
                     {}};
      add_quantity(std::move(t));
    }
    for (const DesignParameter& p : d.parameters) {
      add_quantity({scope + p.name,
                    p.kind,
                    p.value,
                    -1e300,
                    1e300,
                    false,
                    -1,
                    p.meta && scope.empty(),
                    false,
                    p.where});
    }
    for (const ComponentUse& use : d.components) {
      Material material = inherited;
      if (!use.material.empty()) {
        const Material* m = nullptr;
        for (std::size_t k = stack.size(); k-- > 0 && !m;)
          m = find_material(*stack[k], use.material);
        if (!m) {
          std::vector<std::string> names{d.material.name};
          for (const Material& mm : d.materials) names.push_back(mm.name);
          diags.error(codes::kUnknownName,
                      fmt::format("{}: no material '{}'{}",
                                  use.name,
                                  use.material,
                                  did_you_mean(use.material, names)),
                      use.where);
          ok = false;
          continue;
        }
        material = *m;
      }
      const std::string full = scope + use.name;
      if (const auto sub = d.library.find(use.type); sub != d.library.end()) {
        ok = expand(*sub->second, full + ".", material) && ok;
        for (const auto& [param, expr] : use.params) {
          // A sub-design's parameters are set by name (a dimension can be set as "seat.l").
          const Design& used = *sub->second;
          const bool known = param.find('.') != std::string::npos || param == "thickness" ||
                             std::any_of(used.parameters.begin(),
                                         used.parameters.end(),
                                         [&name = param](const DesignParameter& p) {
                                           return p.name == name;  // (clang 14: no binding capture)
                                         });
          if (!known) {
            std::vector<std::string> names;
            for (const DesignParameter& p : used.parameters) names.push_back(p.name);
            diags.error(codes::kUnknownName,
                        fmt::format("{} ({}) has no parameter '{}'{}; its parameters are {}",
                                    full,
                                    use.type,
                                    param,
                                    did_you_mean(param, names),
                                    names.empty() ? std::string("none")
                                                  : fmt::format("{}", fmt::join(names, ", "))),
                        expr.where);
            ok = false;
            continue;
          }
          flat.constraints.push_back({Expression{use.name + "." + param, expr.where},
                                      expr,
                                      scope,
                                      expr.where,
                                      fmt::format("{}.{} = {}", full, param, expr.text),
                                      false});
        }
        continue;
      }
      const ComponentType* type = ComponentLibrary::builtin().find(use.type);
      if (!type) {
        std::vector<std::string> names = ComponentLibrary::builtin().names();
        for (const auto& [n, _] : d.library) names.push_back(n);
        diags.error(codes::kUnknownComponent,
                    fmt::format("{}: unknown component type '{}'{}; known: {}",
                                use.name,
                                use.type,
                                did_you_mean(use.type, names),
                                fmt::join(names, ", ")),
                    use.where);
        ok = false;
        continue;
      }
      if (static_cast<int>(flat.components.size()) >= max_components) {
        diags.error(codes::kLimitExceeded,
                    fmt::format("more than {} components", max_components),
                    use.where);
        stack.pop_back();
        return false;
      }
      if (flat.component_index.count(full)) {
        diags.error(
            codes::kDuplicateName, fmt::format("two components are named '{}'", full), use.where);
        ok = false;
        continue;
      }
      FlatComponent c;
      c.name = full;
      c.type = type;
      c.use = &use;
      c.scope = scope;
      c.material = material;
      const int index = static_cast<int>(flat.components.size());
      for (const ParamSpec& p : type->params) {
        c.params[p.name] = add_quantity({full + "." + p.name,
                                         p.kind,
                                         p.default_value,
                                         p.min,
                                         p.max,
                                         p.exclusive_min,
                                         index,
                                         false,
                                         false,
                                         use.where});
      }
      for (const auto& [param, expr] : use.params) {
        if (!type->param(param)) {
          std::vector<std::string> names;
          for (const ParamSpec& p : type->params) names.push_back(p.name);
          diags.error(codes::kUnknownName,
                      fmt::format("{} ({}) has no parameter '{}'{}; its parameters are {}",
                                  full,
                                  type->name,
                                  param,
                                  did_you_mean(param, names),
                                  names.empty() ? std::string("none")
                                                : fmt::format("{}", fmt::join(names, ", "))),
                      expr.where);
          ok = false;
          continue;
        }
        flat.constraints.push_back({Expression{use.name + "." + param, expr.where},
                                    expr,
                                    scope,
                                    expr.where,
                                    fmt::format("{}.{} = {}", full, param, expr.text),
                                    false});
      }
      for (const auto& [lhs, rhs] : type->constraints) {
        flat.constraints.push_back(
            {Expression{lhs, use.where},
             Expression{rhs, use.where},
             full + ".",
             use.where,
             fmt::format("{}.{} = {} ({}'s own)", full, lhs, rhs, type->name),
             true});
      }
      flat.component_index[full] = index;
      flat.components.push_back(std::move(c));
    }
    for (const Constraint& c : d.constraints) {
      flat.constraints.push_back({c.lhs, c.rhs, scope, c.where, c.text(), false});
    }
    int number = 0;
    for (const Connection& c : d.connections) {
      ++number;
      FlatConnection fc;
      fc.spec = &c;
      fc.scope = scope;
      fc.name = scope + (c.name.empty() ? fmt::format("c{}", number) : c.name);
      fc.text = fmt::format("{} {}", fc.name, c.text());
      if (!resolve_edge(d, scope, c.a_component, c.a_edge, c.where, fc.a, fc.a_edge) ||
          !resolve_edge(d, scope, c.b_component, c.b_edge, c.where, fc.b, fc.b_edge)) {
        ok = false;
        continue;
      }
      if (fc.a == fc.b) {
        diags.error(codes::kInvalidValue,
                    fmt::format("{} connects {} to itself", fc.name, flat.components[fc.a].name),
                    c.where);
        ok = false;
        continue;
      }
      flat.connections.push_back(std::move(fc));
    }
    stack.pop_back();
    return ok;
  }
};

// Own constraints are written in the component's scope ("w = l" inside A means A.w = A.l):
// own lhs was already prefixed, so the scope resolves its rhs.
}  // namespace

bool flatten(const Design& design, FlatDesign& flat, Diagnostics& diags, int max_components) {
  Flattener f{flat, diags, max_components, {}};
  return f.expand(design, "", design.material);
}

Expressions::Expressions(const FlatDesign& flat, std::vector<double>& values)
    : flat_(flat), values_(values) {}

namespace {
double* factory_slot(const char*, void* user) {
  auto* pool = static_cast<std::vector<std::unique_ptr<double>>*>(user);
  pool->push_back(std::make_unique<double>(0.0));
  return pool->back().get();
}
double sind(double x) {
  return std::sin(x * M_PI / 180);
}
double cosd(double x) {
  return std::cos(x * M_PI / 180);
}
double tand(double x) {
  return std::tan(x * M_PI / 180);
}
constexpr const char* kNameChars =
    "0123456789_.abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ";
}  // namespace

int Expressions::compile(const Expression& e, const std::string& scope, Diagnostics& diags) {
  std::string key = scope + '\n' + e.text;
  if (const auto it = compiled_.find(key); it != compiled_.end()) return it->second;
  auto parser = std::make_unique<mu::Parser>();
  std::vector<std::unique_ptr<double>> pool;
  std::vector<int> used;
  try {
    parser->DefineNameChars(kNameChars);
    parser->DefineFun("sind", sind);
    parser->DefineFun("cosd", cosd);
    parser->DefineFun("tand", tand);
    parser->SetVarFactory(factory_slot, &pool);
    parser->SetExpr(e.text.empty() ? std::string("0") : e.text);
    const mu::varmap_type vars = parser->GetUsedVar();
    for (const auto& [name, _] : vars) {
      const auto it = flat_.quantity_index.find(scope + name);
      if (it == flat_.quantity_index.end()) {
        std::vector<std::string> names;
        for (const auto& [n, __] : flat_.quantity_index) {
          if (n.rfind(scope, 0) == 0) names.push_back(n.substr(scope.size()));
        }
        diags.error(codes::kUnknownName,
                    fmt::format("'{}' in '{}' is neither a parameter nor a component dimension{}",
                                name,
                                e.text,
                                did_you_mean(name, names)),
                    e.where);
        return -1;
      }
      parser->DefineVar(name, &values_[static_cast<std::size_t>(it->second)]);
      used.push_back(it->second);
    }
    parser->Eval();  // finds syntax errors the parse above did not
  } catch (const mu::Parser::exception_type& ex) {
    diags.error(codes::kBadExpression,
                fmt::format("cannot read the expression '{}': {}", e.text, ex.GetMsg()),
                e.where);
    return -1;
  }
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  parsers_.push_back(std::move(parser));
  used_.push_back(std::move(used));
  const int id = static_cast<int>(parsers_.size()) - 1;
  compiled_.emplace(std::move(key), id);
  return id;
}

double Expressions::evaluate(int id) const {
  try {
    return parsers_[static_cast<std::size_t>(id)]->Eval();
  } catch (const mu::Parser::exception_type&) {
    return std::nan("");
  }
}

namespace {

std::string unit_of(ParamKind k) {
  return k == ParamKind::kLength ? " mm" : k == ParamKind::kAngle ? "°" : "";
}

}  // namespace

bool solve_quantities(const FlatDesign& flat,
                      Expressions& ex,
                      std::vector<double>& values,
                      Diagnostics& diags,
                      std::optional<std::chrono::steady_clock::time_point> deadline) {
  const std::size_t n = flat.quantities.size();
  struct Row {
    int lhs = -1, rhs = -1;
    std::vector<int> used;
    const FlatConstraint* c = nullptr;
    bool active = true;
  };
  std::vector<Row> rows;
  bool ok = true;
  std::set<int>
      lhs_named;  // quantities a constraint names alone on its left: defaults do not apply
  std::size_t compiled = 0;
  for (const FlatConstraint& c : flat.constraints) {
    // Compiling is most of a first solve (tens of microseconds an expression).
    if (deadline_passed(deadline)) {
      diags.error(codes::kTimeLimit,
                  fmt::format("stopped at the deadline after compiling {} of {} constraints; the "
                              "dimensions, shapes, placement, joints and the assembly order were "
                              "not done",
                              compiled,
                              flat.constraints.size()));
      return false;
    }
    ++compiled;
    Row r;
    r.c = &c;
    r.lhs = ex.compile(c.lhs, c.scope, diags);
    r.rhs = ex.compile(c.rhs, c.scope, diags);
    if (r.lhs < 0 || r.rhs < 0) {
      ok = false;
      continue;
    }
    std::set_union(ex.used(r.lhs).begin(),
                   ex.used(r.lhs).end(),
                   ex.used(r.rhs).begin(),
                   ex.used(r.rhs).end(),
                   std::back_inserter(r.used));
    if (const auto it = flat.quantity_index.find(c.scope + c.lhs.text);
        it != flat.quantity_index.end()) {
      if (flat.quantities[static_cast<std::size_t>(it->second)].material_thickness) {
        diags.error(
            codes::kInvalidValue,
            fmt::format("'{}': {} is the board thickness of the material ({:g} mm) and "
                        "cannot be constrained; set it with material: {{thickness: ...}}",
                        c.text,
                        flat.quantities[static_cast<std::size_t>(it->second)].name,
                        *flat.quantities[static_cast<std::size_t>(it->second)].default_value),
            c.where);
        ok = false;
        continue;
      }
      lhs_named.insert(it->second);
    }
    rows.push_back(std::move(r));
  }
  if (!ok) return false;

  std::vector<char> known(n, 0);
  values.assign(n, 1.0);
  for (std::size_t q = 0; q < n; ++q) {
    if (flat.quantities[q].default_value && !lhs_named.count(static_cast<int>(q))) {
      values[q] = *flat.quantities[q].default_value;
      known[q] = 1;
    } else if (flat.quantities[q].default_value) {
      values[q] = *flat.quantities[q].default_value;  // a good start for Newton
    } else {
      values[q] = 100;  // a furniture-sized start for Newton
    }
  }
  auto residual = [&](const Row& r) { return ex.evaluate(r.lhs) - ex.evaluate(r.rhs); };
  auto scale_of = [&](const Row& r) {
    return std::max({1.0, std::abs(ex.evaluate(r.lhs)), std::abs(ex.evaluate(r.rhs))});
  };
  auto unknowns_of = [&](const Row& r) {
    std::vector<int> u;
    for (int q : r.used) {
      if (!known[static_cast<std::size_t>(q)]) u.push_back(q);
    }
    return u;
  };
  // Gradient over `unknowns` by central differences (exact for affine functions).
  auto gradient = [&](const Row& r, const std::vector<int>& unknowns) {
    Eigen::VectorXd g(static_cast<Eigen::Index>(unknowns.size()));
    for (std::size_t k = 0; k < unknowns.size(); ++k) {
      double& v = values[static_cast<std::size_t>(unknowns[k])];
      const double v0 = v, h = 1e-3 * std::max(1.0, std::abs(v0));
      v = v0 + h;
      const double up = residual(r);
      v = v0 - h;
      const double down = residual(r);
      v = v0;
      g[static_cast<Eigen::Index>(k)] = (up - down) / (2 * h);
    }
    return g;
  };
  auto is_linear = [&](const Row& r, const std::vector<int>& unknowns) {
    const Eigen::VectorXd g0 = gradient(r, unknowns);
    const double r0 = residual(r);
    std::vector<double> saved;
    for (std::size_t k = 0; k < unknowns.size(); ++k) {
      double& v = values[static_cast<std::size_t>(unknowns[k])];
      saved.push_back(v);
      v += 0.37 * (1 + std::abs(v)) * static_cast<double>(k % 3 + 1);
    }
    const Eigen::VectorXd g1 = gradient(r, unknowns);
    double predicted = r0;
    for (std::size_t k = 0; k < unknowns.size(); ++k) {
      predicted += g0[static_cast<Eigen::Index>(k)] *
                   (values[static_cast<std::size_t>(unknowns[k])] - saved[k]);
    }
    const double r1 = residual(r);
    for (std::size_t k = 0; k < unknowns.size(); ++k)
      values[static_cast<std::size_t>(unknowns[k])] = saved[k];
    const double tol = 1e-7 * std::max({1.0, std::abs(r0), std::abs(r1), g0.cwiseAbs().maxCoeff()});
    return std::isfinite(r1) && std::abs(r1 - predicted) <= tol &&
           (g1 - g0).cwiseAbs().maxCoeff() <= tol;
  };
  auto set_known = [&](int q, double v) {
    values[static_cast<std::size_t>(q)] = v;
    known[static_cast<std::size_t>(q)] = 1;
  };

  bool progress = true;
  while (progress && ok) {
    progress = false;
    // 1. Constraints with nothing unknown must hold; with one unknown, solve them directly.
    std::vector<std::size_t> linear_rows;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      Row& r = rows[i];
      if (!r.active) continue;
      const std::vector<int> u = unknowns_of(r);
      if (u.empty()) {
        r.active = false;
        const double res = residual(r);
        if (!(std::abs(res) <= 1e-6 * scale_of(r))) {
          diags.error(
              codes::kOverConstrained,
              fmt::format("over-constrained: '{}' does not hold once the other constraints are met "
                          "(left side {:g}, right side {:g}); remove it or the constraint it "
                          "contradicts",
                          r.c->text,
                          ex.evaluate(r.lhs),
                          ex.evaluate(r.rhs)),
              r.c->where);
          ok = false;
        }
        continue;
      }
      if (u.size() == 1) {
        const int q = u[0];
        if (is_linear(r, u)) {
          const double g = gradient(r, u)[0];
          if (std::abs(g) > 1e-12) {
            set_known(q, values[static_cast<std::size_t>(q)] - residual(r) / g);
            r.active = false;
            progress = true;
            continue;
          }
        } else {
          // Newton from the current guess (a default, or 100 mm).
          double& v = values[static_cast<std::size_t>(q)];
          bool converged = false;
          for (int it = 0; it < 60 && !converged; ++it) {
            const double res = residual(r);
            if (!std::isfinite(res)) break;
            if (std::abs(res) <= 1e-10 * scale_of(r)) {
              converged = true;
              break;
            }
            const double g = gradient(r, u)[0];
            if (!(std::abs(g) > 1e-14)) break;
            double step = res / g;
            // Keep positive sizes positive: halve steps that would cross zero.
            const FlatQuantity& fq = flat.quantities[static_cast<std::size_t>(q)];
            while (fq.exclusive_min && v - step <= fq.min && std::abs(step) > 1e-12) step /= 2;
            v -= step;
          }
          if (converged) {
            known[static_cast<std::size_t>(q)] = 1;
            r.active = false;
            progress = true;
          }
          continue;
        }
      }
      if (is_linear(r, u)) linear_rows.push_back(i);
    }
    if (progress || !ok) continue;
    // 2. The linear constraints together: a rank-revealing solve decides which unknowns they fix.
    if (linear_rows.empty()) break;
    std::vector<int> columns;
    for (std::size_t i : linear_rows) {
      for (int q : unknowns_of(rows[i])) columns.push_back(q);
    }
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    const auto m = static_cast<Eigen::Index>(linear_rows.size());
    const auto k = static_cast<Eigen::Index>(columns.size());
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, k);
    Eigen::VectorXd b(m);
    for (Eigen::Index i = 0; i < m; ++i) {
      const Row& r = rows[linear_rows[static_cast<std::size_t>(i)]];
      const std::vector<int> u = unknowns_of(r);
      const Eigen::VectorXd g = gradient(r, u);
      double rhs = -residual(r);
      for (std::size_t j = 0; j < u.size(); ++j) {
        const auto col = std::lower_bound(columns.begin(), columns.end(), u[j]) - columns.begin();
        A(i, col) = g[static_cast<Eigen::Index>(j)];
        rhs += g[static_cast<Eigen::Index>(j)] * values[static_cast<std::size_t>(u[j])];
      }
      b[i] = rhs;
    }
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
    const Eigen::VectorXd x = cod.solve(b);
    const Eigen::VectorXd e = A * x - b;
    std::vector<std::string> conflicting;
    const SourceLocation* first_where = nullptr;
    for (Eigen::Index i = 0; i < m; ++i) {
      const Row& r = rows[linear_rows[static_cast<std::size_t>(i)]];
      if (std::abs(e[i]) > 1e-6 * std::max(1.0, std::abs(b[i]))) {
        conflicting.push_back(
            fmt::format("'{}'{}",
                        r.c->text,
                        r.c->where.line ? fmt::format(" (line {})", r.c->where.line) : ""));
        if (!first_where) first_where = &r.c->where;
      }
    }
    if (!conflicting.empty()) {
      diags.error(
          codes::kOverConstrained,
          fmt::format(
              "over-constrained: these constraints contradict each other: {}; remove one of them",
              fmt::join(conflicting, ", ")),
          *first_where);
      ok = false;
      break;
    }
    const Eigen::MatrixXd kernel = Eigen::FullPivLU<Eigen::MatrixXd>(A).kernel();
    const bool full_rank = cod.rank() == k;
    for (Eigen::Index j = 0; j < k; ++j) {
      if (full_rank || kernel.row(j).cwiseAbs().maxCoeff() < 1e-9) {
        set_known(columns[static_cast<std::size_t>(j)], x[j]);
        progress = true;
      }
    }
  }
  if (!ok) return false;
  // 3. What is still free is under-constrained: name it and where it appears.
  std::vector<std::string> free_names;
  for (std::size_t q = 0; q < n; ++q) {
    if (known[q]) continue;
    const FlatQuantity& fq = flat.quantities[q];
    std::vector<std::string> in;
    for (const Row& r : rows) {
      if (r.active &&
          std::find(r.used.begin(), r.used.end(), static_cast<int>(q)) != r.used.end()) {
        in.push_back("'" + r.c->text + "'");
      }
    }
    free_names.push_back(in.empty() ? fq.name
                                    : fmt::format("{} (in {})", fq.name, fmt::join(in, ", ")));
  }
  if (!free_names.empty()) {
    std::size_t first_free = 0;
    while (first_free < n && known[first_free]) ++first_free;
    const FlatQuantity& first = flat.quantities[first_free];
    diags.error(
        codes::kUnderConstrained,
        fmt::format(
            "under-constrained: nothing determines {}; add a constraint such as '{} = <value>'",
            fmt::join(free_names, ", "),
            first.name),
        first.where);
    return false;
  }
  // 4. Values must make sense for their kind and range.
  for (std::size_t q = 0; q < n; ++q) {
    const FlatQuantity& fq = flat.quantities[q];
    const double v = values[q];
    if (!std::isfinite(v)) {
      diags.error(
          codes::kInvalidValue, fmt::format("{} is not a finite number", fq.name), fq.where);
      ok = false;
    } else if (fq.kind == ParamKind::kCount && std::abs(v - std::round(v)) > 1e-9) {
      diags.error(codes::kInvalidValue,
                  fmt::format("{} = {:g} must be a whole number", fq.name, v),
                  fq.where);
      ok = false;
    } else if ((fq.exclusive_min && v <= fq.min) || v < fq.min || v > fq.max) {
      diags.error(
          codes::kBadShape,
          fmt::format("{} = {:g}{} is out of range ({} {:g}{}{})",
                      fq.name,
                      v,
                      unit_of(fq.kind),
                      fq.exclusive_min ? "must be more than" : "at least",
                      fq.min,
                      unit_of(fq.kind),
                      fq.max < 1e299 ? fmt::format(", at most {:g}", fq.max) : std::string()),
          fq.where);
      ok = false;
    }
  }
  return ok;
}

}  // namespace fabkit::flatpack::detail
