// The items catalog on SQLite: schema migrations, CSV import/export, an in-memory index.
#include "fabkit/templates/catalog.h"

#include <fmt/format.h>
#include <sqlite3.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <tuple>

#include "embedded_data.h"
#include "fabkit/core/file_io.h"
#include "fabkit/core/text.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/templates/diagnostic_codes.h"

namespace fabkit::templates {

namespace {

constexpr std::array kCategoryNames = {
    std::pair{ItemCategory::kLumber, std::string_view("lumber")},
    std::pair{ItemCategory::kSheet, std::string_view("sheet")},
    std::pair{ItemCategory::kFastener, std::string_view("fastener")},
    std::pair{ItemCategory::kBracket, std::string_view("bracket")},
    std::pair{ItemCategory::kHinge, std::string_view("hinge")},
    std::pair{ItemCategory::kDrawerSlide, std::string_view("drawer-slide")},
    std::pair{ItemCategory::kWheel, std::string_view("wheel")},
    std::pair{ItemCategory::kPipe, std::string_view("pipe")},
    std::pair{ItemCategory::kFitting, std::string_view("fitting")},
    std::pair{ItemCategory::kHardware, std::string_view("hardware")},
};

// Schema migrations: entry v-1 turns version v-1 into version v.
constexpr std::array<std::string_view, ItemCatalog::kSchemaVersion> kMigrations = {
    // 1: items with their three dimensions, each fixed or resizable.
    R"sql(CREATE TABLE items(
  id TEXT PRIMARY KEY NOT NULL,
  name TEXT NOT NULL,
  category TEXT NOT NULL,
  material TEXT NOT NULL DEFAULT '',
  supplier TEXT NOT NULL DEFAULT '',
  part_number TEXT NOT NULL DEFAULT '',
  price REAL NOT NULL,
  unit TEXT NOT NULL DEFAULT 'piece',
  length_mm REAL NOT NULL,
  width_mm REAL NOT NULL,
  thickness_mm REAL NOT NULL,
  length_resizable INTEGER NOT NULL DEFAULT 0,
  width_resizable INTEGER NOT NULL DEFAULT 0,
  thickness_resizable INTEGER NOT NULL DEFAULT 0,
  density_kg_m3 REAL NOT NULL DEFAULT 0,
  mesh TEXT NOT NULL DEFAULT 'box');)sql",
    // 2: stock sizes (lumber lengths, sheet sizes) and pack quantities.
    R"sql(ALTER TABLE items ADD COLUMN pack_quantity INTEGER NOT NULL DEFAULT 1;
CREATE TABLE stock_sizes(
  item_id TEXT NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  length_mm REAL NOT NULL,
  width_mm REAL NOT NULL DEFAULT 0,
  price REAL NOT NULL,
  PRIMARY KEY(item_id, length_mm, width_mm));)sql",
    // 3: hardware masses, notes, and an index for browsing by category.
    R"sql(ALTER TABLE items ADD COLUMN mass_g REAL NOT NULL DEFAULT 0;
ALTER TABLE items ADD COLUMN notes TEXT NOT NULL DEFAULT '';
CREATE INDEX items_by_category ON items(category, id);)sql",
};

constexpr std::array<std::string_view, 18> kCsvColumns = {"id",
                                                          "name",
                                                          "category",
                                                          "material",
                                                          "supplier",
                                                          "part_number",
                                                          "price",
                                                          "unit",
                                                          "pack_quantity",
                                                          "length_mm",
                                                          "width_mm",
                                                          "thickness_mm",
                                                          "resizable",
                                                          "stock",
                                                          "density_kg_m3",
                                                          "mass_g",
                                                          "mesh",
                                                          "notes"};

