#pragma once
// The bundled data compiled into fabkit (generated from templates/data by CMake), so the kit
// works from any directory without the source tree.

#include <span>
#include <string_view>

namespace fabkit::templates::embedded {

struct EmbeddedFile {
  std::string_view path;  ///< relative to templates/data ("designs/dining_table.yaml")
  std::string_view text;
};

/// templates/data/catalog/items.csv
std::string_view catalog_csv();
/// Every templates/data/designs/*.yaml, sorted by path.
std::span<const EmbeddedFile> design_files();

}  // namespace fabkit::templates::embedded
