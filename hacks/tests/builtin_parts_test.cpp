// Checks the built-in parts against the parts table of the reference (§10.2), read from the
// shared reference file at test time so that a transcription slip in builtin_parts.cpp shows.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/hacks/diagnostic_codes.h"
#include "fabkit/hacks/parts_library.h"

namespace fabkit::hacks {
namespace {

constexpr double kTol = 1e-9;

struct RowPrimitive {
  std::string name;
  std::string type;
  std::map<std::string, double> shape;
  std::vector<std::string> flags;  // HookFlex, RodCtl, is_open=False, ...
  std::optional<std::array<double, 2>> theta_range;
  Vec3 pos = Vec3::Zero();
  Vec3 rot = Vec3::Zero();
};

struct Row {
  std::string name;
  std::string library;
  double mass = 0;
  std::string primitives_cell;
  std::vector<RowPrimitive> primitives;
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, const std::string& sep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const auto pos = s.find(sep, start);
    if (pos == std::string::npos) {
      out.push_back(s.substr(start));
      return out;
    }
    out.push_back(s.substr(start, pos - start));
    start = pos + sep.size();
  }
}

// The table writes some minus signs as U+2212.
std::string ascii_minus(const std::string& s) {
  const std::string_view minus = "\xE2\x88\x92";
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    if (std::string_view(s).substr(i, minus.size()) == minus) {
      out += '-';
      i += minus.size();
    } else {
      out += s[i++];
    }
  }
  return out;
}

Vec3 parse_vec3(const std::string& s) {
  const auto parts = split(s, ",");
  EXPECT_EQ(parts.size(), 3u) << s;
  Vec3 v = Vec3::Zero();
  for (std::size_t i = 0; i < std::min<std::size_t>(3, parts.size()); ++i) {
    v[static_cast<int>(i)] = std::stod(trim(parts[i]));
  }
  return v;
}

// "hook1 = Hook(arc_radius 12.5, arc_angle 180, thickness 1.25) [HookFlex] @ (0, 16, -61) / [90, 0,
// 0]"
std::optional<RowPrimitive> parse_primitive(const std::string& text) {
  static const std::regex re(
      R"(^(\w+) = (\w+)\(([^)]*)\)\s*(\[.*\])?\s*@ \(([^)]*)\) / \[([^\]]*)\]$)");
  std::smatch m;
  const std::string t = trim(ascii_minus(text));
  if (!std::regex_match(t, m, re)) return std::nullopt;
  RowPrimitive p;
  p.name = m[1];
  p.type = m[2];
  for (const std::string& kv : split(m[3], ",")) {
    const std::string f = trim(kv);
    const auto space = f.find(' ');
    p.shape[f.substr(0, space)] = std::stod(f.substr(space + 1));
  }
  std::string flags = m[4];
  if (!flags.empty()) {
    flags = flags.substr(1, flags.size() - 2);
    static const std::regex theta(R"(θ range \[([^,\]]+), ([^\]]+)\])");
    std::smatch tm;
    if (std::regex_search(flags, tm, theta)) {
      p.theta_range = std::array<double, 2>{std::stod(tm[1]), std::stod(tm[2])};
      flags = tm.prefix().str() + tm.suffix().str();
    }
    for (const std::string& f : split(flags, ",")) {
      if (!trim(f).empty()) p.flags.push_back(trim(f));
    }
  }
  p.pos = parse_vec3(m[5]);
  p.rot = parse_vec3(m[6]);
  return p;
}

// Rows of the §10.2 table; empty if the reference is not there.
std::vector<Row> read_table() {
  std::ifstream in(std::string(FABKIT_SHARED_DIR) + "/reference/fabhacks-reference.md");
  if (!in) return {};
  std::vector<Row> rows;
  std::string line;
  bool in_section = false;
  bool in_table = false;
  while (std::getline(in, line)) {
    if (line.starts_with("### 10.2")) {
      in_section = true;
      continue;
    }
    if (!in_section) continue;
    if (!line.starts_with("|")) {
      if (in_table) break;
      continue;
    }
    in_table = true;
    if (line.starts_with("|---") || line.starts_with("| part |")) continue;
    auto cells = split(line.substr(2, line.size() - 4), " | ");
    if (cells.size() != 7) {
      ADD_FAILURE() << "unexpected table row: " << line;
      continue;
    }
    Row row;
    row.name = trim(cells[0]);
    row.library = trim(cells[2]);
    row.mass = std::stod(cells[4]);
    row.primitives_cell = cells[6];
    if (row.name != "ParamHanger") {  // formulas, checked separately
      for (const std::string& text : split(cells[6], "<br>")) {
        auto p = parse_primitive(text);
        if (!p) {
          ADD_FAILURE() << row.name << ": cannot parse primitive '" << text << "'";
          continue;
        }
        row.primitives.push_back(*p);
      }
    }
    rows.push_back(row);
  }
  return rows;
}

