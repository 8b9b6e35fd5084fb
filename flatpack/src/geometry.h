#pragma once
// The geometric stages of check(): placement (Alg. 1), coplanar merging and intersection
// detection (Alg. 2), joint cutting (Appendix A) and the press-fit order.
#include <vector>

#include "fabkit/flatpack/check.h"
#include "flat_design.h"

namespace fabkit::flatpack::detail {

/// A connection's relative transform T_rel (component A's frame in component B's frame).
Mat4 relative_transform(const ComponentShape& a,
                        const std::string& a_edge,
                        const ComponentShape& b,
                        const std::string& b_edge,
                        Alignment alignment,
                        const Vec3& offset,
                        const Vec3& rotation_deg);

/// The edge frame of a named edge: origin at its midpoint, x along it, z the front normal,
/// y = z × x into the component. Identity if the edge is unknown.
Mat4 edge_frame(const ComponentShape& shape, const std::string& edge, bool* found = nullptr);

struct ResolvedConnection {
  int a = -1, b = -1;
  Mat4 relative = Mat4::Identity();  ///< A in B's frame
  std::string name, text;
  SourceLocation where;
  bool places_only = false;  ///< `joint: none`
};

/// Algorithm 1 over the connectivity graph; cycle residuals go to `residuals` (if given) and
/// those beyond the tolerances become diagnostics.
void place(std::vector<PlacedComponent>& components,
           const std::vector<ResolvedConnection>& connections,
           const CheckOptions& options,
           Diagnostics& diags,
           std::vector<CycleResidual>* residuals = nullptr);

/// Algorithm 2 and Appendix A: merges, detects, cuts; fills analysis.pieces and joints.
void detect_and_cut(Analysis& analysis,
                    const std::vector<ResolvedConnection>& connections,
                    const JointOptions& joints,
                    const LabelOptions& labels,
                    const CheckOptions& options);

/// The press-fit order (disassembly in reverse), filling analysis.assembly / not_insertable.
void plan_assembly(Analysis& analysis);

}  // namespace fabkit::flatpack::detail