std::string fmt_number(double v) {
  if (v == std::floor(v) && std::abs(v) < 1e15) return fmt::format("{}", static_cast<long long>(v));
  std::string s = fmt::format("{:.6f}", v);
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

std::string csv_field(std::string_view s) {
  if (s.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(s);
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

struct CsvRow {
  int line = 0;
  std::vector<std::string> fields;
};

// RFC 4180 records (quoted fields may hold commas, quotes and newlines).
std::optional<std::vector<CsvRow>> parse_csv(std::string_view text,
                                             std::string_view file,
                                             Diagnostics& diags) {
  std::vector<CsvRow> rows;
  CsvRow row;
  std::string field;
  int line = 1;
  row.line = 1;
  bool quoted = false, field_started = false, any = false;
  auto end_field = [&] {
    row.fields.push_back(std::move(field));
    field.clear();
    field_started = false;
  };
  auto end_row = [&] {
    end_field();
    const bool blank = row.fields.size() == 1 && row.fields[0].empty();
    if (!blank) rows.push_back(std::move(row));
    row = CsvRow{};
    row.line = line;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    any = true;
    if (quoted) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        if (c == '\n') ++line;
        field += c;
      }
      continue;
    }
    if (c == '"' && !field_started) {
      quoted = true;
      field_started = true;
    } else if (c == ',') {
      end_field();
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      ++line;
      end_row();
    } else {
      field += c;
      field_started = true;
    }
  }
  if (quoted) {
    diags.error(codes::kMalformedInput,
                "a quoted field is not closed (missing '\"')",
                SourceLocation{std::string(file), row.line, 0});
    return std::nullopt;
  }
  if (any && (!field.empty() || !row.fields.empty())) end_row();
  return rows;
}

std::optional<double> parse_double(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (s.empty()) return std::nullopt;
  double v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t at = s.find(sep, start);
    const std::size_t end = at == std::string_view::npos ? s.size() : at;
    std::string_view piece = s.substr(start, end - start);
    while (!piece.empty() && piece.front() == ' ') piece.remove_prefix(1);
    while (!piece.empty() && piece.back() == ' ') piece.remove_suffix(1);
    if (!piece.empty()) out.push_back(piece);
    if (at == std::string_view::npos) break;
    start = at + 1;
  }
  return out;
}

std::string stock_text(const Item& item) {
  std::string out;
  for (const StockSize& s : item.stock) {
    if (!out.empty()) out += ';';
    out += fmt_number(s.length_mm);
    if (s.width_mm > 0) out += "x" + fmt_number(s.width_mm);
    out += "@" + fmt_number(s.price);
  }
  return out;
}

std::string resizable_text(const Item& item) {
  static constexpr std::array<std::string_view, 3> kNames = {"length", "width", "thickness"};
  std::string out;
  for (int k = 0; k < 3; ++k) {
    if (!item.dims[k].resizable) continue;
    if (!out.empty()) out += ';';
    out += kNames[k];
  }
  return out;
}

// Stock sizes smallest first (the order the database returns them in).
void sort_stock(Item& it) {
  std::sort(it.stock.begin(), it.stock.end(), [](const StockSize& a, const StockSize& b) {
    return std::tie(a.length_mm, a.width_mm) < std::tie(b.length_mm, b.width_mm);
  });
}

// ---- SQLite helpers (RAII statement, error text) -------------------------------------------

struct Statement {
  sqlite3_stmt* stmt = nullptr;
  Statement(sqlite3* db, std::string_view sql) {
    sqlite3_prepare_v2(db, sql.data(), static_cast<int>(sql.size()), &stmt, nullptr);
  }
  ~Statement() { sqlite3_finalize(stmt); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  explicit operator bool() const { return stmt != nullptr; }
  void bind(int i, std::string_view s) {
    sqlite3_bind_text(stmt, i, s.data(), static_cast<int>(s.size()), SQLITE_TRANSIENT);
  }
  void bind(int i, double v) { sqlite3_bind_double(stmt, i, v); }
  void bind(int i, int v) { sqlite3_bind_int(stmt, i, v); }
  std::string text(int col) const {
    const unsigned char* t = sqlite3_column_text(stmt, col);
    return t ? std::string(reinterpret_cast<const char*>(t)) : std::string();
  }
  double real(int col) const { return sqlite3_column_double(stmt, col); }
  int integer(int col) const { return sqlite3_column_int(stmt, col); }
};

}  // namespace

std::string_view to_string(ItemCategory c) {
  for (const auto& [k, name] : kCategoryNames) {
    if (k == c) return name;
  }
  return "hardware";
}

std::optional<ItemCategory> category_from_string(std::string_view s) {
  for (const auto& [k, name] : kCategoryNames) {
    if (name == s) return k;
  }
  return std::nullopt;
}

