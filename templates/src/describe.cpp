#include <fmt/format.h>

#include <functional>
#include <map>

#include "fabkit/templates/database.h"
#include "fabkit/templates/manipulate.h"

namespace fabkit::templates {

std::string describe_template(const Template& t, const ItemCatalog& catalog) {
  std::string out;
  int principal = 0;
  for (const Element& e : t.elements) principal += e.is_principal();
  out +=
      fmt::format("{} — {}{}: {} parts, {} elements ({} principal), {} connections, {} relations\n",
                  t.name,
                  t.title,
                  t.category.empty() ? "" : " (" + t.category + ")",
                  t.part_count(),
                  t.element_count(),
                  principal,
                  t.connections.size(),
                  t.relations.size());
  const Manipulator m(t, {}, &catalog);
  std::function<void(NodeId, int)> walk = [&](NodeId n, int depth) {
    const Node& node = t.node(n);
    const std::string indent(2 * depth, ' ');
    if (node.element) {
      const Element& e = t.element(*node.element);
      const Box b = t.box(*node.element);
      std::string controls;
      if (e.is_principal()) {
        for (const Control& c : m.controls(n)) {
          if (!c.hidden) controls += " " + std::string(to_string(c.kind));
        }
      }
      out +=
          fmt::format("{}{}{} [{}] {:g} x {:g} x {:g} mm at ({:g}, {:g}, {:g}){}{}\n",
                      indent,
                      e.name,
                      e.pattern ? fmt::format(" ({} parts in a pattern)", e.pattern->total()) : "",
                      e.item,
                      b.size.x(),
                      b.size.y(),
                      b.size.z(),
                      b.center.x(),
                      b.center.y(),
                      b.center.z(),
                      e.is_principal() ? "" : " connecting",
                      controls.empty() ? "" : "; controls:" + controls);
      return;
    }
    if (node.connection_node) {
      out += fmt::format("{}{} (connection)\n", indent, node.name);
    } else {
      out += fmt::format("{}{}/\n", indent, node.name);
    }
    for (NodeId c : node.children) walk(c, depth + 1);
  };
  walk(t.root(), 1);
  if (!t.connections.empty()) out += "connections:\n";
  for (const Connection& c : t.connections) {
    std::vector<std::string> p, k;
    for (ElementId e : c.principal) p.push_back(t.element(e).name);
    for (ElementId e : c.connecting) {
      const Element& el = t.element(e);
      k.push_back(el.pattern ? fmt::format("{} x {}", el.pattern->total(), el.item) : el.item);
    }
    out += fmt::format("  {} + held by {}\n", fmt::join(p, " + "), fmt::join(k, ", "));
  }
  std::map<std::string, int> kinds;
  for (const Relation& r : t.relations) ++kinds[std::string(to_string(r.kind))];
  std::vector<std::string> counts;
  for (const auto& [k, n] : kinds) counts.push_back(fmt::format("{} {}", n, k));
  out += fmt::format("relations: {}\n", fmt::join(counts, ", "));
  if (!t.articulations.empty()) {
    for (const TemplateArticulation& a : t.articulations) {
      std::vector<std::string> moving;
      for (ElementId e : a.moving) moving.push_back(t.element(e).name);
      out += fmt::format("articulation {} ({}): {} rest poses at {:g} and {:g}; moves {}\n",
                         a.name,
                         to_string(a.type),
                         a.type == JointType::kBall ? "no fixed" : "two",
                         a.lower,
                         a.upper,
                         fmt::join(moving, ", "));
    }
  }
  return out;
}

}  // namespace fabkit::templates