const std::vector<Row>& table() {
  static const std::vector<Row> rows = read_table();
  return rows;
}

// The table is test data: without it the tests fail (they must never pass by skipping).
#define REQUIRE_TABLE()                                                                      \
  if (table().empty()) {                                                                     \
    FAIL() << "the reference table is missing: " FABKIT_SHARED_DIR                           \
              "/reference/fabhacks-reference.md (§10.2) must be beside the project to test"; \
  }                                                                                          \
  static_assert(true)

std::optional<PrimitiveType> table_type(const std::string& t) {
  static const std::map<std::string, PrimitiveType> types{
      {"Rod", PrimitiveType::kRod},
      {"Hook", PrimitiveType::kHook},
      {"Ring", PrimitiveType::kRing},
      {"Clip", PrimitiveType::kClip},
      {"Tube", PrimitiveType::kTube},
      {"Edge", PrimitiveType::kEdge},
      {"Surface", PrimitiveType::kSurface},
      {"Hemisphere", PrimitiveType::kHemisphere}};
  const auto it = types.find(t);
  if (it == types.end()) return std::nullopt;
  return it->second;
}

// -1 -> "-1", 100.5 -> "100.5", as {:g} prints them.
std::string fmt_value(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

Mat3 rotation(const Vec3& euler) {
  return rot_euler(euler.x(), euler.y(), euler.z()).topLeftCorner<3, 3>();
}

std::shared_ptr<Part> make(const std::string& name, const ParamValues& params = {}) {
  Diagnostics diags;
  auto part = PartsLibrary::builtin().make(name, params, diags);
  EXPECT_FALSE(diags.has_errors()) << name << ": " << diags.format();
  return part;
}

// Compares a built primitive with the table's description.
void expect_primitive(const std::string& part, const Primitive& got, const RowPrimitive& want) {
  SCOPED_TRACE(part + "." + want.name);
  EXPECT_EQ(got.name, want.name);
  const auto type = table_type(want.type);
  ASSERT_TRUE(type.has_value()) << "unknown table type " << want.type;
  ASSERT_EQ(got.type, *type);
  for (const auto& [field, value] : want.shape) {
    const auto names = shape_field_names(*type);
    ASSERT_NE(std::find(names.begin(), names.end(), field), names.end())
        << field << " is not a " << want.type << " shape field";
    EXPECT_NEAR(shape_field_value(got.shape, field), value, kTol) << field;
  }
  EXPECT_EQ(want.shape.size(), shape_field_names(*type).size()) << "table lists every field";
  EXPECT_LT((got.frame.pos - want.pos).cwiseAbs().maxCoeff(), kTol)
      << got.frame.pos.transpose() << " vs " << want.pos.transpose();
  EXPECT_LT((rotation(got.frame.rot) - rotation(want.rot)).cwiseAbs().maxCoeff(), kTol)
      << got.frame.rot.transpose() << " vs " << want.rot.transpose();

  bool flex = false;
  bool centerline = false;
  bool is_open = *type != PrimitiveType::kSurface;
  bool open_for_connect = *type != PrimitiveType::kRing;
  bool closed = false;
  bool explicit_open_for_connect = false;
  for (const std::string& f : want.flags) {
    if (f == "HookFlex" || f == "RingFlex") {
      flex = true;
    } else if (f == "RodCtl" || f == "RingCtl" || f == "TubeCtl") {
      centerline = true;
    } else if (f == "is_open=False") {
      closed = true;
    } else if (f == "open_for_connect=True") {
      explicit_open_for_connect = true;
    } else {
      ADD_FAILURE() << "unknown table flag '" << f << "'";
    }
  }
  if (closed) {
    is_open = false;
    open_for_connect = explicit_open_for_connect;
  }
  EXPECT_EQ(got.flex, flex);
  EXPECT_EQ(got.centerline, centerline);
  EXPECT_EQ(got.is_open, is_open);
  EXPECT_EQ(got.open_for_connect, open_for_connect);
  EXPECT_EQ(got.theta_range.has_value(), want.theta_range.has_value());
  if (got.theta_range && want.theta_range) {
    EXPECT_DOUBLE_EQ((*got.theta_range)[0], (*want.theta_range)[0]);
    EXPECT_DOUBLE_EQ((*got.theta_range)[1], (*want.theta_range)[1]);
  }
  EXPECT_FALSE(got.phi_range.has_value());
}

PartCategory category_of(const std::string& library) {
  if (library == "env/target") return PartCategory::kEnvironment;
  if (library == "part") return PartCategory::kHack;
  if (library == "env+part") return PartCategory::kBoth;
  EXPECT_EQ(library, "—");
  return PartCategory::kOther;
}

TEST(BuiltinParts, TableIsComplete) {
  REQUIRE_TABLE();
  EXPECT_EQ(table().size(), 56u);
  // Every library part has a row and every row a part.
  for (const PartGenerator& g : PartsLibrary::builtin().generators()) {
    EXPECT_TRUE(
        std::any_of(table().begin(), table().end(), [&](const Row& r) { return r.name == g.name; }))
        << g.name << " is not in the table";
  }
  EXPECT_EQ(PartsLibrary::builtin().generators().size(), table().size());
}

TEST(BuiltinParts, EveryRowMatchesTheTable) {
  REQUIRE_TABLE();
  for (const Row& row : table()) {
    SCOPED_TRACE(row.name);
    const PartGenerator* g = PartsLibrary::builtin().find(row.name);
    ASSERT_NE(g, nullptr) << row.name << " missing";
    EXPECT_EQ(g->name, row.name);
    EXPECT_EQ(g->category, category_of(row.library));
    auto part = make(row.name);
    ASSERT_NE(part, nullptr);
    EXPECT_EQ(part->type_name, row.name);
    EXPECT_EQ(part->category, g->category);
    EXPECT_NEAR(part->mass, row.mass, 1e-6 * row.mass);
    if (row.name == "ParamHanger") continue;  // see ParamHangerFormulas
    ASSERT_EQ(part->primitives.size(), row.primitives.size());
    for (std::size_t i = 0; i < row.primitives.size(); ++i) {
      // By name: the order may differ where it decides end_with's default (Toothbrush).
      const int at = part->find_primitive(row.primitives[i].name).value;
      ASSERT_GE(at, 0) << row.name << " has no " << row.primitives[i].name;
      expect_primitive(row.name, part->primitives[static_cast<std::size_t>(at)], row.primitives[i]);
    }
  }
}

TEST(BuiltinParts, MeshesAndMassProperties) {
  REQUIRE_TABLE();
  for (const PartGenerator& g : PartsLibrary::builtin().generators()) {
    SCOPED_TRACE(g.name);
    auto part = make(g.name);
    ASSERT_NE(part, nullptr);
    EXPECT_FALSE(part->description.empty());
    ASSERT_FALSE(part->mesh.empty());
    EXPECT_LT(part->mesh.faces.size(), 20000u);
    EXPECT_GT(part->mesh.volume(), 0.0);
    EXPECT_GT(part->mass, 0.0);
    EXPECT_TRUE(part->center_of_mass.allFinite());
    const Vec3 lo = part->mesh.bounds_min();
    const Vec3 hi = part->mesh.bounds_max();
    const double tol = 0.1 * (hi - lo).norm() + 5.0;
    EXPECT_TRUE((part->center_of_mass.array() >= lo.array() - tol).all() &&
                (part->center_of_mass.array() <= hi.array() + tol).all())
        << "COM " << part->center_of_mass.transpose();
    for (const Primitive& p : part->primitives) {
      const Vec3& o = p.frame.pos;
      EXPECT_TRUE((o.array() >= lo.array() - tol).all() && (o.array() <= hi.array() + tol).all())
          << p.name << " at " << o.transpose() << " outside [" << lo.transpose() << "] - ["
          << hi.transpose() << "]";
      Diagnostics d;
      p.validate(g.name + "." + p.name, d);
      EXPECT_TRUE(d.empty()) << d.format();
      EXPECT_FALSE(primitive_mesh(p).empty()) << p.name;
    }
    // Primitive names are unique within the part.
    for (std::size_t i = 0; i < part->primitives.size(); ++i) {
      EXPECT_EQ(part->find_primitive(part->primitives[i].name).value, static_cast<int>(i));
    }
  }
}

TEST(BuiltinParts, BodiesSitWhereTheObjectIs) {
  // A few plausibility checks on the centre of mass relative to the connectors.
  auto feeder = make("BirdFeeder");
  ASSERT_NE(feeder, nullptr);
  EXPECT_LT(feeder->center_of_mass.z(), feeder->primitives[0].frame.pos.z() - 40);  // below ring
  auto mug = make("Mug");
  ASSERT_NE(mug, nullptr);
  EXPECT_LT(mug->center_of_mass.x(), 30);  // the body, not the handle, dominates
  auto basket = make("Basket");
  ASSERT_NE(basket, nullptr);
  EXPECT_LT(basket->center_of_mass.z(), 200);  // below the handle rods at z 252
  EXPECT_NEAR(basket->center_of_mass.x(), 0, 1);
}

TEST(BuiltinParts, Aliases) {
  const PartsLibrary& lib = PartsLibrary::builtin();
  ASSERT_NE(lib.find("HookEyeLeft5"), nullptr);
  EXPECT_EQ(lib.find("HookEyeLeft5")->name, "HookEyeLeftS");
  ASSERT_NE(lib.find("TowelRackRods"), nullptr);
  EXPECT_EQ(lib.find("TowelRackRods")->name, "ClosetRods");
  ASSERT_NE(lib.find("doublehook"), nullptr);
  EXPECT_EQ(lib.find("doublehook")->name, "DoubleHook");
  auto eye = make("HookEyeLeft5");
  ASSERT_NE(eye, nullptr);
  EXPECT_EQ(eye->type_name, "HookEyeLeftS");
}

TEST(BuiltinParts, HoleAndRingNameTheSamePrimitive) {
  auto clip = make("BinderClip");
  ASSERT_NE(clip, nullptr);
  EXPECT_EQ(clip->find_primitive("ring1").value, 1);
  EXPECT_EQ(clip->find_primitive("hole1").value, 1);
  EXPECT_EQ(clip->find_primitive("hole2").value, 2);
  EXPECT_EQ(clip->find_primitive("clip").value, 0);
  EXPECT_EQ(clip->find_primitive("hole3").value, -1);
  EXPECT_EQ(clip->find_primitive("rod").value, -1);
  EXPECT_EQ(clip->primitive_list(), "clip, ring1, ring2");
  auto eye = make("HookEyeLeftS");
  ASSERT_NE(eye, nullptr);
  EXPECT_EQ(eye->find_primitive("hole"), eye->find_primitive("ring"));
  EXPECT_TRUE(eye->find_primitive("hole").valid());

  // And the other way round on a part whose primitive is called "hole".
  Part env = make_primitive_part({Primitive::make("hole2", PrimitiveType::kRing, [] {
    PrimitiveShape s;
    s.arc_radius = 10;
    s.thickness = 1;
    return s;
  }())});
  EXPECT_EQ(env.find_primitive("ring2").value, 0);
  EXPECT_EQ(env.type_name, "Environment");
  EXPECT_EQ(env.mass, 0);
  EXPECT_FALSE(env.mesh.empty());
}

TEST(BuiltinParts, CategoryNames) {
  EXPECT_EQ(to_string(PartCategory::kEnvironment), "environment");
  EXPECT_EQ(to_string(PartCategory::kHack), "hack");
  EXPECT_EQ(to_string(PartCategory::kBoth), "both");
  EXPECT_EQ(to_string(PartCategory::kOther), "other");
  // Read back in any case; another word is no category.
  for (PartCategory c : {PartCategory::kEnvironment,
                         PartCategory::kHack,
                         PartCategory::kBoth,
                         PartCategory::kOther}) {
    EXPECT_EQ(category_named(to_string(c)), c);
  }
  EXPECT_EQ(category_named("Environment"), PartCategory::kEnvironment);
  EXPECT_EQ(category_named("HACK"), PartCategory::kHack);
  EXPECT_EQ(category_named("hacks"), std::nullopt);
  EXPECT_EQ(category_named(""), std::nullopt);
}

TEST(BuiltinParts, ParamTurnbuckle) {
  auto def = make("ParamTurnbuckle");
  ASSERT_NE(def, nullptr);
  ASSERT_EQ(def->params.count("extended_length"), 1u);
  EXPECT_EQ(def->params.at("extended_length"), 0.0);
  EXPECT_TRUE(def->primitives[0].frame.pos.isApprox(Vec3(2, 43.5, 0)));

  for (double l : {4.57, 25.135, 27.42, 40.0, 43.415, 100.0}) {
    SCOPED_TRACE(l);
    auto part = make("ParamTurnbuckle", {{"extended_length", l}});
    ASSERT_NE(part, nullptr);
    const double hook_y = 6 + 10 + 27.5 + l / 2;
    EXPECT_NEAR((part->primitives[0].frame.pos - Vec3(2, hook_y, 0)).norm(), 0, kTol);
    EXPECT_NEAR((part->primitives[1].frame.pos - Vec3(-2, -hook_y, 0)).norm(), 0, kTol);
    EXPECT_TRUE(part->primitives[1].flex);
    EXPECT_FALSE(part->primitives[0].flex);
    EXPECT_DOUBLE_EQ(part->mass, 1699.8);
    EXPECT_DOUBLE_EQ(part->params.at("extended_length"), l);
    // The details after the table write hook2's rotation as [-5, 90, 0].
    EXPECT_LT(
        (rotation(part->primitives[1].frame.rot) - rotation(Vec3(-5, 90, 0))).cwiseAbs().maxCoeff(),
        kTol);
  }
  auto fig11 = make("ParamTurnbuckle", {{"extended_length", 25.135}});
  ASSERT_NE(fig11, nullptr);
  EXPECT_NEAR((fig11->primitives[0].frame.pos - Vec3(2, 56.0675, 0)).norm(), 0, kTol);
  // Extending the screws lengthens the display mesh along y.
  EXPECT_GT(fig11->mesh.bounds_max().y(), def->mesh.bounds_max().y() + 12);
}

// A ParamHanger as it measures: width, hook and bends, from its mesh and primitives, against
// the parameters that name them (docs/parts.md).
void expect_hanger_measures(const Part& part, const ParamValues& v) {
  ASSERT_EQ(part.primitives.size(), 4u);
  const Primitive& h1 = part.primitives[0];
  const Primitive& rod = part.primitives[1];
  const Primitive& h2 = part.primitives[2];
  const Primitive& h3 = part.primitives[3];
  EXPECT_EQ(h1.name, "hook1");
  EXPECT_EQ(rod.name, "rod");
  EXPECT_EQ(h2.name, "hook2");
  EXPECT_EQ(h3.name, "hook3");
  // length: the width the mesh measures, tip to tip (y).
  EXPECT_NEAR(part.mesh.bounds_max().y() - part.mesh.bounds_min().y(), v.at("length"), 0.05);
  // hook_d: the top hook's inner diameter is the hook size asked; hook_h: its top's height.
  EXPECT_NEAR(2 * h1.shape.arc_radius, v.at("hook_d"), 1e-9);
  EXPECT_NEAR(part.mesh.bounds_max().z(), v.at("hook_h"), 0.05);
  // bar_d: the wire everywhere; bend_d: the bends' diameter.
  for (const Primitive* p : {&h1, &h2, &h3})
    EXPECT_NEAR(2 * p->shape.thickness, v.at("bar_d"), 1e-9);
  EXPECT_NEAR(2 * rod.shape.radius, v.at("bar_d"), 1e-9);
  EXPECT_NEAR(2 * h2.shape.arc_radius, v.at("bend_d"), 1e-9);
  EXPECT_NEAR(2 * h3.shape.arc_radius, v.at("bend_d"), 1e-9);
  // The bottom bar runs between the bends, symmetric about the middle, inside the width.
  EXPECT_NEAR(h2.frame.pos.y(), -h3.frame.pos.y(), 1e-9);
  EXPECT_LE(rod.shape.length, std::abs(h2.frame.pos.y() - h3.frame.pos.y()) + 1e-9);
  EXPECT_LT(std::abs(h2.frame.pos.y()) + h2.shape.arc_radius, v.at("length") / 2);
  EXPECT_FALSE(rod.is_open);
  EXPECT_TRUE(h1.is_open);
}

TEST(BuiltinParts, ParamHangerFormulas) {
  REQUIRE_TABLE();
  const auto row = std::find_if(
      table().begin(), table().end(), [](const Row& r) { return r.name == "ParamHanger"; });
  ASSERT_NE(row, table().end());
  // "defaults length 435, height 115, bar_d 6.35, ...": the schema defaults match the row.
  std::smatch m;
  const std::string cell = row->primitives_cell;
  ASSERT_TRUE(std::regex_search(cell, m, std::regex(R"(defaults (.*?)\. With)")));
  ParamValues defaults;
  for (const std::string& kv : split(m[1], ",")) {
    const std::string f = trim(kv);
    defaults[f.substr(0, f.find(' '))] = std::stod(f.substr(f.find(' ') + 1));
  }
  ASSERT_EQ(defaults.size(), 6u) << m[1];
  const PartGenerator* g = PartsLibrary::builtin().find("ParamHanger");
  ASSERT_NE(g, nullptr);
  ASSERT_EQ(g->params.size(), 6u);
  for (const ParamSchema& s : g->params) {
    ASSERT_EQ(defaults.count(s.name), 1u) << s.name;
    EXPECT_DOUBLE_EQ(s.default_value, defaults.at(s.name)) << s.name;
    EXPECT_LE(s.min, s.default_value);
    EXPECT_GE(s.max, s.default_value);
    EXPECT_EQ(s.unit, "mm");
  }

  auto def = make("ParamHanger");
  ASSERT_NE(def, nullptr);
  expect_hanger_measures(*def, defaults);
  EXPECT_EQ(def->params, defaults);
  EXPECT_NEAR(def->mass, 33345.3, 1e-6 * 33345.3);
  // The row's worked numbers.
  EXPECT_NEAR(def->primitives[0].shape.arc_radius, 20, kTol);
  EXPECT_NEAR(def->primitives[0].frame.pos.z(), 81.825, kTol);
  EXPECT_NEAR(def->primitives[1].shape.length, 378.3, kTol);
  EXPECT_NEAR(def->primitives[2].frame.pos.y(), 189.15, kTol);

  // Other values, including one where rod_l <= 20 skips the adjustment.
  const std::vector<ParamValues> variants{
      {{"length", 500}, {"bend_d", 30}, {"hook_d", 50}, {"hook_h", 120}, {"bar_d", 5}},
      {{"length", 300}, {"height", 60}},
      {{"length", 100}, {"bend_d", 70}, {"bar_d", 2}},
  };
  for (const ParamValues& given : variants) {
    ParamValues full = defaults;
    for (const auto& [k, v] : given) full[k] = v;
    SCOPED_TRACE(full.at("length"));
    auto part = make("ParamHanger", given);
    ASSERT_NE(part, nullptr);
    expect_hanger_measures(*part, full);
    EXPECT_EQ(part->params, full);
    EXPECT_NEAR(part->mass / def->mass, part->mesh.volume() / def->mesh.volume(), 1e-9);
  }
  auto longer = make("ParamHanger", {{"length", 600}});
  ASSERT_NE(longer, nullptr);
  EXPECT_GT(longer->mass, def->mass);
}

TEST(BuiltinParts, MakeRejectsBadInput) {
  const PartsLibrary& lib = PartsLibrary::builtin();
  {
    Diagnostics d;
    EXPECT_EQ(lib.make("DoubleHok", {}, d), nullptr);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.items()[0].code, codes::kUnknownPart);
    EXPECT_NE(d.items()[0].message.find("did you mean DoubleHook"), std::string::npos)
        << d.format();
  }
  {
    Diagnostics d;
    EXPECT_EQ(lib.make("Xylophone", {}, d), nullptr);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.items()[0].code, codes::kUnknownPart);
    EXPECT_EQ(d.items()[0].message.find("did you mean"), std::string::npos);
  }
  {
    Diagnostics d;
    EXPECT_EQ(lib.make("ParamTurnbuckle", {{"length", 3}}, d), nullptr);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.items()[0].code, codes::kUnknownName);
    EXPECT_NE(d.items()[0].message.find("extended_length"), std::string::npos);
  }
  {
    Diagnostics d;
    EXPECT_EQ(lib.make("DoubleHook", {{"size", 3}}, d), nullptr);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.items()[0].code, codes::kUnknownName);
  }
  {
    Diagnostics d;
    const SourceLocation where{"design.yaml", 7, 3};
    EXPECT_EQ(lib.make("ParamTurnbuckle",
                       {{"extended_length", std::numeric_limits<double>::quiet_NaN()}},
                       d,
                       where),
              nullptr);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.items()[0].code, codes::kInvalidValue);
    EXPECT_NE(d.items()[0].message.find("nan"), std::string::npos);
    EXPECT_EQ(d.items()[0].where.line, 7);
  }
  for (double bad : {-1.0, 100.5}) {
    Diagnostics d;
    EXPECT_EQ(lib.make("ParamTurnbuckle", {{"extended_length", bad}}, d), nullptr);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.items()[0].code, codes::kInvalidValue);
    const std::string& msg = d.items()[0].message;
    EXPECT_NE(msg.find(fmt_value(bad)), std::string::npos) << msg;
    EXPECT_NE(msg.find("[0, 100]"), std::string::npos) << msg;
    EXPECT_NE(msg.find("mm"), std::string::npos) << msg;
  }
  {
    // In range individually but impossible together: the bends are wider than the hanger.
    Diagnostics d;
    EXPECT_EQ(lib.make("ParamHanger", {{"length", 100}, {"bend_d", 100}}, d), nullptr);
    EXPECT_TRUE(d.has_errors());
    EXPECT_EQ(d.items()[0].code, codes::kInvalidValue);
  }
}

}  // namespace
}  // namespace fabkit::hacks

