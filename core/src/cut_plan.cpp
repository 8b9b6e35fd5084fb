// 1D stock cutting: first fit over seeded orderings, then the Gilmore–Gomory pattern program
// solved with GLPK (column generation for the bound, the integer master for the plan). GLPK is
// included here only.
#include "fabkit/core/cut_plan.h"

#include <fmt/format.h>
#include <glpk.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>

#include "fabkit/core/text.h"

namespace fabkit {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// Pieces that fit "exactly" must fit despite rounding in the sums (mm).
double fit_tolerance(double capacity) {
  return 1e-9 + 1e-12 * capacity;
}

using Bins = std::vector<std::vector<int>>;  // piece indices per stock piece

// First fit of the pieces in `order`: each goes into the first stock piece it fits.
Bins first_fit(const std::vector<int>& order,
               const std::vector<double>& size,
               double capacity,
               std::vector<double>& load) {
  Bins bins;
  load.clear();
  const double tol = fit_tolerance(capacity);
  for (const int i : order) {
    const double s = size[static_cast<std::size_t>(i)];
    std::size_t b = 0;
    while (b < bins.size() && load[b] + s > capacity + tol) ++b;
    if (b == bins.size()) {
      bins.emplace_back();
      load.push_back(0);
    }
    bins[b].push_back(i);
    load[b] += s;
  }
  return bins;
}

// Of two plans with the same count, the one with the most uneven fill leaves its offcut in
// fewer, longer pieces (more useful to a maker).
double fill_spread(const std::vector<double>& load) {
  double s = 0;
  for (const double l : load) s += l * l;
  return s;
}

struct PieceType {
  double size = 0;          // ℓ + kerf
  std::vector<int> pieces;  // indices of the pieces of this size
};

// Exact bounded knapsack for pricing: maximise Σ value·z subject to Σ size·z ≤ capacity,
// 0 ≤ z ≤ demand, by depth-first branch and bound with the fractional bound. `node_limit`
// keeps it bounded; `exact` says whether the search finished.
struct Knapsack {
  const std::vector<double>& value;
  const std::vector<double>& size;
  const std::vector<int>& demand;
  double capacity;
  std::vector<int> order;  // types by value density, best first
  std::vector<int> z, best_z;
  double best = 0;
  long long nodes = 0;
  long long node_limit = 2'000'000;
  bool exact = true;

  Knapsack(const std::vector<double>& v,
           const std::vector<double>& s,
           const std::vector<int>& d,
           double c)
      : value(v), size(s), demand(d), capacity(c) {
    for (std::size_t t = 0; t < v.size(); ++t) {
      if (v[t] > 1e-12) order.push_back(static_cast<int>(t));
    }
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return v[static_cast<std::size_t>(a)] / s[static_cast<std::size_t>(a)] >
             v[static_cast<std::size_t>(b)] / s[static_cast<std::size_t>(b)];
    });
    z.assign(v.size(), 0);
    best_z = z;
  }

  double bound(std::size_t k, double room, double val) const {
    for (; k < order.size(); ++k) {
      const auto t = static_cast<std::size_t>(order[k]);
      const double take = std::min(static_cast<double>(demand[t]), room / size[t]);
      val += take * value[t];
      room -= take * size[t];
      if (room <= 0) break;
    }
    return val;
  }

  void search(std::size_t k, double room, double val) {
    if (++nodes > node_limit) {
      exact = false;
      return;
    }
    if (val > best + 1e-12) {
      best = val;
      best_z = z;
    }
    if (k == order.size() || bound(k, room, val) <= best + 1e-12) return;
    const auto t = static_cast<std::size_t>(order[k]);
    const double tol = fit_tolerance(capacity);
    const int most = std::min(demand[t], static_cast<int>(std::floor((room + tol) / size[t])));
    for (int n = most; n >= 0 && exact; --n) {
      z[t] = n;
      search(k + 1, room - n * size[t], val + n * value[t]);
    }
    z[t] = 0;
  }

  double solve() {
    search(0, capacity, 0);
    return best;
  }
};

struct GlpkProblem {
  glp_prob* p = glp_create_prob();
  GlpkProblem() = default;
  GlpkProblem(const GlpkProblem&) = delete;
  GlpkProblem& operator=(const GlpkProblem&) = delete;
  ~GlpkProblem() { glp_delete_prob(p); }
};

