// The templates kit's commands: check and build of a working model, and browsing the
// bundled database (fabkit templates list | show NAME).
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "fabkit/templates/database.h"
#include "kits.h"

namespace fabkit::cli {

int run_templates(const TemplatesSettings& settings) {
  const templates::TemplateDatabase& db = templates::TemplateDatabase::bundled();
  if (settings.action == "list") {
    std::printf("%zu source designs (every node of each is a template: use design/path):\n",
                db.names().size());
    for (const std::string& name : db.names()) {
      const templates::Template* t = db.source_template(name);
      int nodes = 0;
      for (const templates::Node& n : t->nodes) nodes += !n.connection_node && !n.element;
      std::printf("  %-18s %-24s %-9s %4d parts, %2zu connections, %d sub-assemblies\n",
                  name.c_str(),
                  t->title.c_str(),
                  t->category.c_str(),
                  t->part_count(),
                  t->connections.size(),
                  nodes);
    }
    std::printf("%zu catalog items; fabkit templates show NAME for one template\n",
                db.catalog().size());
    return kExitOk;
  }
  Diagnostics d;
  const auto t = db.find(settings.name, d);
  if (!t) {
    print_diagnostics(d);
    return kExitBadInput;
  }
  std::fputs(templates::describe_template(*t, db.catalog()).c_str(), stdout);
  if (const templates::SourceDesign* sd = db.design(settings.name);
      sd && !sd->description.empty()) {
    std::printf("about: %s", sd->description.c_str());
  }
  return kExitOk;
}

}  // namespace fabkit::cli