std::span<const ItemCategory> all_categories() {
  static constexpr std::array kAll = {ItemCategory::kLumber,
                                      ItemCategory::kSheet,
                                      ItemCategory::kFastener,
                                      ItemCategory::kBracket,
                                      ItemCategory::kHinge,
                                      ItemCategory::kDrawerSlide,
                                      ItemCategory::kWheel,
                                      ItemCategory::kPipe,
                                      ItemCategory::kFitting,
                                      ItemCategory::kHardware};
  return kAll;
}

std::string_view catalog_migration_sql(int version) {
  if (version < 1 || version > ItemCatalog::kSchemaVersion) return {};
  return kMigrations[version - 1];
}

bool Item::cut_to_size() const {
  return dims[0].resizable || dims[1].resizable || dims[2].resizable;
}

double Item::part_mass_kg(const Vec3& size) const {
  if (density_kg_m3 > 0) return density_kg_m3 * size.x() * size.y() * size.z() * 1e-9;
  return mass_g * 1e-3;
}

std::vector<StockSize> Item::stock_sizes() const {
  if (!stock.empty()) return stock;
  return {StockSize{dims[0].mm, category == ItemCategory::kSheet ? dims[1].mm : 0.0, price}};
}

std::string ItemCatalog::validate(const Item& item) {
  if (item.id.empty()) return "the id is empty";
  if (item.id.size() > 64) return "the id is longer than 64 characters";
  for (char c : item.id) {
    const bool ok =
        std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' || c == '/';
    if (!ok)
      return fmt::format("the id '{}' has a character other than letters, digits, - _ . /",
                         excerpt(item.id));
  }
  if (item.name.empty()) return "the name is empty";
  if (!is_valid_utf8(item.name) || !is_valid_utf8(item.material) || !is_valid_utf8(item.supplier) ||
      !is_valid_utf8(item.notes)) {
    return "a text field is not valid UTF-8";
  }
  if (!(item.price >= 0) || item.price > 1e6) {
    return fmt::format("price {} is not between 0 and 1000000 USD", item.price);
  }
  if (item.pack_quantity < 1 || item.pack_quantity > 100000) {
    return fmt::format("pack_quantity {} is not between 1 and 100000", item.pack_quantity);
  }
  static constexpr std::array<std::string_view, 3> kNames = {"length", "width", "thickness"};
  for (int k = 0; k < 3; ++k) {
    if (!(item.dims[k].mm > 0) || item.dims[k].mm > 1e5) {
      return fmt::format("{} {} mm is not between 0 and 100000 mm", kNames[k], item.dims[k].mm);
    }
  }
  if (item.density_kg_m3 < 0 || item.density_kg_m3 > 30000) {
    return fmt::format("density {} kg/m³ is not between 0 and 30000", item.density_kg_m3);
  }
  if (item.mass_g < 0 || item.mass_g > 1e6) {
    return fmt::format("mass {} g is not between 0 and 1000000", item.mass_g);
  }
  for (const StockSize& s : item.stock) {
    if (!(s.length_mm > 0) || s.length_mm > item.dims[0].mm + 1e-9) {
      return fmt::format("stock length {} mm is not between 0 and the item's length {} mm",
                         s.length_mm,
                         item.dims[0].mm);
    }
    if (s.width_mm < 0 || s.width_mm > item.dims[1].mm + 1e-9) {
      return fmt::format("stock width {} mm is not between 0 and the item's width {} mm",
                         s.width_mm,
                         item.dims[1].mm);
    }
    if (!(s.price >= 0)) return fmt::format("stock price {} is negative", s.price);
  }
  return "";
}

// ---- the database -----------------------------------------------------------------------------

struct ItemCatalog::Impl {
  sqlite3* db = nullptr;
  std::string name;  // the file, or ":memory:"
  std::map<std::string, Item, std::less<>> items;
  mutable std::mutex mutex;

  ~Impl() {
    if (db) sqlite3_close(db);
  }

  std::string error() const { return db ? sqlite3_errmsg(db) : "out of memory"; }

  bool exec(std::string_view sql, Diagnostics& diags, std::string_view what) {
    char* message = nullptr;
    const std::string text(sql);
    if (sqlite3_exec(db, text.c_str(), nullptr, nullptr, &message) == SQLITE_OK) return true;
    diags.error(codes::kCatalogError,
                fmt::format("catalog {}: {} failed: {}", name, what, message ? message : "?"));
    sqlite3_free(message);
    return false;
  }

