#include "fabkit/core/cut_plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace fabkit {
namespace {

std::vector<CutPiece> pieces_of(const std::vector<double>& lengths) {
  std::vector<CutPiece> pieces;
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    std::string label = "p";
    label += std::to_string(i + 1);
    pieces.push_back(CutPiece{label, lengths[i]});
  }
  return pieces;
}

CutPlan plan_or_fail(const std::vector<CutPiece>& pieces,
                     const StockSpec& stock,
                     const CutPlanOptions& options = {}) {
  Diagnostics d;
  auto plan = plan_cuts(pieces, stock, d, options);
  EXPECT_TRUE(plan.has_value()) << d.format();
  if (!plan) return {};
  const Diagnostics problems = validate_cut_plan(*plan, pieces, stock);
  EXPECT_TRUE(problems.empty()) << problems.format();
  return *plan;
}

// Fewest bins by exhaustive search (for small instances): an independent optimum.
int brute_force_optimum(std::vector<double> sizes, double capacity) {
  std::sort(sizes.rbegin(), sizes.rend());
  for (int bins = 1;; ++bins) {
    std::vector<double> load(static_cast<std::size_t>(bins), 0);
    std::function<bool(std::size_t)> place = [&](std::size_t i) {
      if (i == sizes.size()) return true;
      for (std::size_t b = 0; b < load.size(); ++b) {
        if (load[b] + sizes[i] <= capacity + 1e-9) {
          load[b] += sizes[i];
          if (place(i + 1)) return true;
          load[b] -= sizes[i];
        }
        if (load[b] == 0) break;  // empty bins are interchangeable
      }
      return false;
    };
    if (place(0)) return bins;
  }
}

// Triplets that fill a 1000 mm usable length exactly: the optimum is n / 3 and first fit
// decreasing misses it.
std::vector<double> triplets(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<double> lengths;
  while (static_cast<int>(lengths.size()) < 3 * count) {
    const int a = 250 + static_cast<int>(rng() % 251);
    const int b = 250 + static_cast<int>(rng() % 251);
    const int c = 1000 - a - b;
    if (c < 250 || c > 500) continue;
    lengths.insert(lengths.end(), {double(a), double(b), double(c)});
  }
  return lengths;
}

TEST(CutPlan, PaddingAndKerfDecideWhatFits) {
  // Usable 980 mm; two 489 mm pieces need 489 + 2 + 489 = 980 mm: one stock piece.
  const StockSpec stock{.length = 1000, .end_padding = 10, .kerf = 2};
  CutPlan fits = plan_or_fail(pieces_of({489, 489}), stock);
  EXPECT_EQ(fits.stock_count(), 1);
  ASSERT_EQ(fits.stock[0].pieces.size(), 2u);
  EXPECT_DOUBLE_EQ(fits.stock[0].pieces[0].start, 10);
  EXPECT_DOUBLE_EQ(fits.stock[0].pieces[1].start, 10 + 489 + 2);
  EXPECT_NEAR(fits.stock[0].remainder, 0, 1e-9);
  // Half a millimetre more each and the kerf no longer fits: two stock pieces.
  EXPECT_EQ(plan_or_fail(pieces_of({489.5, 489.5}), stock).stock_count(), 2);
  // Without kerf, 490 + 490 = 980 fits exactly.
  EXPECT_EQ(plan_or_fail(pieces_of({490, 490}), StockSpec{1000, 10, 0}).stock_count(), 1);
}

TEST(CutPlan, PieceLongerThanStockNamesPieceAndBothLengths) {
  Diagnostics d;
  std::vector<CutPiece> pieces = {{"rod 03-07", 995}, {"rod 01-02", 300}, {"rod 04-05", 1200}};
  EXPECT_FALSE(plan_cuts(pieces, StockSpec{1000, 10, 0}, d));
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d.items()[0].code, codes::kPieceLongerThanStock);
  EXPECT_EQ(d.items()[0].kind(), DiagnosticClass::kInfeasible);
  EXPECT_NE(d.items()[0].message.find("'rod 03-07' is 995 mm long"), std::string::npos)
      << d.format();
  EXPECT_NE(d.items()[0].message.find("usable stock length 980 mm"), std::string::npos);
  EXPECT_NE(d.items()[0].message.find("stock 1000 mm"), std::string::npos);
  EXPECT_NE(d.items()[1].message.find("'rod 04-05' is 1200 mm"), std::string::npos);
}

