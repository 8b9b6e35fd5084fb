#include "fabkit/templates/working_model.h"

#include <fmt/format.h>

#include "fabkit/core/yaml_reader.h"
#include "fabkit/templates/diagnostic_codes.h"

namespace fabkit::templates {

WorkingModel::WorkingModel(std::string name) {
  model_.name = name;
  model_.title = name;
  model_.nodes.push_back(Node{std::move(name), NodeId(), {}, std::nullopt, false, {}, {}});
  model_.q.resize(0);
}

std::optional<Composition> WorkingModel::add(const Template& part,
                                             std::string_view source,
                                             const std::string& name,
                                             std::optional<Vec3> at,
                                             Diagnostics& diags) {
  for (NodeId c : model_.node(model_.root()).children) {
    if (model_.node(c).name == name) {
      diags.error(codes::kDuplicateName,
                  fmt::format("the model already has a part named '{}'; give the new one "
                              "another name",
                              name));
      return std::nullopt;
    }
  }
  Template copy = part;
  if (at && copy.element_count() > 0) {
    const Vec3 shift = *at - copy.node_box(copy.root()).center;
    for (int e = 0; e < copy.element_count(); ++e) {
      copy.q.segment<3>(e * kParamsPerElement) += shift;
    }
  }
  Composition c;
  c.name = name;
  c.source = std::string(source);
  c.node = model_.append(copy, model_.root(), name);
  compositions_.push_back(c);
  return c;
}

bool WorkingModel::remove(std::string_view node, Diagnostics& diags) {
  const NodeId n = model_.find_node_or_element(node);
  if (!n.valid() || n == model_.root()) {
    std::vector<std::string> names;
    for (const Composition& c : compositions_) names.push_back(c.name);
    diags.error(codes::kUnknownName,
                fmt::format("the model has no part '{}'{}", node, did_you_mean(node, names)));
    return false;
  }
  const std::string removed_path = model_.path(n);
  Template next = model_.without(n);
  std::vector<Composition> kept;
  for (const Composition& c : compositions_) {
    const std::string path = model_.path(c.node);
    if (path == removed_path || path.rfind(removed_path + "/", 0) == 0) continue;
    Composition copy = c;
    copy.node = next.find(path);
    if (copy.node.valid()) kept.push_back(copy);
  }
  model_ = std::move(next);
  compositions_ = kept;
  return true;
}

const Composition* WorkingModel::composition(std::string_view name) const {
  for (const Composition& c : compositions_) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::vector<ElementId> WorkingModel::elements_of(const Composition& c) const {
  return model_.elements_under(c.node);
}

}  // namespace fabkit::templates