  int user_version() const {
    Statement s(db, "PRAGMA user_version");
    return s && sqlite3_step(s.stmt) == SQLITE_ROW ? s.integer(0) : -1;
  }

  bool migrate(Diagnostics& diags) {
    const int have = user_version();
    if (have < 0) {
      diags.error(codes::kCatalogError,
                  fmt::format("catalog {} is not an SQLite database ({})", name, error()));
      return false;
    }
    if (have > kSchemaVersion) {
      diags.error(codes::kCatalogError,
                  fmt::format("catalog {} has schema version {}, newer than this fabkit's {}; "
                              "use a newer fabkit",
                              name,
                              have,
                              kSchemaVersion));
      return false;
    }
    for (int v = have + 1; v <= kSchemaVersion; ++v) {
      const std::string sql = fmt::format(
          "BEGIN;\n{}\nPRAGMA user_version = {};\nCOMMIT;", catalog_migration_sql(v), v);
      if (!exec(sql, diags, fmt::format("migration to schema version {}", v))) {
        exec("ROLLBACK;", diags, "rollback");
        return false;
      }
    }
    return true;
  }

  bool load(Diagnostics& diags) {
    items.clear();
    Statement s(db,
                "SELECT id, name, category, material, supplier, part_number, price, unit, "
                "pack_quantity, length_mm, width_mm, thickness_mm, length_resizable, "
                "width_resizable, thickness_resizable, density_kg_m3, mass_g, mesh, notes "
                "FROM items ORDER BY id");
    if (!s) {
      diags.error(codes::kCatalogError, fmt::format("catalog {}: {}", name, error()));
      return false;
    }
    while (sqlite3_step(s.stmt) == SQLITE_ROW) {
      Item it;
      it.id = s.text(0);
      it.name = s.text(1);
      it.category = category_from_string(s.text(2)).value_or(ItemCategory::kHardware);
      it.material = s.text(3);
      it.supplier = s.text(4);
      it.part_number = s.text(5);
      it.price = s.real(6);
      it.unit = s.text(7);
      it.pack_quantity = s.integer(8);
      for (int k = 0; k < 3; ++k) {
        it.dims[k].mm = s.real(9 + k);
        it.dims[k].resizable = s.integer(12 + k) != 0;
      }
      it.density_kg_m3 = s.real(15);
      it.mass_g = s.real(16);
      it.mesh = s.text(17);
      it.notes = s.text(18);
      items.emplace(it.id, std::move(it));
    }
    Statement st(db,
                 "SELECT item_id, length_mm, width_mm, price FROM stock_sizes "
                 "ORDER BY item_id, length_mm, width_mm");
    while (st && sqlite3_step(st.stmt) == SQLITE_ROW) {
      auto it = items.find(st.text(0));
      if (it == items.end()) continue;
      it->second.stock.push_back(StockSize{st.real(1), st.real(2), st.real(3)});
    }
    return true;
  }

