// The items catalog: the bundled data, CSV round trips, SQLite migrations, bad input.
#include "fabkit/templates/catalog.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <set>

#include "fabkit/templates/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::templates {
namespace {

using testing::has_diagnostic;

std::filesystem::path temp_file(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "fabkit_templates_tests";
  std::filesystem::create_directories(dir);
  const auto p = dir / name;
  std::filesystem::remove(p);
  return p;
}

TEST(Catalog, BundledCatalogHasRealisticItemsOfEveryCategory) {
  const ItemCatalog& c = ItemCatalog::bundled();
  EXPECT_GE(c.size(), 120u);
  std::map<ItemCategory, int> per;
  for (const Item* it : c.items()) {
    ++per[it->category];
    EXPECT_EQ(ItemCatalog::validate(*it), "") << it->id;
    EXPECT_FALSE(it->supplier.empty()) << it->id;
    EXPECT_FALSE(it->part_number.empty()) << it->id;
    EXPECT_GT(it->price, 0) << it->id;
    // Cut goods resize; hardware never does.
    const bool cut = it->category == ItemCategory::kLumber ||
                     it->category == ItemCategory::kSheet || it->category == ItemCategory::kPipe;
    if (it->category != ItemCategory::kHinge) {
      EXPECT_EQ(it->cut_to_size(), cut) << it->id;
    }
  }
  for (ItemCategory k : all_categories()) EXPECT_GE(per[k], 5) << to_string(k);
  // Spot checks against real stock: a 2x4 is 38 x 89 mm, 12 ft long at most, cut to length.
  const Item* stud = c.find("LUM-PINE-2x4");
  ASSERT_TRUE(stud);
  EXPECT_DOUBLE_EQ(stud->dims[1].mm, 89);
  EXPECT_DOUBLE_EQ(stud->dims[2].mm, 38);
  EXPECT_TRUE(stud->dims[0].resizable);
  EXPECT_FALSE(stud->dims[1].resizable);
  EXPECT_EQ(stud->stock.size(), 3u);
  const Item* ply = c.find("PLY-BIRCH-18");
  ASSERT_TRUE(ply);
  EXPECT_TRUE(ply->dims[0].resizable && ply->dims[1].resizable && !ply->dims[2].resizable);
  EXPECT_DOUBLE_EQ(ply->stock_sizes().back().width_mm, 1220);
  const Item* screw = c.find("SCR-4x40");
  ASSERT_TRUE(screw);
  EXPECT_EQ(screw->pack_quantity, 100);
  EXPECT_FALSE(screw->cut_to_size());
  // Mass from density: a 600 x 89 x 38 mm pine piece at 510 kg/m³ is 1.035 kg.
  EXPECT_NEAR(stud->part_mass_kg(Vec3(600, 89, 38)), 510 * 0.6 * 0.089 * 0.038, 1e-12);
}

TEST(Catalog, CsvRoundTripReproducesEveryItem) {
  const ItemCatalog& bundled = ItemCatalog::bundled();
  const std::string csv = bundled.export_csv();
  Diagnostics d;
  auto copy = ItemCatalog::create_in_memory(d);
  ASSERT_TRUE(copy);
  ASSERT_TRUE(copy->import_csv(csv, "export.csv", d)) << d.format();
  EXPECT_EQ(copy->size(), bundled.size());
  EXPECT_EQ(copy->export_csv(), csv);
  for (const Item* it : bundled.items()) {
    const Item* other = copy->find(it->id);
    ASSERT_TRUE(other);
    EXPECT_EQ(other->name, it->name);
    EXPECT_EQ(other->stock.size(), it->stock.size());
    EXPECT_EQ(other->dims[0].resizable, it->dims[0].resizable);
    EXPECT_DOUBLE_EQ(other->price, it->price);
  }
}

TEST(Catalog, SqliteFileRoundTripAndReopen) {
  const auto path = temp_file("catalog.sqlite");
  Diagnostics d;
  ASSERT_TRUE(ItemCatalog::bundled().save_as(path, d)) << d.format();
  auto opened = ItemCatalog::open(path, d);
  ASSERT_TRUE(opened) << d.format();
  EXPECT_EQ(opened->schema_version(), ItemCatalog::kSchemaVersion);
  EXPECT_EQ(opened->export_csv(), ItemCatalog::bundled().export_csv());
}

TEST(Catalog, MigratesVersionOneDatabasesKeepingTheirItems) {
  const auto path = temp_file("v1.sqlite");
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    const std::string sql = std::string(catalog_migration_sql(1)) +
                            "INSERT INTO items(id, name, category, price, length_mm, width_mm, "
                            "thickness_mm, length_resizable) VALUES('MY-BOARD', 'my board', "
                            "'lumber', 7.5, 2400, 140, 21, 1);"
                            "PRAGMA user_version = 1;";
    ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  Diagnostics d;
  auto c = ItemCatalog::open(path, d);
  ASSERT_TRUE(c) << d.format();
  EXPECT_EQ(c->schema_version(), 3);
  const Item* board = c->find("MY-BOARD");
  ASSERT_TRUE(board);
  EXPECT_EQ(board->pack_quantity, 1);  // column added by migration 2, default kept
  EXPECT_EQ(board->mass_g, 0);         // migration 3
  EXPECT_TRUE(board->dims[0].resizable);
  // The migrated database accepts the new columns.
  Item with_stock = *board;
  with_stock.stock = {StockSize{2400, 0, 7.5}};
  with_stock.notes = "from my store";
  ASSERT_TRUE(c->put(with_stock, d)) << d.format();
  auto again = ItemCatalog::open(path, d);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->find("MY-BOARD")->stock.size(), 1u);
  EXPECT_EQ(again->find("MY-BOARD")->notes, "from my store");
}