// GLPK keeps an environment per thread from its first call until glp_free_env(); a server
// plans cuts on short-lived job threads, and each kept 5 kB (found by LeakSanitizer). Declared
// before any problem, it is freed after the last one is deleted.
struct GlpkEnvironment {
  GlpkEnvironment() = default;
  GlpkEnvironment(const GlpkEnvironment&) = delete;
  GlpkEnvironment& operator=(const GlpkEnvironment&) = delete;
  ~GlpkEnvironment() { glp_free_env(); }
};

struct StopAtBound {
  double bound = 0;
};

void stop_at_bound(glp_tree* tree, void* info) {
  if (glp_ios_reason(tree) != GLP_IBINGO) return;
  const auto* stop = static_cast<const StopAtBound*>(info);
  if (glp_mip_obj_val(glp_ios_get_prob(tree)) <= stop->bound + 0.5) glp_ios_terminate(tree);
}

struct ProgramResult {
  int lower_bound = 0;
  bool converged = false;
  bool hit_time_limit = false;
  std::vector<std::vector<int>> patterns;  // chosen patterns, one per stock piece (counts)
};

// The pattern program: min Σ x_p subject to Σ_p a_tp x_p ≥ demand_t, x integer. `incumbent`
// is the count to beat; `seed_patterns` (first fit's bins as counts) start the generation.
ProgramResult solve_pattern_program(const std::vector<PieceType>& types,
                                    double capacity,
                                    const std::vector<std::vector<int>>& seed_patterns,
                                    int incumbent,
                                    int known_bound,
                                    Clock::time_point deadline) {
  const GlpkEnvironment environment;
  ProgramResult result;
  result.lower_bound = known_bound;
  glp_term_out(GLP_OFF);
  const int nt = static_cast<int>(types.size());
  std::vector<double> size(types.size());
  std::vector<int> demand(types.size());
  for (std::size_t t = 0; t < types.size(); ++t) {
    size[t] = types[t].size;
    demand[t] = static_cast<int>(types[t].pieces.size());
  }

  GlpkProblem master;
  glp_set_obj_dir(master.p, GLP_MIN);
  glp_add_rows(master.p, nt);
  for (int t = 0; t < nt; ++t) {
    glp_set_row_bnds(master.p, t + 1, GLP_LO, demand[static_cast<std::size_t>(t)], 0);
  }
  std::vector<std::vector<int>> columns;
  auto add_column = [&](const std::vector<int>& counts) {
    std::vector<int> index{0};
    std::vector<double> value{0};
    for (int t = 0; t < nt; ++t) {
      if (counts[static_cast<std::size_t>(t)] > 0) {
        index.push_back(t + 1);
        value.push_back(counts[static_cast<std::size_t>(t)]);
      }
    }
    if (index.size() == 1) return;
    const int col = glp_add_cols(master.p, 1);
    glp_set_col_bnds(master.p, col, GLP_LO, 0, 0);
    glp_set_obj_coef(master.p, col, 1);
    glp_set_mat_col(master.p, col, static_cast<int>(index.size()) - 1, index.data(), value.data());
    columns.push_back(counts);
  };
  const double tol = fit_tolerance(capacity);
  for (int t = 0; t < nt; ++t) {
    std::vector<int> single(types.size(), 0);
    single[static_cast<std::size_t>(t)] = std::min(
        demand[static_cast<std::size_t>(t)],
        static_cast<int>(std::floor((capacity + tol) / size[static_cast<std::size_t>(t)])));
    add_column(single);
  }
  for (const auto& pattern : seed_patterns) add_column(pattern);

  glp_smcp simplex;
  glp_init_smcp(&simplex);
  simplex.msg_lev = GLP_MSG_OFF;
  std::vector<double> dual(types.size());
  for (;;) {
    if (Clock::now() >= deadline) {
      result.hit_time_limit = true;
      break;
    }
    if (glp_simplex(master.p, &simplex) != 0 || glp_get_status(master.p) != GLP_OPT) break;
    const double lp = glp_get_obj_val(master.p);
    for (int t = 0; t < nt; ++t) {
      dual[static_cast<std::size_t>(t)] = std::max(0.0, glp_get_row_dual(master.p, t + 1));
    }
    Knapsack pricing(dual, size, demand, capacity);
    const double reduced = pricing.solve();
    if (!pricing.exact) break;  // cannot prove convergence; keep the bounds found so far
    // Farley's bound: no plan beats lp / (best pattern value), valid at every iteration.
    const double farley = reduced > 1.0 ? lp / reduced : lp;
    result.lower_bound = std::max(result.lower_bound, static_cast<int>(std::ceil(farley - 1e-6)));
    if (reduced <= 1.0 + 1e-9) {
      result.converged = true;
      break;
    }
    if (result.lower_bound >= incumbent) break;
    add_column(pricing.best_z);
  }
  if (result.lower_bound >= incumbent || Clock::now() >= deadline) {
    result.hit_time_limit = result.hit_time_limit || result.lower_bound < incumbent;
    return result;
  }

  // The integer master over the generated patterns.
  const int ncols = glp_get_num_cols(master.p);
  for (int c = 1; c <= ncols; ++c) glp_set_col_kind(master.p, c, GLP_IV);
  glp_iocp mip;
  glp_init_iocp(&mip);
  mip.msg_lev = GLP_MSG_OFF;
  mip.presolve = GLP_ON;
  mip.gmi_cuts = GLP_ON;
  mip.mir_cuts = GLP_ON;
  mip.cov_cuts = GLP_ON;
  const double left_ms = std::chrono::duration<double, std::milli>(deadline - Clock::now()).count();
  mip.tm_lim = std::max(1, static_cast<int>(left_ms));
  StopAtBound stop{static_cast<double>(result.lower_bound)};
  mip.cb_func = stop_at_bound;
  mip.cb_info = &stop;
  const int ret = glp_intopt(master.p, &mip);
  if (ret == GLP_ETMLIM) result.hit_time_limit = true;
  const int status = glp_mip_status(master.p);
  if (status != GLP_OPT && status != GLP_FEAS) return result;
  if (glp_mip_obj_val(master.p) > incumbent - 0.5) return result;
  for (int c = 1; c <= ncols; ++c) {
    const int copies = static_cast<int>(std::lround(glp_mip_col_val(master.p, c)));
    for (int k = 0; k < copies; ++k)
      result.patterns.push_back(columns[static_cast<std::size_t>(c - 1)]);
  }
  return result;
}