  bool write(const Item& it, Diagnostics& diags) {
    Statement s(db,
                "INSERT OR REPLACE INTO items(id, name, category, material, supplier, "
                "part_number, price, unit, pack_quantity, length_mm, width_mm, thickness_mm, "
                "length_resizable, width_resizable, thickness_resizable, density_kg_m3, mass_g, "
                "mesh, notes) VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    Statement del(db, "DELETE FROM stock_sizes WHERE item_id = ?");
    Statement add(db,
                  "INSERT INTO stock_sizes(item_id, length_mm, width_mm, price) VALUES(?,?,?,?)");
    if (!s || !del || !add) {
      diags.error(codes::kCatalogError, fmt::format("catalog {}: {}", name, error()));
      return false;
    }
    s.bind(1, it.id);
    s.bind(2, it.name);
    s.bind(3, to_string(it.category));
    s.bind(4, it.material);
    s.bind(5, it.supplier);
    s.bind(6, it.part_number);
    s.bind(7, it.price);
    s.bind(8, it.unit);
    s.bind(9, it.pack_quantity);
    for (int k = 0; k < 3; ++k) {
      s.bind(10 + k, it.dims[k].mm);
      s.bind(13 + k, it.dims[k].resizable ? 1 : 0);
    }
    s.bind(16, it.density_kg_m3);
    s.bind(17, it.mass_g);
    s.bind(18, it.mesh);
    s.bind(19, it.notes);
    del.bind(1, it.id);
    if (sqlite3_step(s.stmt) != SQLITE_DONE || sqlite3_step(del.stmt) != SQLITE_DONE) {
      diags.error(codes::kCatalogError,
                  fmt::format("catalog {}: writing item {}: {}", name, it.id, error()));
      return false;
    }
    for (const StockSize& st : it.stock) {
      sqlite3_reset(add.stmt);
      add.bind(1, it.id);
      add.bind(2, st.length_mm);
      add.bind(3, st.width_mm);
      add.bind(4, st.price);
      if (sqlite3_step(add.stmt) != SQLITE_DONE) {
        diags.error(codes::kCatalogError,
                    fmt::format("catalog {}: stock of item {}: {}", name, it.id, error()));
        return false;
      }
    }
    return true;
  }
};

ItemCatalog::ItemCatalog(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

namespace {

std::optional<std::shared_ptr<ItemCatalog::Impl>> open_impl(const std::string& name,
                                                            Diagnostics& diags) {
  auto impl = std::make_shared<ItemCatalog::Impl>();
  impl->name = name;
  const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX;
  if (sqlite3_open_v2(name.c_str(), &impl->db, flags, nullptr) != SQLITE_OK) {
    diags.error(codes::kCatalogError,
                fmt::format("cannot open catalog {}: {}", name, impl->error()));
    return std::nullopt;
  }
  sqlite3_busy_timeout(impl->db, 2000);
  if (!impl->exec("PRAGMA foreign_keys = ON;", diags, "enabling foreign keys")) {
    return std::nullopt;
  }
  if (!impl->migrate(diags) || !impl->load(diags)) return std::nullopt;
  return impl;
}

}  // namespace

std::optional<ItemCatalog> ItemCatalog::create_in_memory(Diagnostics& diags) {
  auto impl = open_impl(":memory:", diags);
  if (!impl) return std::nullopt;
  return ItemCatalog(*impl);
}

std::optional<ItemCatalog> ItemCatalog::open(const std::filesystem::path& path,
                                             Diagnostics& diags) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec)) {
    diags.error(codes::kCatalogError,
                fmt::format("catalog {} is not a regular file", path.string()));
    return std::nullopt;
  }
  auto impl = open_impl(path.string(), diags);
  if (!impl) return std::nullopt;
  return ItemCatalog(*impl);
}

const ItemCatalog& ItemCatalog::bundled() {
  static const ItemCatalog catalog = [] {
    Diagnostics d;
    auto c = create_in_memory(d);
    // The bundled CSV is tested; failing here is a build defect, not user input.
    if (!c || !c->import_csv(embedded::catalog_csv(), "items.csv (bundled)", d)) {
      std::fprintf(stderr, "fabkit: internal error: bundled catalog: %s\n", d.format().c_str());
      std::abort();
    }
    return *c;
  }();
  return catalog;
}

int ItemCatalog::schema_version() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->user_version();
}

bool ItemCatalog::put(const Item& given, Diagnostics& diags) {
  Item item = given;
  sort_stock(item);
  const std::string why = validate(item);
  if (!why.empty()) {
    diags.error(codes::kInvalidValue, fmt::format("item '{}': {}", excerpt(item.id), why));
    return false;
  }
  std::lock_guard lock(impl_->mutex);
  if (!impl_->exec("BEGIN;", diags, "begin")) return false;
  if (!impl_->write(item, diags)) {
    impl_->exec("ROLLBACK;", diags, "rollback");
    return false;
  }
  if (!impl_->exec("COMMIT;", diags, "commit")) return false;
  impl_->items[item.id] = item;
  return true;
}