namespace fabkit::hacks {
namespace {

// The fixed built-in parts are a part file in the users' format: it must load without a single
// diagnostic and give every fixed part of the library, primitive for primitive (the library
// reads each entry on its own when first made: the same parts as this whole read).
TEST(BuiltinParts, DataFileIsAPlainPartFile) {
  PartsLibrary lib;
  Diagnostics diags;
  ASSERT_TRUE(lib.load_yaml(std::string(FABKIT_SOURCE_DIR) + "/hacks/data/parts.yaml", diags))
      << diags.format();
  EXPECT_TRUE(diags.empty()) << diags.format();
  int fixed = 0;
  for (const PartGenerator& g : PartsLibrary::builtin().generators()) {
    if (!g.params.empty()) continue;
    ++fixed;
    const PartGenerator* from_file = lib.find(g.name);
    ASSERT_NE(from_file, nullptr) << g.name;
    EXPECT_EQ(from_file->aliases, g.aliases) << g.name;
    EXPECT_EQ(from_file->description, g.description) << g.name;
    EXPECT_EQ(from_file->category, g.category) << g.name;
    const Part a = g.build({});
    const Part b = from_file->build({});
    EXPECT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size()) << g.name;
    EXPECT_EQ(a.collision_pieces.size(), b.collision_pieces.size()) << g.name;
    ASSERT_EQ(a.primitives.size(), b.primitives.size()) << g.name;
    for (std::size_t i = 0; i < a.primitives.size(); ++i) {
      EXPECT_EQ(a.primitives[i].describe(), b.primitives[i].describe()) << g.name;
    }
    EXPECT_DOUBLE_EQ(a.mass, b.mass) << g.name;
    EXPECT_LT((a.center_of_mass - b.center_of_mass).norm(), 1e-9) << g.name;
  }
  EXPECT_EQ(fixed, 54);
}

}  // namespace
}  // namespace fabkit::hacks