TEST(CutPlan, InvalidNumbersAreInputErrors) {
  Diagnostics d;
  EXPECT_FALSE(plan_cuts(pieces_of({100, std::nan(""), -3}), StockSpec{1000, 10, 0}, d));
  EXPECT_EQ(d.size(), 2u);
  EXPECT_TRUE(d.has_errors_of(DiagnosticClass::kInput));
  Diagnostics s;
  EXPECT_FALSE(plan_cuts(pieces_of({100}), StockSpec{100, 50, 0}, s));
  EXPECT_NE(s.format().find("leaves no usable length"), std::string::npos) << s.format();
  Diagnostics k;
  EXPECT_FALSE(plan_cuts(pieces_of({100}), StockSpec{1000, 10, -1}, k));
  EXPECT_NE(k.format().find("stock kerf"), std::string::npos);
}

TEST(CutPlan, EmptyListNeedsNoStock) {
  CutPlan plan = plan_or_fail({}, StockSpec{});
  EXPECT_EQ(plan.stock_count(), 0);
  EXPECT_TRUE(plan.proven_optimal);
}

TEST(CutPlan, MatchesExhaustiveOptimumOnSmallInstances) {
  std::mt19937 rng(11);
  for (int instance = 0; instance < 40; ++instance) {
    std::vector<double> lengths;
    const int n = 4 + instance % 6;
    for (int i = 0; i < n; ++i) lengths.push_back(120 + static_cast<double>(rng() % 5000) / 10);
    const StockSpec stock{.length = 700, .end_padding = 5, .kerf = 1.5};
    std::vector<double> sizes;
    for (double l : lengths) sizes.push_back(l + stock.kerf);
    const int optimum = brute_force_optimum(sizes, stock.usable_length() + stock.kerf);
    const CutPlan plan = plan_or_fail(pieces_of(lengths), stock);
    EXPECT_EQ(plan.stock_count(), optimum) << "instance " << instance;
    EXPECT_GE(plan.stock_count(), plan.lower_bound);
    EXPECT_LE(plan.lower_bound, optimum);  // the bound is a true bound
  }
}

TEST(CutPlan, IntegerProgramSolvesTripletsThatFirstFitDecreasingMisses) {
  const std::vector<CutPiece> pieces = pieces_of(triplets(17, 3));
  const StockSpec stock{.length = 1020, .end_padding = 10, .kerf = 0};
  CutPlanOptions ffd_only{.orderings = 0, .integer_program = false};
  const CutPlan ffd = plan_or_fail(pieces, stock, ffd_only);
  EXPECT_GT(ffd.stock_count(), 17);  // first fit decreasing is not optimal here
  EXPECT_FALSE(ffd.proven_optimal);
  CutPlanOptions exact{.orderings = 0, .time_limit_s = 5};
  const CutPlan plan = plan_or_fail(pieces, stock, exact);
  EXPECT_EQ(plan.stock_count(), 17);
  EXPECT_TRUE(plan.proven_optimal);
  EXPECT_EQ(plan.method, CutPlanMethod::kIntegerProgram);
  EXPECT_EQ(plan.summary, "17 stock pieces, proven optimal");
  for (const StockCut& s : plan.stock) EXPECT_NEAR(s.remainder, 0, 1e-6);
}

TEST(CutPlan, ColumnGenerationProvesABoundAboveTheSumBound) {
  // Six 510 mm pieces in 1000 mm: Σ = 3060 → sum bound 4, but no two fit: optimum 6.
  const CutPlan plan =
      plan_or_fail(pieces_of({510, 510, 510, 510, 510, 510}), StockSpec{1000, 0, 0});
  EXPECT_EQ(plan.sum_lower_bound, 4);
  EXPECT_EQ(plan.stock_count(), 6);
  EXPECT_EQ(plan.lower_bound, 6);
  EXPECT_TRUE(plan.proven_optimal);
  EXPECT_TRUE(plan.column_generation_converged);
}

