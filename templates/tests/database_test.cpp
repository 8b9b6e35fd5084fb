// The bundled template database: every design reads, extracts and holds its own relations;
// connections are found from proximity; sub-templates are self-contained.
#include "fabkit/templates/database.h"

#include <gtest/gtest.h>

#include <set>

#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/manipulate.h"
#include "test_support.h"

namespace fabkit::templates {
namespace {

using testing::has_diagnostic;

TEST(Database, EveryBundledDesignIsATemplateDetailedDownToTheScrews) {
  const TemplateDatabase& db = TemplateDatabase::bundled();
  EXPECT_GE(db.names().size(), 12u);
  for (const std::string& name : db.names()) {
    SCOPED_TRACE(name);
    const SourceDesign* d = db.design(name);
    const Template* t = db.source_template(name);
    ASSERT_TRUE(d && t);
    EXPECT_LT(t->max_violation(), 1e-9);
    int connecting = 0, fasteners = 0;
    for (const DesignPart& p : d->parts) {
      connecting += p.role == PartRole::kConnecting;
      const Item* it = db.catalog().find(p.item);
      ASSERT_TRUE(it) << p.item;
      fasteners += it->category == ItemCategory::kFastener;
    }
    EXPECT_GT(fasteners, 0) << "no screws";
    EXPECT_GT(connecting, 0);
    // Every connecting element belongs to a connection that joins principal elements.
    std::set<int> in_connection;
    for (const Connection& c : t->connections) {
      EXPECT_FALSE(c.principal.empty()) << c.name;
      for (ElementId e : c.connecting) in_connection.insert(e.value);
    }
    for (int e = 0; e < t->element_count(); ++e) {
      if (!t->element(ElementId(e)).is_principal()) {
        EXPECT_TRUE(in_connection.count(e)) << t->element(ElementId(e)).name;
      }
    }
    EXPECT_EQ(t->part_count(), static_cast<int>(d->parts.size()));
    // Every node is a template: its subtree holds its own relations.
    for (std::size_t n = 0; n < t->nodes.size(); ++n) {
      const Template sub = t->subtree(NodeId(static_cast<int>(n)));
      EXPECT_LT(sub.max_violation(), 1e-9) << sub.name;
    }
  }
}

TEST(Database, FindsSubTemplatesByPathAndSuggestsNames) {
  const TemplateDatabase& db = TemplateDatabase::bundled();
  Diagnostics d;
  const auto legs = db.find("dining_table/base/legs", d);
  ASSERT_TRUE(legs) << d.format();
  EXPECT_EQ(legs->element_count(), 4);
  EXPECT_FALSE(db.find("dinning_table", d));
  EXPECT_TRUE(has_diagnostic(d, codes::kUnknownTemplate, "did you mean 'dining_table'?"));
  Diagnostics d2;
  EXPECT_FALSE(db.find("dining_table/base/leggs", d2));
  EXPECT_TRUE(has_diagnostic(d2, codes::kUnknownTemplate, "did you mean 'base/legs'?"));
}

}  // namespace
}  // namespace fabkit::templates