bool ItemCatalog::import_csv(std::string_view text, std::string_view file, Diagnostics& diags) {
  const auto rows = parse_csv(text, file, diags);
  if (!rows) return false;
  auto where = [&](int line) { return SourceLocation{std::string(file), line, 0}; };
  if (rows->empty()) {
    diags.error(codes::kMalformedInput, "the CSV file is empty (no header row)", where(1));
    return false;
  }
  // Columns by header name, so a user's file may order them freely and omit optional ones.
  const CsvRow& header = rows->front();
  std::map<std::string, std::size_t, std::less<>> column;
  for (std::size_t i = 0; i < header.fields.size(); ++i) {
    const std::string& h = header.fields[i];
    if (std::find(kCsvColumns.begin(), kCsvColumns.end(), h) == kCsvColumns.end()) {
      std::vector<std::string> known(kCsvColumns.begin(), kCsvColumns.end());
      diags.error(codes::kMalformedInput,
                  fmt::format("unknown column '{}'{}; the columns are: {}",
                              excerpt(h),
                              did_you_mean(h, known),
                              fmt::join(kCsvColumns, ", ")),
                  where(header.line));
      return false;
    }
    column[h] = i;
  }
  for (std::string_view required :
       {"id", "name", "category", "price", "length_mm", "width_mm", "thickness_mm"}) {
    if (!column.count(required)) {
      diags.error(codes::kMalformedInput,
                  fmt::format("the header lacks the required column '{}'", required),
                  where(header.line));
      return false;
    }
  }
  std::vector<Item> parsed;
  int errors = 0;
  std::map<std::string, int, std::less<>> seen;
  for (std::size_t r = 1; r < rows->size(); ++r) {
    const CsvRow& row = (*rows)[r];
    auto get = [&](std::string_view name) -> std::string {
      auto it = column.find(name);
      if (it == column.end() || it->second >= row.fields.size()) return "";
      return row.fields[it->second];
    };
    auto bad = [&](std::string_view col, const std::string& value, std::string_view why) {
      diags.error(codes::kInvalidValue,
                  fmt::format("column {}: '{}' {}", col, excerpt(value), why),
                  where(row.line));
      ++errors;
    };
    if (row.fields.size() > header.fields.size()) {
      diags.error(codes::kMalformedInput,
                  fmt::format("{} fields, but the header has {} columns (quote fields that "
                              "contain commas)",
                              row.fields.size(),
                              header.fields.size()),
                  where(row.line));
      ++errors;
      continue;
    }
    Item it;
    it.id = get("id");
    it.name = get("name");
    it.material = get("material");
    it.supplier = get("supplier");
    it.part_number = get("part_number");
    it.notes = get("notes");
    if (const std::string u = get("unit"); !u.empty()) it.unit = u;
    if (const std::string m = get("mesh"); !m.empty()) it.mesh = m;
    const std::string cat = get("category");
    if (auto c = category_from_string(cat)) {
      it.category = *c;
    } else {
      std::vector<std::string> names;
      for (const auto& [k, n] : kCategoryNames) names.emplace_back(n);
      bad("category",
          cat,
          fmt::format("is not a category{}; expected one of: {}",
                      did_you_mean(cat, names),
                      fmt::join(names, ", ")));
      continue;
    }
    auto number =
        [&](std::string_view col, double fallback, bool required) -> std::optional<double> {
      const std::string v = get(col);
      if (v.empty() && !required) return fallback;
      auto d = parse_double(v);
      if (!d) bad(col, v, "is not a number");
      return d;
    };
    const auto price = number("price", 0, true);
    const auto pack = number("pack_quantity", 1, false);
    const auto len = number("length_mm", 0, true);
    const auto wid = number("width_mm", 0, true);
    const auto thk = number("thickness_mm", 0, true);
    const auto density = number("density_kg_m3", 0, false);
    const auto mass = number("mass_g", 0, false);
    if (!price || !pack || !len || !wid || !thk || !density || !mass) continue;
    if (*pack != std::floor(*pack)) {
      bad("pack_quantity", get("pack_quantity"), "is not a whole number");
      continue;
    }
    it.price = *price;
    it.pack_quantity = static_cast<int>(std::clamp(*pack, -1.0, 1e6));
    it.dims = {ItemDimension{*len, false}, ItemDimension{*wid, false}, ItemDimension{*thk, false}};
    it.density_kg_m3 = *density;
    it.mass_g = *mass;
    bool ok = true;
    const std::string resizable = get("resizable");
    const std::string stock = get("stock");
    for (std::string_view word : split(resizable, ';')) {
      if (word == "length") {
        it.dims[0].resizable = true;
      } else if (word == "width") {
        it.dims[1].resizable = true;
      } else if (word == "thickness") {
        it.dims[2].resizable = true;
      } else {
        bad("resizable", std::string(word), "is not one of length, width, thickness");
        ok = false;
      }
    }
    for (std::string_view s : split(stock, ';')) {
      const std::size_t at = s.find('@');
      std::string_view size = s.substr(0, at);
      const std::size_t x = size.find('x');
      const auto l = parse_double(size.substr(0, x));
      const auto w =
          x == std::string_view::npos ? std::optional<double>(0) : parse_double(size.substr(x + 1));
      const auto p =
          at == std::string_view::npos ? std::optional<double>() : parse_double(s.substr(at + 1));
      if (!l || !w || !p) {
        bad("stock",
            std::string(s),
            "is not LENGTH@PRICE or LENGTHxWIDTH@PRICE (mm, USD; several separated by ';')");
        ok = false;
        continue;
      }
      it.stock.push_back(StockSize{*l, *w, *p});
    }
    if (!ok) continue;
    sort_stock(it);
    if (const std::string why = validate(it); !why.empty()) {
      diags.error(
          codes::kInvalidValue, fmt::format("item '{}': {}", excerpt(it.id), why), where(row.line));
      ++errors;
      continue;
    }
    if (auto [pos, inserted] = seen.emplace(it.id, row.line); !inserted) {
      diags.error(codes::kDuplicateName,
                  fmt::format("item '{}' is already defined on line {}", it.id, pos->second),
                  where(row.line));
      ++errors;
      continue;
    }
    parsed.push_back(std::move(it));
  }
  if (errors) return false;
  std::lock_guard lock(impl_->mutex);
  if (!impl_->exec("BEGIN;", diags, "begin")) return false;
  for (const Item& it : parsed) {
    if (!impl_->write(it, diags)) {
      impl_->exec("ROLLBACK;", diags, "rollback");
      return false;
    }
  }
  if (!impl_->exec("COMMIT;", diags, "commit")) return false;
  for (Item& it : parsed) impl_->items[it.id] = std::move(it);
  return true;
}