TEST(CutPlan, TimeLimitReportsTheGap) {
  const std::vector<CutPiece> pieces = pieces_of(triplets(17, 3));
  CutPlanOptions hurried{.orderings = 0, .time_limit_s = 0};
  const CutPlan plan = plan_or_fail(pieces, StockSpec{1020, 10, 0}, hurried);
  EXPECT_FALSE(plan.proven_optimal);
  EXPECT_TRUE(plan.hit_time_limit);
  EXPECT_EQ(plan.lower_bound, 17);
  EXPECT_EQ(plan.gap(), plan.stock_count() - 17);
  EXPECT_NE(
      plan.summary.find("above the lower bound 17 (integer program stopped at its time limit)"),
      std::string::npos)
      << plan.summary;
}

TEST(CutPlan, SameSeedSamePlan) {
  const std::vector<CutPiece> pieces = pieces_of(triplets(10, 8));
  const StockSpec stock{1030, 12, 3};
  CutPlanOptions options{.integer_program = false};
  const CutPlan a = plan_or_fail(pieces, stock, options);
  const CutPlan b = plan_or_fail(pieces, stock, options);
  EXPECT_EQ(cut_plan_csv(a, pieces), cut_plan_csv(b, pieces));
}

TEST(CutPlan, SvgIsTrueSizeWithOneCutPerKerf) {
  std::vector<CutPiece> pieces = {{"a<&>", 300}, {"b", 200}, {"c", 900}};
  const StockSpec stock{.length = 1000, .end_padding = 10, .kerf = 2};
  const CutPlan plan = plan_or_fail(pieces, stock);
  ASSERT_EQ(plan.stock_count(), 2);
  const std::string svg = cut_plan_svg(
      plan, pieces, stock, CutPlanSvgOptions{.stock_width = 10, .row_gap = 6, .margin = 5});
  EXPECT_NE(svg.find("width=\"1010mm\" height=\"36mm\" viewBox=\"0 0 1010 36\""), std::string::npos)
      << svg.substr(0, 300);
  // Stock 1 (900): cuts at 9 and 911. Stock 2 (300, 200): cuts at 9, 311, 513.
  auto count = [&](std::string_view needle) {
    std::size_t n = 0;
    for (auto p = svg.find(needle); p != std::string::npos; p = svg.find(needle, p + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("<line"), 5u);
  EXPECT_NE(svg.find("x1=\"916\""), std::string::npos);  // 5 mm margin + 911
  EXPECT_NE(svg.find("x1=\"518\""), std::string::npos);  // 5 + 10 + 300 + 2 + 200 + 1
  EXPECT_NE(svg.find("a&lt;&amp;&gt; · 300.0 mm"), std::string::npos);
  EXPECT_EQ(svg.find("a<&>"), std::string::npos);
}

TEST(CutPlan, CsvSortedByLengthWithQuoting) {
  std::vector<CutPiece> pieces = {{"short", 100}, {"long, \"top\"", 700}, {"mid", 400}};
  const CutPlan plan = plan_or_fail(pieces, StockSpec{1000, 0, 0});
  EXPECT_EQ(cut_plan_csv(plan, pieces),
            "label,length_mm,stock,position_mm\n"
            "\"long, \"\"top\"\"\",700.000,1,0.000\n"
            "mid,400.000,2,0.000\n"
            "short,100.000,1,700.000\n");
}

TEST(CutPlan, ValidatorCatchesOverlapsAndMissingPieces) {
  std::vector<CutPiece> pieces = pieces_of({300, 300});
  const StockSpec stock{1000, 10, 2};
  CutPlan plan = plan_or_fail(pieces, stock);
  ASSERT_EQ(plan.stock[0].pieces.size(), 2u);
  plan.stock[0].pieces[1].start -= 1.5;  // closer than the kerf
  Diagnostics d = validate_cut_plan(plan, pieces, stock);
  EXPECT_NE(d.format().find("less than the 2 mm kerf"), std::string::npos) << d.format();
  plan.stock[0].pieces.pop_back();
  EXPECT_NE(validate_cut_plan(plan, pieces, stock).format().find("placed 0 times"),
            std::string::npos);
}

}  // namespace
}  // namespace fabkit