std::string mm(double v) {
  std::string s = fmt::format("{:.3f}", v);
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

std::string csv_field(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::string_view to_string(CutPlanMethod m) {
  return m == CutPlanMethod::kFirstFit ? "first-fit" : "integer-program";
}

double CutPlan::waste(const StockSpec& stock_spec) const {
  double w = 0;
  for (const StockCut& s : stock) {
    double pieces = 0;
    for (const PlacedPiece& p : s.pieces) pieces += p.length;
    w += stock_spec.usable_length() - pieces;
  }
  return w;
}

std::optional<CutPlan> plan_cuts(std::span<const CutPiece> pieces,
                                 const StockSpec& stock,
                                 Diagnostics& diags,
                                 const CutPlanOptions& options) {
  const auto started = Clock::now();
  bool ok = true;
  auto finite_at_least = [&](double v, double min, bool strict, std::string_view what) {
    if (!std::isfinite(v) || v < min || (strict && v == min)) {
      diags.error(
          codes::kInvalidValue,
          fmt::format(
              "{} must be a finite number {} {} mm, got {}", what, strict ? ">" : ">=", min, v));
      ok = false;
    }
  };
  finite_at_least(stock.length, 0, true, "stock length");
  finite_at_least(stock.end_padding, 0, false, "stock end padding");
  finite_at_least(stock.kerf, 0, false, "stock kerf");
  if (ok && stock.usable_length() <= 0) {
    diags.error(codes::kInvalidValue,
                fmt::format("stock length {} mm leaves no usable length after 2 × {} mm end "
                            "padding",
                            mm(stock.length),
                            mm(stock.end_padding)));
    ok = false;
  }
  if (!ok) return std::nullopt;
  const double usable = stock.usable_length();
  for (const CutPiece& p : pieces) {
    const std::string name = p.label.empty() ? std::string("a piece") : "'" + p.label + "'";
    if (!std::isfinite(p.length) || p.length <= 0) {
      diags.error(
          codes::kInvalidValue,
          fmt::format("piece {} has length {} mm; lengths must be finite and > 0", name, p.length));
      ok = false;
    } else if (p.length > usable + fit_tolerance(usable)) {
      diags.error(codes::kPieceLongerThanStock,
                  fmt::format("piece {} is {} mm long, longer than the usable stock length {} mm "
                              "(stock {} mm minus 2 × {} mm end padding)",
                              name,
                              mm(p.length),
                              mm(usable),
                              mm(stock.length),
                              mm(stock.end_padding)));
      ok = false;
    }
  }
  if (!ok) return std::nullopt;

  CutPlan plan;
  const int n = static_cast<int>(pieces.size());
  const double capacity = usable + stock.kerf;
  std::vector<double> size(pieces.size());
  double total = 0;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    size[i] = pieces[i].length + stock.kerf;
    total += size[i];
  }
  plan.sum_lower_bound =
      n == 0 ? 0 : std::max(1, static_cast<int>(std::ceil(total / capacity - 1e-9)));
  plan.lower_bound = plan.sum_lower_bound;

  // 1. First fit: decreasing order, then seeded random orderings; keep the best.
  std::vector<int> order(pieces.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return size[static_cast<std::size_t>(a)] > size[static_cast<std::size_t>(b)];
  });
  std::vector<double> load;
  Bins best = first_fit(order, size, capacity, load);
  double best_spread = fill_spread(load);
  std::mt19937_64 rng(options.seed);
  for (int k = 0; k<options.orderings&& static_cast<int>(best.size())> plan.lower_bound; ++k) {
    // Fisher–Yates with the engine's raw output: the same sequence on every standard library.
    for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng() % i]);
    Bins bins = first_fit(order, size, capacity, load);
    const double spread = fill_spread(load);
    if (bins.size() < best.size() || (bins.size() == best.size() && spread > best_spread)) {
      best = std::move(bins);
      best_spread = spread;
    }
  }
  plan.first_fit_stock_count = static_cast<int>(best.size());
  plan.first_fit_ms = ms_since(started);

  // 2. The exact program, when first fit did not meet the bound.
  if (options.integer_program && static_cast<int>(best.size()) > plan.lower_bound) {
    const auto ip_started = Clock::now();
    std::vector<PieceType> types;
    std::vector<int> type_of(pieces.size());
    {
      std::vector<int> by_size(pieces.size());
      std::iota(by_size.begin(), by_size.end(), 0);
      std::stable_sort(by_size.begin(), by_size.end(), [&](int a, int b) {
        return size[static_cast<std::size_t>(a)] > size[static_cast<std::size_t>(b)];
      });
      for (const int i : by_size) {
        const double s = size[static_cast<std::size_t>(i)];
        if (types.empty() || types.back().size - s > 1e-9) types.push_back(PieceType{s, {}});
        types.back().pieces.push_back(i);
        type_of[static_cast<std::size_t>(i)] = static_cast<int>(types.size()) - 1;
      }
      // A type's size is its largest member's, so every pattern stays feasible.
    }
    std::vector<std::vector<int>> seed_patterns;
    for (const auto& bin : best) {
      std::vector<int> counts(types.size(), 0);
      for (const int i : bin)
        ++counts[static_cast<std::size_t>(type_of[static_cast<std::size_t>(i)])];
      seed_patterns.push_back(std::move(counts));
    }
    const auto deadline = ip_started + std::chrono::microseconds(static_cast<long long>(
                                           std::max(0.0, options.time_limit_s) * 1e6));
    ProgramResult program = solve_pattern_program(
        types, capacity, seed_patterns, static_cast<int>(best.size()), plan.lower_bound, deadline);
    plan.lower_bound = std::max(plan.lower_bound, program.lower_bound);
    plan.column_generation_converged = program.converged;
    plan.hit_time_limit = program.hit_time_limit;
    if (!program.patterns.empty() && program.patterns.size() < best.size()) {
      // Patterns cover the demand (≥); give each stock piece real pieces until all are placed.
      std::vector<std::size_t> next(types.size(), 0);
      Bins bins;
      for (const auto& pattern : program.patterns) {
        std::vector<int> bin;
        for (std::size_t t = 0; t < types.size(); ++t) {
          for (int c = 0; c < pattern[t] && next[t] < types[t].pieces.size(); ++c) {
            bin.push_back(types[t].pieces[next[t]++]);
          }
        }
        if (!bin.empty()) bins.push_back(std::move(bin));
      }
      bool all_placed = true;
      for (std::size_t t = 0; t < types.size(); ++t) {
        all_placed = all_placed && next[t] == types[t].pieces.size();
      }
      if (all_placed && bins.size() < best.size()) {
        best = std::move(bins);
        plan.method = CutPlanMethod::kIntegerProgram;
      }
    }
    plan.integer_program_ms = ms_since(ip_started);
  }

  // Lay each stock piece out: longest first, from the left padding, one kerf apart.
  for (auto& bin : best) {
    std::stable_sort(bin.begin(), bin.end(), [&](int a, int b) {
      return pieces[static_cast<std::size_t>(a)].length >
             pieces[static_cast<std::size_t>(b)].length;
    });
    StockCut cut;
    double x = stock.end_padding;
    for (const int i : bin) {
      const double l = pieces[static_cast<std::size_t>(i)].length;
      cut.pieces.push_back(PlacedPiece{i, x, l});
      x += l + stock.kerf;
    }
    cut.used = bin.empty() ? 0 : x - stock.kerf - stock.end_padding;
    cut.remainder = std::max(0.0, usable - cut.used);
    plan.stock.push_back(std::move(cut));
  }
  std::stable_sort(plan.stock.begin(), plan.stock.end(), [](const StockCut& a, const StockCut& b) {
    return a.used > b.used;
  });
  plan.proven_optimal = plan.stock_count() <= plan.lower_bound;
  if (plan.proven_optimal) plan.lower_bound = plan.stock_count();
  const int count = plan.stock_count();
  if (plan.proven_optimal) {
    plan.summary = fmt::format("{} stock piece{}, proven optimal", count, count == 1 ? "" : "s");
  } else {
    plan.summary =
        fmt::format("{} stock piece{}, {} above the lower bound {}{}",
                    count,
                    count == 1 ? "" : "s",
                    plan.gap(),
                    plan.lower_bound,
                    plan.hit_time_limit ? " (integer program stopped at its time limit)" : "");
  }
  return plan;
}