TEST(Catalog, RefusesNewerSchemasAndNonDatabases) {
  const auto newer = temp_file("newer.sqlite");
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(newer.c_str(), &db), SQLITE_OK);
    sqlite3_exec(db, "PRAGMA user_version = 99;", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  Diagnostics d;
  EXPECT_FALSE(ItemCatalog::open(newer, d));
  EXPECT_TRUE(has_diagnostic(d, codes::kCatalogError, "schema version 99, newer than"));
  const auto text = temp_file("text.sqlite");
  {
    std::FILE* f = std::fopen(text.c_str(), "w");
    std::fputs("not a database at all, just text\n", f);
    std::fclose(f);
  }
  Diagnostics d2;
  EXPECT_FALSE(ItemCatalog::open(text, d2));
  EXPECT_TRUE(has_diagnostic(d2, codes::kCatalogError, "text.sqlite"));
}

TEST(Catalog, BadCsvRowsNameLineColumnAndValueAndWriteNothing) {
  Diagnostics d;
  auto c = ItemCatalog::create_in_memory(d);
  ASSERT_TRUE(c);
  const std::string csv =
      "id,name,category,price,length_mm,width_mm,thickness_mm,resizable,stock\n"
      "GOOD,good board,lumber,5,2400,89,19,length,2400@5\n"
      "BAD1,bad board,lumbr,5,2400,89,19,,\n"
      "BAD2,bad price,lumber,cheap,2400,89,19,,\n"
      "BAD3,bad stock,lumber,5,2400,89,19,length,2400-5\n"
      "GOOD,again,lumber,5,2400,89,19,,\n";
  EXPECT_FALSE(c->import_csv(csv, "store.csv", d));
  EXPECT_TRUE(has_diagnostic(d,
                             codes::kInvalidValue,
                             "column category: 'lumbr' is not a category; did you mean 'lumber'?"));
  EXPECT_TRUE(has_diagnostic(d, codes::kInvalidValue, "column price: 'cheap' is not a number"));
  EXPECT_TRUE(has_diagnostic(d, codes::kInvalidValue, "column stock: '2400-5'"));
  EXPECT_TRUE(has_diagnostic(d, codes::kDuplicateName, "item 'GOOD' is already defined on line 2"));
  bool line3 = false;
  for (const Diagnostic& x : d) line3 |= x.where.file == "store.csv" && x.where.line == 3;
  EXPECT_TRUE(line3);
  EXPECT_EQ(c->size(), 0u);  // all or nothing
  Diagnostics d2;
  EXPECT_FALSE(c->import_csv("id,name,colour\n", "x.csv", d2));
  EXPECT_TRUE(has_diagnostic(d2, codes::kMalformedInput, "unknown column 'colour'"));
  Diagnostics d3;
  EXPECT_FALSE(
      c->import_csv("id,name,category,price,length_mm,width_mm,thickness_mm\n"
                    "X,\"quoted, with comma\",lumber,1,2,3,-4\n",
                    "y.csv",
                    d3));
  EXPECT_TRUE(
      has_diagnostic(d3, codes::kInvalidValue, "thickness -4 mm is not between 0 and 100000"));
}

TEST(Catalog, UserItemsImportNextToTheBundledOnes) {
  Diagnostics d;
  auto c = ItemCatalog::create_in_memory(d);
  ASSERT_TRUE(c);
  ASSERT_TRUE(c->import_csv(ItemCatalog::bundled().export_csv(), "bundled", d));
  ASSERT_TRUE(c->import_csv(
      "id,name,category,price,length_mm,width_mm,thickness_mm,resizable,stock,supplier\n"
      "STORE-OAK-1x4,\"oak 1x4, S4S\",lumber,21.5,2438,89,19,length,1829@16.5;2438@21.5,My store\n",
      "my_store.csv",
      d))
      << d.format();
  EXPECT_EQ(c->size(), ItemCatalog::bundled().size() + 1);
  EXPECT_EQ(c->find("STORE-OAK-1x4")->name, "oak 1x4, S4S");
  EXPECT_EQ(c->find("STORE-OAK-1x4")->stock.size(), 2u);
}

}  // namespace
}  // namespace fabkit::templates
