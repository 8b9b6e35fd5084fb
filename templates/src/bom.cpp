// The bill of materials and the cut plans.
#include "fabkit/templates/bom.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "fabkit/core/json.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/extract.h"

namespace fabkit::templates {

namespace {

using Clock = std::chrono::steady_clock;

std::string money(double v) {
  return fmt::format("${:.2f}", v);
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// Grainless sheet materials may be turned on the sheet; veneered and solid wood keep their
// grain along the piece's length.
bool may_rotate(const Item& it) {
  for (std::string_view m : {"MDF", "OSB", "melamine", "hardboard", "acrylic"}) {
    if (it.material.find(m) != std::string::npos) return true;
  }
  return false;
}

std::string size_summary(std::vector<double> sizes) {
  std::sort(sizes.begin(), sizes.end(), std::greater<>());
  std::string out;
  std::size_t i = 0;
  while (i < sizes.size()) {
    std::size_t j = i;
    while (j < sizes.size() && std::abs(sizes[j] - sizes[i]) < 0.05) ++j;
    if (!out.empty()) out += ", ";
    out += fmt::format("{} x {:g} mm", j - i, std::round(sizes[i] * 10) / 10);
    i = j;
  }
  return out;
}

}  // namespace

std::optional<BillOfMaterials> bill_of_materials(const Template& t,
                                                 const ItemCatalog& catalog,
                                                 Diagnostics& diags,
                                                 const BomOptions& o) {
  const auto start = Clock::now();
  BillOfMaterials bom;
  struct Use {
    std::vector<PlacedPart> parts;
  };
  std::map<std::string, Use> by_item;
  for (const PlacedPart& p : t.placed_parts()) by_item[p.item].parts.push_back(p);
  bool ok = true;
  for (auto& [id, use] : by_item) {
    const Item* it = catalog.find(id);
    if (!it) {
      diags.error(codes::kUnknownItem,
                  fmt::format("part '{}': unknown item '{}'", use.parts.front().name, id));
      ok = false;
      continue;
    }
    BomLine line;
    line.item = id;
    line.name = it->name;
    line.category = it->category;
    line.supplier = it->supplier;
    line.part_number = it->part_number;
    line.unit = it->unit;
    line.parts = static_cast<int>(use.parts.size());
    bom.parts += line.parts;
    int resizable = 0;
    for (const ItemDimension& d : it->dims) resizable += d.resizable;
    // The part's extent along the item's length and width (its axes map from extraction).
    auto extents = [&](const PlacedPart& p) {
      std::array<double, 3> e{};
      const auto axes = item_axes(*it, p.box.size);
      const std::array<int, 3> map = axes.value_or(std::array<int, 3>{0, 1, 2});
      for (int k = 0; k < 3; ++k) e[map[k]] = p.box.size[k];
      return e;
    };
    if (resizable == 0) {
      line.units = (line.parts + it->pack_quantity - 1) / it->pack_quantity;
      line.unit_price = it->price;
      line.total = line.units * it->price;
      line.buy = it->pack_quantity > 1 ? fmt::format("{} {}{} of {} at {}",
                                                     line.units,
                                                     it->unit,
                                                     line.units == 1 ? "" : "s",
                                                     it->pack_quantity,
                                                     money(it->price))
                                       : fmt::format("{} at {}", line.units, money(it->price));
    } else if (resizable == 1 || it->category == ItemCategory::kLumber ||
               it->category == ItemCategory::kPipe) {
      // 1D: cut to length from the cheapest stock length that holds every piece.
      std::vector<CutPiece> pieces;
      std::vector<double> lengths;
      for (const PlacedPart& p : use.parts) {
        const double l = extents(p)[0];
        pieces.push_back({p.name, l});
        lengths.push_back(l);
      }
      const double kerf = it->category == ItemCategory::kPipe ? o.pipe_kerf_mm : o.saw_kerf_mm;
      std::optional<LumberCuts> best;
      double best_cost = std::numeric_limits<double>::infinity();
      double longest_stock = 0;
      for (const StockSize& s : it->stock_sizes()) {
        longest_stock = std::max(longest_stock, s.length_mm);
        StockSpec spec{s.length_mm, o.lumber_end_trim_mm, kerf};
        if (*std::max_element(lengths.begin(), lengths.end()) > spec.usable_length()) continue;
        Diagnostics quiet;
        auto plan = plan_cuts(pieces, spec, quiet, o.cut_plan);
        if (!plan) continue;
        const double cost = plan->stock_count() * s.price;
        if (cost < best_cost - 1e-9) {
          best_cost = cost;
          best = LumberCuts{id, pieces, spec, s.price, std::move(*plan), it->dims[1].mm};
        }
      }
      if (!best) {
        for (const CutPiece& p : pieces) {
          if (p.length > longest_stock - 2 * o.lumber_end_trim_mm) {
            diags.error(
                codes::kPieceTooLarge,
                fmt::format("part '{}' is {:g} mm long; the longest stock of {} ({}) is {:g} mm "
                            "({:g} mm usable after trimming the ends)",
                            p.label,
                            p.length,
                            id,
                            it->name,
                            longest_stock,
                            longest_stock - 2 * o.lumber_end_trim_mm));
          }
        }
        ok = false;
        continue;
      }
      line.units = best->plan.stock_count();
      line.unit_price = best->stock_price;
      line.total = best_cost;
      line.buy = fmt::format(
          "{} x {:g} mm at {}", line.units, best->stock.length, money(best->stock_price));
      line.sizes = size_summary(lengths);
      bom.lumber.push_back(std::move(*best));
    } else {
      // 2D: guillotine cuts from sheets; the cheapest of each stock size alone, or full sheets
      // with lightly used ones replaced by a smaller size.
      std::vector<SheetPiece> pieces;
      std::vector<double> areas;
      for (const PlacedPart& p : use.parts) {
        const auto e = extents(p);
        pieces.push_back({p.name, e[0], e[1], may_rotate(*it)});
        areas.push_back(e[0] * e[1]);
      }
      std::vector<StockSize> stock = it->stock_sizes();
      std::sort(stock.begin(), stock.end(), [](const StockSize& a, const StockSize& b) {
        return a.length_mm * a.width_mm > b.length_mm * b.width_mm;
      });
      std::optional<SheetCuts> best;
      double best_cost = std::numeric_limits<double>::infinity();
      auto spec_of = [&](const StockSize& s) {
        return SheetSpec{s.length_mm,
                         s.width_mm > 0 ? s.width_mm : it->dims[1].mm,
                         o.saw_kerf_mm,
                         o.sheet_edge_trim_mm};
      };
      for (std::size_t si = 0; si < stock.size(); ++si) {
        Diagnostics quiet;
        auto plan = plan_sheets(pieces, spec_of(stock[si]), quiet, o.sheet_plan);
        if (!plan) continue;
        SheetCuts cuts{id,
                       pieces,
                       std::vector<SheetSpec>(plan->sheets.size(), spec_of(stock[si])),
                       std::vector<double>(plan->sheets.size(), stock[si].price),
                       *plan};
        // Smaller stock for sheets whose pieces fit on one.
        for (std::size_t sh = 0; sh < cuts.plan.sheets.size(); ++sh) {
          for (std::size_t smaller = si + 1; smaller < stock.size(); ++smaller) {
            if (stock[smaller].price >= cuts.sheet_prices[sh]) continue;
            std::vector<SheetPiece> on_sheet;
            for (const SheetPlacement& p : cuts.plan.sheets[sh].pieces)
              on_sheet.push_back(pieces[p.piece]);
            auto small = plan_sheets(on_sheet, spec_of(stock[smaller]), quiet, o.sheet_plan);
            if (!small || small->sheet_count() != 1) continue;
            // Re-index the pieces of the smaller plan to the item's piece list.
            SheetCut replaced = small->sheets[0];
            for (SheetPlacement& p : replaced.pieces)
              p.piece = cuts.plan.sheets[sh].pieces[p.piece].piece;
            cuts.plan.sheets[sh] = replaced;
            cuts.sheet_specs[sh] = spec_of(stock[smaller]);
            cuts.sheet_prices[sh] = stock[smaller].price;
          }
        }
        double cost = 0;
        for (double p : cuts.sheet_prices) cost += p;
        if (cost < best_cost - 1e-9) {
          best_cost = cost;
          best = std::move(cuts);
        }
      }
      if (!best) {
        const StockSize& largest = stock.front();
        for (const SheetPiece& p : pieces) {
          const SheetSpec s = spec_of(largest);
          const bool fits =
              (p.length <= s.usable_length() && p.width <= s.usable_width()) ||
              (p.may_rotate && p.width <= s.usable_length() && p.length <= s.usable_width());
          if (!fits) {
            diags.error(
                codes::kPieceTooLarge,
                fmt::format(
                    "part '{}' is {:g} x {:g} mm; the largest sheet of {} ({}) is {:g} x {:g} mm",
                    p.label,
                    p.length,
                    p.width,
                    id,
                    it->name,
                    s.length,
                    s.width));
          }
        }
        ok = false;
        continue;
      }
      line.units = best->plan.sheet_count();
      line.total = best_cost;
      line.unit_price = line.units ? best_cost / line.units : 0;
      std::map<std::pair<double, double>, std::pair<int, double>> counts;
      for (std::size_t sh = 0; sh < best->sheet_specs.size(); ++sh) {
        auto& c = counts[{best->sheet_specs[sh].length, best->sheet_specs[sh].width}];
        ++c.first;
        c.second = best->sheet_prices[sh];
      }
      std::vector<std::string> buys;
      for (auto it2 = counts.rbegin(); it2 != counts.rend(); ++it2) {
        buys.push_back(fmt::format("{} {} {:g} x {:g} mm at {}",
                                   it2->second.first,
                                   it2->second.first == 1 ? "sheet" : "sheets",
                                   it2->first.first,
                                   it2->first.second,
                                   money(it2->second.second)));
      }
      line.buy = fmt::format("{}", fmt::join(buys, " + "));
      std::vector<std::string> sizes;
      for (const SheetPiece& p : pieces)
        sizes.push_back(fmt::format(
            "{:g} x {:g}", std::round(p.length * 10) / 10, std::round(p.width * 10) / 10));
      std::sort(sizes.begin(), sizes.end());
      line.sizes = fmt::format("{} mm", fmt::join(sizes, ", "));
      bom.sheets.push_back(std::move(*best));
    }
    bom.lines.push_back(std::move(line));
  }
  if (!ok) return std::nullopt;
  std::stable_sort(bom.lines.begin(), bom.lines.end(), [](const BomLine& a, const BomLine& b) {
    return static_cast<int>(a.category) < static_cast<int>(b.category);
  });
  for (const BomLine& l : bom.lines) bom.total += l.total;
  bom.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return bom;
}

std::string bom_csv(const BillOfMaterials& bom) {
  std::string out =
      "category,item,name,parts,units,unit,unit_price_usd,total_usd,supplier,part_number,buy,"
      "sizes\n";
  for (const BomLine& l : bom.lines) {
    out += fmt::format("{},{},{},{},{},{},{:.2f},{:.2f},{},{},{},{}\n",
                       to_string(l.category),
                       csv_field(l.item),
                       csv_field(l.name),
                       l.parts,
                       l.units,
                       csv_field(l.unit),
                       l.unit_price,
                       l.total,
                       csv_field(l.supplier),
                       csv_field(l.part_number),
                       csv_field(l.buy),
                       csv_field(l.sizes));
  }
  out += fmt::format("TOTAL,,,{},,,,{:.2f},,,,\n", bom.parts, bom.total);
  return out;
}

std::string bom_json(const BillOfMaterials& bom) {
  Json j;
  j["total_usd"] = tidy(bom.total);
  j["parts"] = bom.parts;
  Json lines = Json::array();
  for (const BomLine& l : bom.lines) {
    lines.push_back({{"item", l.item},
                     {"name", l.name},
                     {"category", std::string(to_string(l.category))},
                     {"parts", l.parts},
                     {"units", l.units},
                     {"unit", l.unit},
                     {"unit_price_usd", tidy(l.unit_price)},
                     {"total_usd", tidy(l.total)},
                     {"supplier", l.supplier},
                     {"part_number", l.part_number},
                     {"buy", l.buy},
                     {"sizes", l.sizes}});
  }
  j["lines"] = lines;
  Json lumber = Json::array();
  for (const LumberCuts& c : bom.lumber) {
    Json stock = Json::array();
    for (const StockCut& s : c.plan.stock) {
      Json cuts = Json::array();
      for (const PlacedPiece& p : s.pieces) {
        cuts.push_back({{"part", c.pieces[p.piece].label},
                        {"start_mm", tidy(p.start)},
                        {"length_mm", tidy(p.length)}});
      }
      stock.push_back({{"pieces", cuts}, {"remainder_mm", tidy(s.remainder)}});
    }
    lumber.push_back({{"item", c.item},
                      {"stock_length_mm", tidy(c.stock.length)},
                      {"kerf_mm", tidy(c.stock.kerf)},
                      {"end_trim_mm", tidy(c.stock.end_padding)},
                      {"stock", stock},
                      {"summary", c.plan.summary}});
  }
  j["lumber"] = lumber;
  Json sheets = Json::array();
  for (const SheetCuts& c : bom.sheets) {
    Json list = Json::array();
    for (std::size_t sh = 0; sh < c.plan.sheets.size(); ++sh) {
      Json pieces = Json::array();
      for (const SheetPlacement& p : c.plan.sheets[sh].pieces) {
        pieces.push_back({{"part", c.pieces[p.piece].label},
                          {"x_mm", tidy(p.x)},
                          {"y_mm", tidy(p.y)},
                          {"length_mm", tidy(p.length)},
                          {"width_mm", tidy(p.width)},
                          {"rotated", p.rotated}});
      }
      list.push_back({{"length_mm", tidy(c.sheet_specs[sh].length)},
                      {"width_mm", tidy(c.sheet_specs[sh].width)},
                      {"price_usd", tidy(c.sheet_prices[sh])},
                      {"pieces", pieces},
                      {"cuts", static_cast<int>(c.plan.sheets[sh].cuts.size())}});
    }
    sheets.push_back({{"item", c.item},
                      {"kerf_mm", c.sheet_specs.empty() ? 0.0 : tidy(c.sheet_specs[0].kerf)},
                      {"sheets", list}});
  }
  j["sheet_goods"] = sheets;
  return dump_json(j, 2) + "\n";
}

}  // namespace fabkit::templates