Diagnostics validate_cut_plan(const CutPlan& plan,
                              std::span<const CutPiece> pieces,
                              const StockSpec& stock) {
  Diagnostics d;
  const double tol = 1e-6;
  std::vector<int> seen(pieces.size(), 0);
  for (std::size_t s = 0; s < plan.stock.size(); ++s) {
    const StockCut& cut = plan.stock[s];
    double previous_end = -1;
    for (const PlacedPiece& p : cut.pieces) {
      if (p.piece < 0 || static_cast<std::size_t>(p.piece) >= pieces.size()) {
        d.error(codes::kInternalError,
                fmt::format("stock {}: piece index {} is out of range", s + 1, p.piece));
        continue;
      }
      ++seen[static_cast<std::size_t>(p.piece)];
      const CutPiece& piece = pieces[static_cast<std::size_t>(p.piece)];
      if (std::abs(p.length - piece.length) > tol) {
        d.error(codes::kInternalError,
                fmt::format("stock {}: piece '{}' is placed {} mm long, not {} mm",
                            s + 1,
                            piece.label,
                            mm(p.length),
                            mm(piece.length)));
      }
      if (p.start < stock.end_padding - tol) {
        d.error(codes::kInternalError,
                fmt::format("stock {}: piece '{}' starts at {} mm, inside the {} mm end padding",
                            s + 1,
                            piece.label,
                            mm(p.start),
                            mm(stock.end_padding)));
      }
      if (p.start + piece.length > stock.length - stock.end_padding + tol) {
        d.error(codes::kInternalError,
                fmt::format("stock {}: piece '{}' ends at {} mm, past the usable end {} mm",
                            s + 1,
                            piece.label,
                            mm(p.start + piece.length),
                            mm(stock.length - stock.end_padding)));
      }
      if (previous_end >= 0 && p.start < previous_end + stock.kerf - tol) {
        d.error(codes::kInternalError,
                fmt::format("stock {}: piece '{}' starts {} mm after the previous piece, less "
                            "than the {} mm kerf",
                            s + 1,
                            piece.label,
                            mm(p.start - previous_end),
                            mm(stock.kerf)));
      }
      previous_end = p.start + piece.length;
    }
  }
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (seen[i] != 1) {
      d.error(codes::kInternalError,
              fmt::format("piece '{}' is placed {} times, not once", pieces[i].label, seen[i]));
    }
  }
  return d;
}