std::string ItemCatalog::export_csv() const {
  std::lock_guard lock(impl_->mutex);
  std::string out = fmt::format("{}\n", fmt::join(kCsvColumns, ","));
  for (const auto& [id, it] : impl_->items) {
    const std::array<std::string, 18> f = {it.id,
                                           it.name,
                                           std::string(to_string(it.category)),
                                           it.material,
                                           it.supplier,
                                           it.part_number,
                                           fmt_number(it.price),
                                           it.unit,
                                           fmt_number(it.pack_quantity),
                                           fmt_number(it.dims[0].mm),
                                           fmt_number(it.dims[1].mm),
                                           fmt_number(it.dims[2].mm),
                                           resizable_text(it),
                                           stock_text(it),
                                           fmt_number(it.density_kg_m3),
                                           fmt_number(it.mass_g),
                                           it.mesh,
                                           it.notes};
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (i) out += ',';
      out += csv_field(f[i]);
    }
    out += '\n';
  }
  return out;
}

bool ItemCatalog::save_as(const std::filesystem::path& path, Diagnostics& diags) const {
  // The database's image, written like every other output (write_file_atomically): never a
  // half-written file, never through a FIFO, a device or a link out of its directory.
  std::string bytes;
  {
    std::lock_guard lock(impl_->mutex);
    sqlite3_int64 size = 0;
    unsigned char* data = sqlite3_serialize(impl_->db, "main", &size, 0);
    if (!data) {
      diags.error(codes::kWriteFailed,
                  fmt::format("cannot write {}: {}", path.string(), impl_->error()));
      return false;
    }
    bytes.assign(reinterpret_cast<const char*>(data), static_cast<std::size_t>(size));
    sqlite3_free(data);
  }
  return write_file_atomically(path, bytes, diags);
}

const Item* ItemCatalog::find(std::string_view id) const {
  std::lock_guard lock(impl_->mutex);
  auto it = impl_->items.find(id);
  return it == impl_->items.end() ? nullptr : &it->second;
}

std::vector<const Item*> ItemCatalog::items() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<const Item*> out;
  for (const auto& [id, it] : impl_->items) out.push_back(&it);
  return out;
}

std::vector<std::string> ItemCatalog::ids() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<std::string> out;
  for (const auto& [id, it] : impl_->items) out.push_back(id);
  return out;
}

std::size_t ItemCatalog::size() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->items.size();
}

}  // namespace fabkit::templates
