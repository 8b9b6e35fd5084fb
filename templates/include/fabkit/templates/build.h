#pragma once
/// Building a working model's outputs: the bill of materials (bom.csv, bom.json), a printable
/// report with pictures (report.html), cut diagrams (cuts_<item>.svg for lumber and pipe,
/// sheet_<item>_<n>.svg for sheet goods), the 3D model (scene.glb with materials, unstable
/// parts red; stability.glb green/red; model.stl) and the model's parameters (model.json).

#include <filesystem>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/check.h"

namespace fabkit::templates {

struct BuildOptions {
  CheckOptions check;
  bool write_meshes = true;  ///< scene.glb, stability.glb, model.stl
};

struct StageTiming {
  std::string stage;  ///< "compose", "check", "bill of materials", "export"
  double milliseconds = 0;
};

enum class BuildTermination {
  kBuilt,              ///< every output written, no findings
  kBuiltWithFindings,  ///< written, but a check failed (unstable, overlaps, ...)
  kNotBuilt,           ///< input errors or no bill of materials: nothing written
  kWriteFailed,        ///< an output could not be written
};
std::string_view to_string(BuildTermination t);

struct BuildSummary {
  BuildTermination termination = BuildTermination::kNotBuilt;
  std::string message;  ///< "built 'table with a bottom shelf': 93 parts, $172.41, stable"
  std::vector<std::filesystem::path> written;
  std::vector<StageTiming> timings;
  CheckResult check;
  Diagnostics diagnostics;
};

/// Checks `model` and writes its outputs into `directory` (created if needed; every file is
/// written atomically).
BuildSummary build(const ComposedModel& model,
                   const TemplateDatabase& db,
                   const std::filesystem::path& directory,
                   const BuildOptions& options = {});

/// The report as HTML text (embedded pictures: a preview of the model and the cut diagrams).
std::string report_html(const ComposedModel& model,
                        const CheckResult& check,
                        const std::vector<std::pair<std::string, std::string>>& drawings);

/// The model's parameters as JSON: compositions, elements with boxes, parts with items.
std::string model_json(const ComposedModel& model, const CheckResult& check);

}  // namespace fabkit::templates
