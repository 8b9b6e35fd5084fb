#pragma once
/// The items catalog: everything a design can be built from, as it is sold (lumber, sheet
/// goods, screws, brackets, hinges, slides, casters, pipe), stored in an SQLite database.
///
/// The schema (docs/templates.md) is versioned with `PRAGMA user_version` and migrated forward
/// on open; the bundled catalog is built from `templates/data/catalog/items.csv` so that it
/// diffs, and a user adds a store's items by importing a CSV with the same columns.
///
///   Diagnostics d;
///   auto catalog = ItemCatalog::open("my_items.sqlite", d);   // creates or migrates
///   catalog->import_csv(text, "my_store.csv", d);              // all rows or none
///   const Item* board = catalog->find("LUM-PINE-1x4");

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"

namespace fabkit::templates {

/// What kind of thing an item is; decides how the bill of materials groups and cuts it.
enum class ItemCategory {
  kLumber,       ///< boards, posts, dowels: cut to length from stock lengths
  kSheet,        ///< plywood, MDF, OSB: cut to rectangles from stock sheets
  kFastener,     ///< screws, bolts, nuts, washers, dowel pins
  kBracket,      ///< L-brackets, corner braces, plates, shelf brackets
  kHinge,        ///< butt, concealed and piano hinges
  kDrawerSlide,  ///< drawer runners (a pair per drawer)
  kWheel,        ///< casters and wheels
  kPipe,         ///< metal pipe and tube (cut to length)
  kFitting,      ///< pipe fittings, flanges, axle parts
  kHardware,     ///< knobs, handles, feet, levelers
};
/// "lumber", "sheet", "fastener", "bracket", "hinge", "drawer-slide", "wheel", "pipe",
/// "fitting", "hardware".
std::string_view to_string(ItemCategory c);
std::optional<ItemCategory> category_from_string(std::string_view s);
/// Every category, in the order above.
std::span<const ItemCategory> all_categories();

/// One of an item's three dimensions, in mm. A resizable dimension can be changed by a
/// physical process (cutting wood or pipe to length); `mm` is then the largest stock size.
struct ItemDimension {
  double mm = 0;
  bool resizable = false;
};

/// A size an item is sold in: lumber by length, sheets by length × width; price per piece.
struct StockSize {
  double length_mm = 0;
  double width_mm = 0;  ///< sheets only (0 for lumber and pipe)
  double price = 0;     ///< USD per stock piece
};

/// A purchasable item.
struct Item {
  std::string id;    ///< unique key ("LUM-PINE-2x4"); parts refer to items by it
  std::string name;  ///< "2x4 pine stud"
  ItemCategory category = ItemCategory::kHardware;
  std::string material;        ///< "pine", "birch plywood", "steel", "rubber"
  std::string supplier;        ///< where to buy it
  std::string part_number;     ///< the supplier's number
  double price = 0;            ///< USD per unit of sale (for cut goods: the largest stock piece)
  std::string unit = "piece";  ///< unit of sale: "piece", "box", "pair", "sheet", "length"
  int pack_quantity = 1;       ///< parts per unit of sale (100 screws in a box)
  /// [length, width, thickness] in mm; for hardware the bounding box of the item as sold
  /// (length along its main axis: a screw's length, a caster's height).
  std::array<ItemDimension, 3> dims;
  std::vector<StockSize> stock;  ///< cut goods: every stock size sold (empty: dims at price)
  double density_kg_m3 = 0;      ///< for cut goods (mass from volume)
  double mass_g = 0;             ///< for hardware: the mass of one part
  std::string mesh = "box";      ///< display: box, cylinder, tube, l-bracket, hinge, caster, plate
  std::string notes;

  /// Whether any dimension is resizable (cut from stock).
  bool cut_to_size() const;
  /// Mass in kg of one part of `size` mm (volume × density for cut goods, mass_g otherwise).
  double part_mass_kg(const Vec3& size) const;
  /// The stock sizes, or the item's own size at its price when none are listed.
  std::vector<StockSize> stock_sizes() const;
};

/// The catalog: an SQLite database plus an in-memory index. Copies share the database.
class ItemCatalog {
 public:
  /// The schema this fabkit writes; older files are migrated on open.
  static constexpr int kSchemaVersion = 3;

  /// An empty catalog in memory, at the current schema version.
  static std::optional<ItemCatalog> create_in_memory(Diagnostics& diags);
  /// Opens an SQLite file, creating it when missing; migrates older schemas (each migration in
  /// a transaction). A newer schema than kSchemaVersion, or a file that is not an SQLite
  /// database, is refused with a catalog-error naming the file.
  static std::optional<ItemCatalog> open(const std::filesystem::path& path, Diagnostics& diags);
  /// The bundled catalog (built in memory from the CSV compiled into fabkit).
  static const ItemCatalog& bundled();

  /// The schema version of the open database.
  int schema_version() const;
  /// Adds or replaces the items of a CSV text (header row with the columns of
  /// docs/templates.md). All rows or none: any bad row makes a diagnostic naming
  /// `file`:line, the column and the value, and nothing is written.
  bool import_csv(std::string_view text, std::string_view file, Diagnostics& diags);
  /// The whole catalog as CSV (the same columns; rows sorted by id): import_csv(export_csv())
  /// reproduces it.
  std::string export_csv() const;
  /// Adds or replaces one item (validated like a CSV row).
  bool put(const Item& item, Diagnostics& diags);
  /// Writes a copy of the database to `path` (atomically).
  bool save_as(const std::filesystem::path& path, Diagnostics& diags) const;

  const Item* find(std::string_view id) const;
  /// Every item, sorted by id.
  std::vector<const Item*> items() const;
  std::vector<std::string> ids() const;
  std::size_t size() const;

  /// Why `item` is not acceptable ("" when it is): empty id, non-positive sizes, negative
  /// price, stock sizes larger than resizable dimensions allow, ...
  static std::string validate(const Item& item);

  struct Impl;

 private:
  explicit ItemCatalog(std::shared_ptr<Impl> impl);
  std::shared_ptr<Impl> impl_;
};

/// The SQL that creates schema version `version` from version `version - 1` (1-based), for
/// documentation and the migration tests.
std::string_view catalog_migration_sql(int version);

}  // namespace fabkit::templates