std::string cut_plan_svg(const CutPlan& plan,
                         std::span<const CutPiece> pieces,
                         const StockSpec& stock,
                         const CutPlanSvgOptions& options) {
  const double rows = static_cast<double>(plan.stock.size());
  const double width = 2 * options.margin + stock.length;
  const double height =
      2 * options.margin + rows * options.stock_width + std::max(0.0, rows - 1) * options.row_gap;
  std::string svg = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}mm\" height=\"{1}mm\" "
      "viewBox=\"0 0 {0} {1}\">\n"
      "<!-- fabkit cut plan: {2}; stock {3} mm, end padding {4} mm, kerf {5} mm. Red lines are "
      "cuts (at the centre of each kerf), blue outlines the stock, black text labels. -->\n",
      mm(width),
      mm(height),
      xml_escape(plan.summary),
      mm(stock.length),
      mm(stock.end_padding),
      mm(stock.kerf));
  for (std::size_t s = 0; s < plan.stock.size(); ++s) {
    const StockCut& cut = plan.stock[s];
    const double y =
        options.margin + static_cast<double>(s) * (options.stock_width + options.row_gap);
    svg += fmt::format("<g id=\"stock-{}\">\n", s + 1);
    svg += fmt::format(
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#0000ff\" "
        "stroke-width=\"0.1\"/>\n",
        mm(options.margin),
        mm(y),
        mm(stock.length),
        mm(options.stock_width));
    std::vector<double> cuts;
    for (std::size_t k = 0; k < cut.pieces.size(); ++k) {
      const PlacedPiece& p = cut.pieces[k];
      if (k == 0 && p.start > 1e-9) cuts.push_back(std::max(0.0, p.start - stock.kerf / 2));
      const double end = p.start + p.length;
      if (end < stock.length - 1e-9) cuts.push_back(std::min(stock.length, end + stock.kerf / 2));
    }
    for (const double c : cuts) {
      svg += fmt::format(
          "<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"#ff0000\" "
          "stroke-width=\"0.1\"/>\n",
          mm(options.margin + c),
          mm(y),
          mm(y + options.stock_width));
    }
    if (options.label_size > 0) {
      for (const PlacedPiece& p : cut.pieces) {
        const CutPiece& piece = pieces[static_cast<std::size_t>(p.piece)];
        svg += fmt::format(
            "<text x=\"{}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"{}\" "
            "text-anchor=\"middle\" dominant-baseline=\"central\" fill=\"#000000\">{} · {} "
            "mm</text>\n",
            mm(options.margin + p.start + p.length / 2),
            mm(y + options.stock_width / 2),
            mm(options.label_size),
            xml_escape(piece.label),
            fmt::format("{:.1f}", p.length));
      }
    }
    svg += "</g>\n";
  }
  svg += "</svg>\n";
  return svg;
}

std::string cut_plan_csv(const CutPlan& plan, std::span<const CutPiece> pieces) {
  struct Row {
    const CutPiece* piece;
    std::size_t stock;
    double position;
  };
  std::vector<Row> rows;
  for (std::size_t s = 0; s < plan.stock.size(); ++s) {
    for (const PlacedPiece& p : plan.stock[s].pieces) {
      rows.push_back(Row{&pieces[static_cast<std::size_t>(p.piece)], s + 1, p.start});
    }
  }
  std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
    if (a.piece->length != b.piece->length) return a.piece->length > b.piece->length;
    return a.piece->label < b.piece->label;
  });
  std::string csv = "label,length_mm,stock,position_mm\n";
  for (const Row& r : rows) {
    csv += fmt::format(
        "{},{:.3f},{},{:.3f}\n", csv_field(r.piece->label), r.piece->length, r.stock, r.position);
  }
  return csv;
}

}  // namespace fabkit
