#include "fabkit/templates/database.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "embedded_data.h"
#include "fabkit/core/file_io.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/templates/design_file.h"
#include "fabkit/templates/diagnostic_codes.h"

namespace fabkit::templates {

std::string material_class(std::string_view material) {
  auto has = [&](std::string_view w) { return material.find(w) != std::string_view::npos; };
  if (has("steel") && has("rubber")) return "metal";
  for (std::string_view w : {"steel", "iron", "alumin", "zinc", "brass", "metal"}) {
    if (has(w)) return "metal";
  }
  for (std::string_view w : {"rubber"}) {
    if (has(w)) return "rubber";
  }
  for (std::string_view w : {"plastic", "acrylic", "nylon", "felt"}) {
    if (has(w)) return "plastic";
  }
  if (has("glass")) return "glass";
  return "wood";
}

ConnectionExample describe_pair(const Template& t,
                                const ItemCatalog& catalog,
                                ElementId a,
                                ElementId b) {
  ConnectionExample ex;
  ex.design = t.name;
  ex.principal = {a, b};
  const std::array<ElementId, 2> es{a, b};
  for (int i = 0; i < 2; ++i) {
    const Element& el = t.element(es[i]);
    const Item* it = catalog.find(el.item);
    ex.material[i] = material_class(it ? it->material : "wood");
    ex.size[i] = t.box(es[i]).size;
    for (int k = 0; k < 3; ++k) ex.constrained[i][k] = !el.resizable[k];
  }
  const Box ba = t.box(a), bb = t.box(b);
  for (int k = 0; k < 3; ++k) {
    ex.planes[k] = {ba.min()[k] - bb.min()[k],
                    ba.min()[k] - bb.max()[k],
                    ba.max()[k] - bb.min()[k],
                    ba.max()[k] - bb.max()[k]};
  }
  return ex;
}

double descriptor_distance(const ConnectionExample& q, const ConnectionExample& e, bool* swapped) {
  auto one = [&](bool swap) {
    const int i0 = swap ? 1 : 0, i1 = swap ? 0 : 1;
    if (q.material[0] != e.material[i0] || q.material[1] != e.material[i1]) {
      return std::numeric_limits<double>::infinity();
    }
    double d = 0;
    for (int k = 0; k < 3; ++k) {
      // Constrained sizes cannot be fitted by manipulating the template: they weigh more.
      const double w0 = e.constrained[i0][k] ? 3.0 : 1.0;
      const double w1 = e.constrained[i1][k] ? 3.0 : 1.0;
      d +=
          w0 * std::abs(q.size[0][k] - e.size[i0][k]) + w1 * std::abs(q.size[1][k] - e.size[i1][k]);
      // Plane distances of the example as seen with the query's order.
      std::array<double, 4> p = e.planes[k];
      if (swap) p = {-p[0], -p[2], -p[1], -p[3]};
      for (int j = 0; j < 4; ++j) {
        // Signs carry order (which side) and zeros carry coplanarity: a flip costs a lot.
        const double sign_flip =
            (p[j] > 0.5 && q.planes[k][j] < -0.5) || (p[j] < -0.5 && q.planes[k][j] > 0.5) ? 1000.0
                                                                                           : 0.0;
        d += 0.5 * std::min(std::abs(p[j] - q.planes[k][j]), 200.0) + sign_flip;
      }
    }
    return d;
  };
  const double straight = one(false), crossed = one(true);
  if (swapped) *swapped = crossed < straight;
  return std::min(straight, crossed);
}

void TemplateDatabase::index() {
  examples_.clear();
  for (const auto& [name, t] : templates_) {
    for (std::size_t c = 0; c < t.connections.size(); ++c) {
      const Connection& conn = t.connections[c];
      if (conn.principal.size() < 2 || conn.connecting.empty()) continue;
      ConnectionExample ex = describe_pair(t, catalog_, conn.principal[0], conn.principal[1]);
      ex.connection = ConnectionId(static_cast<int>(c));
      examples_.push_back(std::move(ex));
    }
  }
}

std::optional<TemplateDatabase> TemplateDatabase::load(
    const ItemCatalog& catalog,
    const std::vector<std::pair<std::string, std::string>>& designs,
    Diagnostics& diags) {
  TemplateDatabase db;
  db.catalog_ = catalog;
  for (const auto& [file, text] : designs) {
    Diagnostics d;
    auto design = read_source_design(text, file, d);
    std::optional<Template> t;
    if (design) {
      if (db.designs_.count(design->name)) {
        d.error(codes::kDuplicateName,
                fmt::format("design '{}' is defined twice", design->name),
                SourceLocation{file, 1, 1});
      } else {
        t = make_template(*design, &db.catalog_, d);
      }
    }
    diags.append(d);
    if (!design || !t) continue;
    db.templates_.emplace(design->name, std::move(*t));
    db.designs_.emplace(design->name, std::move(*design));
  }
  if (db.designs_.empty()) return std::nullopt;
  db.index();
  return db;
}

const TemplateDatabase& TemplateDatabase::bundled() {
  static const TemplateDatabase db = [] {
    std::vector<std::pair<std::string, std::string>> files;
    for (const embedded::EmbeddedFile& f : embedded::design_files()) {
      files.emplace_back("templates/data/" + std::string(f.path), std::string(f.text));
    }
    Diagnostics d;
    auto loaded = load(ItemCatalog::bundled(), files, d);
    // The bundled designs are tested; a failure here is a build defect.
    if (!loaded || d.has_errors()) {
      std::fprintf(stderr, "fabkit: internal error: bundled templates:\n%s\n", d.format().c_str());
      std::abort();
    }
    return std::move(*loaded);
  }();
  return db;
}

std::optional<TemplateDatabase> TemplateDatabase::with_directory(
    const std::filesystem::path& directory, const ItemCatalog& catalog, Diagnostics& diags) {
  std::vector<std::pair<std::string, std::string>> files;
  for (const embedded::EmbeddedFile& f : embedded::design_files()) {
    files.emplace_back("templates/data/" + std::string(f.path), std::string(f.text));
  }
  std::error_code ec;
  std::vector<std::filesystem::path> paths;
  for (const auto& entry : std::filesystem::directory_iterator(directory, ec)) {
    if (entry.path().extension() == ".yaml") paths.push_back(entry.path());
  }
  if (ec) {
    diags.error(codes::kUnreadableFile,
                fmt::format("cannot read directory {}: {}", directory.string(), ec.message()));
    return std::nullopt;
  }
  std::sort(paths.begin(), paths.end());
  for (const auto& p : paths) {
    if (auto text = read_input_file(p, "design file", diags)) files.emplace_back(p.string(), *text);
  }
  return load(catalog, files, diags);
}

std::vector<std::string> TemplateDatabase::names() const {
  std::vector<std::string> out;
  for (const auto& [n, d] : designs_) out.push_back(n);
  return out;
}

const SourceDesign* TemplateDatabase::design(std::string_view name) const {
  auto it = designs_.find(name);
  return it == designs_.end() ? nullptr : &it->second;
}

const Template* TemplateDatabase::source_template(std::string_view name) const {
  auto it = templates_.find(name);
  return it == templates_.end() ? nullptr : &it->second;
}

std::optional<Template> TemplateDatabase::find(std::string_view spec, Diagnostics& diags) const {
  const std::size_t slash = spec.find('/');
  const std::string_view design = spec.substr(0, slash);
  const Template* t = source_template(design);
  if (!t) {
    diags.error(codes::kUnknownTemplate,
                fmt::format("unknown template '{}'{}; the database has: {}",
                            spec,
                            did_you_mean(design, names()),
                            fmt::join(names(), ", ")));
    return std::nullopt;
  }
  if (slash == std::string_view::npos) return *t;
  const std::string_view path = spec.substr(slash + 1);
  NodeId n = t->find(path);
  if (!n.valid()) n = t->find_node_or_element(path);
  if (!n.valid() || t->node(n).connection_node) {
    std::vector<std::string> paths;
    for (std::size_t i = 1; i < t->nodes.size(); ++i) {
      bool under_connection = false;
      for (NodeId a = NodeId(static_cast<int>(i)); a.valid(); a = t->node(a).parent) {
        under_connection = under_connection || t->node(a).connection_node;
      }
      if (!under_connection) paths.push_back(t->path(NodeId(static_cast<int>(i))));
    }
    diags.error(codes::kUnknownTemplate,
                fmt::format("design '{}' has no node '{}'{}; its nodes: {}",
                            design,
                            path,
                            did_you_mean(path, paths),
                            fmt::join(paths, ", ")));
    return std::nullopt;
  }
  return t->subtree(n);
}

}  // namespace fabkit::templates
