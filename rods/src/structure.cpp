#include "fabkit/rods/structure.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <set>
#include <unordered_map>

#include "fabkit/core/yaml_reader.h"
#include "fabkit/rods/diagnostic_codes.h"

namespace fabkit::rods {
namespace {

constexpr double kPi = std::numbers::pi;

std::string id_text(int id, std::size_t count) {
  return count > 99 ? fmt::format("{:03d}", id) : fmt::format("{:02d}", id);
}

// Node positions in messages: short and exact enough to find the node.
std::string at(const Vec3& p) {
  return fmt::format("[{:g}, {:g}, {:g}]", p.x(), p.y(), p.z());
}

int find(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] =
        parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

}  // namespace

std::string Structure::joint_label(int node) const {
  return id_text(nodes[static_cast<std::size_t>(node)].id, nodes.size());
}

std::string Structure::joint_name(int node) const {
  return "joint " + joint_label(node);
}

std::string Structure::rod_name(int rod) const {
  const Rod& r = rods[static_cast<std::size_t>(rod)];
  return fmt::format("rod {}-{}", joint_label(r.a), joint_label(r.b));
}

std::vector<std::vector<int>> Structure::rods_at_nodes() const {
  std::vector<std::vector<int>> at(nodes.size());
  for (std::size_t e = 0; e < rods.size(); ++e) {
    at[static_cast<std::size_t>(rods[e].a)].push_back(static_cast<int>(e));
    at[static_cast<std::size_t>(rods[e].b)].push_back(static_cast<int>(e));
  }
  return at;
}

std::span<const RodMaterial> rod_material_presets() {
  // Typical values for small dowels and rods; strengths are conservative design values.
  static const std::array<RodMaterial, 6> kAll = {{
      {"hardwood", 680, 12000, 750, 80},  // birch / beech dowel
      {"oak", 700, 11000, 690, 70},
      {"pine", 500, 9000, 560, 40},
      {"bamboo", 700, 15000, 900, 100},
      {"aluminium", 2700, 69000, 26000, 150},  // 6060/6063 rod, yield ~ 150 MPa
      {"steel", 7850, 210000, 81000, 235},     // S235 round bar
  }};
  return kAll;
}

std::span<const JointMaterial> joint_material_presets() {
  static const std::array<JointMaterial, 5> kAll = {
      {{"pla", 1240}, {"petg", 1270}, {"abs", 1040}, {"asa", 1070}, {"nylon", 1140}}};
  return kAll;
}

std::optional<RodMaterial> find_rod_material(std::string_view name) {
  for (const RodMaterial& m : rod_material_presets()) {
    if (m.name == name) return m;
  }
  return std::nullopt;
}

std::optional<JointMaterial> find_joint_material(std::string_view name) {
  for (const JointMaterial& m : joint_material_presets()) {
    if (m.name == name) return m;
  }
  return std::nullopt;
}

double Parameters::socket_circumradius() const {
  const double r = radius + tolerance;
  return circular() ? r / std::cos(kPi / circle_sides) : r;
}

double Parameters::section_area() const {
  if (circular()) return kPi * radius * radius;
  return 0.5 * sides * radius * radius * std::sin(2 * kPi / sides);
}

double Parameters::section_inertia() const {
  if (circular()) return kPi * std::pow(radius, 4) / 4;
  // Regular polygon of circumradius R and side a: I = A (6R² − a²) / 24 about any axis.
  const double a = 2 * radius * std::sin(kPi / sides);
  return section_area() * (6 * radius * radius - a * a) / 24;
}

double Parameters::section_torsion() const {
  if (circular()) return kPi * std::pow(radius, 4) / 2;
  const double a = 2 * radius * std::sin(kPi / sides);
  if (sides == 3) return std::sqrt(3.0) * std::pow(a, 4) / 80;  // exact (Saint-Venant)
  if (sides == 4) return 0.1406 * std::pow(a, 4);               // exact (Saint-Venant)
  // Saint-Venant's approximation J ≈ A⁴ / (4π² I_p), exact for the circle.
  const double area = section_area();
  return std::pow(area, 4) / (4 * kPi * kPi * 2 * section_inertia());
}

Diagnostics Parameters::validate() const {
  Diagnostics d;
  auto bad = [&](std::string_view what, double v, std::string_view rule) {
    d.error(codes::kInvalidValue, fmt::format("{} is {:g}; {}", what, v, rule));
  };
  auto in = [&](std::string_view what, double v, double lo, double hi, bool lo_open = true) {
    if (!std::isfinite(v) || v < lo || (lo_open && v == lo) || v > hi) {
      bad(what,
          v,
          fmt::format(
              "it must be a finite number in {}{:g}, {:g}] mm", lo_open ? "(" : "[", lo, hi));
      return false;
    }
    return true;
  };
  const bool r_ok = in("rod radius r", radius, 0, 500);
  if (sides != 0 && (sides < 3 || sides > 64)) {
    bad("profile sides p", sides, "a polygonal profile has 3 to 64 sides (or use circle)");
  }
  if (circle_sides < 8 || circle_sides > 256) {
    bad("circle sides", circle_sides, "a circle is drawn with 8 to 256 sides");
  }
  const bool wall_ok = in("joint wall σ", wall, 0, 100);
  in("socket length h", socket, 0, 1000);
  in("leaf offset", leaf_offset, 0, 1000, false);
  in("minimum rod length", min_rod_length, 0, 1e6, false);
  in("merge tolerance", merge_tolerance, 0, 100, false);
  if (!std::isfinite(tolerance) || std::abs(tolerance) > 10) {
    bad("tolerance ε", tolerance, "it must be a finite number within ±10 mm");
  } else if (r_ok && radius + tolerance <= 0) {
    bad("tolerance ε", tolerance, fmt::format("r + ε must stay positive (r = {:g} mm)", radius));
  } else if (wall_ok && tolerance >= wall) {
    bad("tolerance ε",
        tolerance,
        fmt::format("it must be smaller than the wall σ = {:g} mm, or the socket breaks through "
                    "the joint",
                    wall));
  }
  auto positive = [&](std::string_view what, double v, double hi, std::string_view unit) {
    if (!std::isfinite(v) || v <= 0 || v > hi) {
      d.error(codes::kInvalidValue,
              fmt::format("{} is {:g}; it must be in (0, {:g}] {}", what, v, hi, unit));
    }
  };
  positive("rod material density", rod_material.density, 30000, "kg/m³");
  positive("rod material Young's modulus", rod_material.youngs_modulus, 1e6, "MPa");
  positive("rod material shear modulus", rod_material.shear_modulus, 1e6, "MPa");
  positive("rod material strength", rod_material.strength, 1e5, "MPa");
  positive("joint material density", joint_material.density, 30000, "kg/m³");
  if (!std::isfinite(stock.length) || stock.length <= 0 || stock.length > 1e5) {
    bad("stock length", stock.length, "it must be in (0, 100000] mm");
  } else if (!std::isfinite(stock.end_padding) || stock.end_padding < 0 ||
             2 * stock.end_padding >= stock.length) {
    bad("stock end padding", stock.end_padding, "it must be >= 0 and leave some usable length");
  }
  if (!std::isfinite(stock.kerf) || stock.kerf < 0 || stock.kerf > 20) {
    bad("stock kerf", stock.kerf, "it must be in [0, 20] mm");
  }
  return d;
}

std::optional<Structure> build_structure(std::span<const NodeInput> nodes,
                                         std::span<const EdgeInput> edges,
                                         int first_index,
                                         double merge_tolerance,
                                         Diagnostics& diags) {
  const std::size_t before = diags.size();
  auto errors_since = [&] {
    for (std::size_t i = before; i < diags.size(); ++i) {
      if (diags.items()[i].severity == Severity::kError) return true;
    }
    return false;
  };
  auto number = [&](std::size_t i) { return static_cast<long long>(i) + first_index; };
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Vec3& p = nodes[i].position;
    if (!p.allFinite()) {
      diags.error(codes::kInvalidValue,
                  fmt::format("node {} has a coordinate that is not a finite number", number(i)),
                  nodes[i].where);
    } else if (p.cwiseAbs().maxCoeff() > kMaxCoordinateMm) {
      diags.error(codes::kInvalidValue,
                  fmt::format("node {} at {} is more than {:g} mm from the origin (mm throughout)",
                              number(i),
                              at(p),
                              kMaxCoordinateMm),
                  nodes[i].where);
    }
  }
  if (nodes.empty()) diags.error(codes::kMalformedInput, "the structure has no nodes");
  if (edges.empty()) diags.error(codes::kMalformedInput, "the structure has no edges (rods)");
  if (errors_since()) return std::nullopt;

  // Merge coincident nodes: hash into cells of the tolerance, join neighbours within it.
  const auto n = static_cast<int>(nodes.size());
  std::vector<int> parent(nodes.size());
  std::iota(parent.begin(), parent.end(), 0);
  if (merge_tolerance > 0) {
    struct Key {
      long long x, y, z;
      bool operator==(const Key&) const = default;
    };
    struct Hash {
      std::size_t operator()(const Key& k) const {
        return std::hash<long long>()(k.x * 73856093 ^ k.y * 19349663 ^ k.z * 83492791);
      }
    };
    std::unordered_map<Key, std::vector<int>, Hash> cells;
    auto key = [&](const Vec3& p) {
      return Key{static_cast<long long>(std::floor(p.x() / merge_tolerance)),
                 static_cast<long long>(std::floor(p.y() / merge_tolerance)),
                 static_cast<long long>(std::floor(p.z() / merge_tolerance))};
    };
    for (int i = 0; i < n; ++i) {
      const Vec3& p = nodes[static_cast<std::size_t>(i)].position;
      const Key k = key(p);
      for (long long dx = -1; dx <= 1; ++dx) {
        for (long long dy = -1; dy <= 1; ++dy) {
          for (long long dz = -1; dz <= 1; ++dz) {
            auto it = cells.find(Key{k.x + dx, k.y + dy, k.z + dz});
            if (it == cells.end()) continue;
            for (const int j : it->second) {
              if ((nodes[static_cast<std::size_t>(j)].position - p).norm() <= merge_tolerance) {
                const int ri = find(parent, i), rj = find(parent, j);
                if (ri != rj) parent[static_cast<std::size_t>(std::max(ri, rj))] = std::min(ri, rj);
              }
            }
          }
        }
      }
      cells[k].push_back(i);
    }
  }
  std::vector<int> compact(nodes.size(), -1);
  Structure s;
  for (int i = 0; i < n; ++i) {
    const int root = find(parent, i);
    if (root == i) {
      compact[static_cast<std::size_t>(i)] = static_cast<int>(s.nodes.size());
      s.nodes.push_back(Node{nodes[static_cast<std::size_t>(i)].position,
                             static_cast<int>(i) + 1,
                             nodes[static_cast<std::size_t>(i)].where});
    }
  }
  for (int i = 0; i < n; ++i) {
    const int root = find(parent, i);
    if (root != i) {
      compact[static_cast<std::size_t>(i)] = compact[static_cast<std::size_t>(root)];
      diags.note(codes::kNodesMerged,
                 fmt::format("node {} is within {:g} mm of node {}: merged into joint {}",
                             number(static_cast<std::size_t>(i)),
                             merge_tolerance,
                             number(static_cast<std::size_t>(root)),
                             root + 1),
                 nodes[static_cast<std::size_t>(i)].where);
    }
  }

  std::map<std::pair<int, int>, std::size_t> seen;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const EdgeInput& in = edges[e];
    bool ok = true;
    for (const long long v : {in.a, in.b}) {
      if (v < first_index || v >= first_index + n) {
        diags.error(codes::kNoSuchNode,
                    fmt::format("edge {} names node {}, but the nodes are numbered {} to {}",
                                e + 1,
                                v,
                                first_index,
                                first_index + n - 1),
                    in.where);
        ok = false;
      }
    }
    if (!ok) continue;
    const int a = compact[static_cast<std::size_t>(in.a - first_index)];
    const int b = compact[static_cast<std::size_t>(in.b - first_index)];
    if (a == b) {
      diags.error(codes::kZeroLengthEdge,
                  in.a == in.b ? fmt::format("edge {} joins node {} to itself", e + 1, in.a)
                               : fmt::format("edge {} joins nodes {} and {}, which are within {:g} "
                                             "mm of each other (zero length)",
                                             e + 1,
                                             in.a,
                                             in.b,
                                             merge_tolerance),
                  in.where);
      continue;
    }
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    if (auto it = seen.find(key); it != seen.end()) {
      diags.error(codes::kDuplicateEdge,
                  fmt::format("edge {} joins nodes {} and {} again (edge {} already does)",
                              e + 1,
                              in.a,
                              in.b,
                              it->second + 1),
                  in.where);
      continue;
    }
    seen.emplace(key, e);
    s.rods.push_back(Rod{a, b, in.where});
  }
  const auto at_nodes = s.rods_at_nodes();
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (at_nodes[i].empty()) {
      diags.error(codes::kIsolatedNode,
                  fmt::format("node {} at {} is not joined to any other node by an edge",
                              s.nodes[i].id - 1 + first_index,
                              at(s.nodes[i].position)),
                  s.nodes[i].where);
    }
    // Rods leaving a node in the same direction would lie inside each other.
    const Vec3& p = s.nodes[i].position;
    for (std::size_t x = 0; x < at_nodes[i].size(); ++x) {
      for (std::size_t y = x + 1; y < at_nodes[i].size(); ++y) {
        auto dir = [&](int rod) {
          const Rod& r = s.rods[static_cast<std::size_t>(rod)];
          const int other = r.a == static_cast<int>(i) ? r.b : r.a;
          return (s.nodes[static_cast<std::size_t>(other)].position - p).normalized();
        };
        const double angle =
            std::acos(std::clamp(dir(at_nodes[i][x]).dot(dir(at_nodes[i][y])), -1.0, 1.0));
        if (angle < 0.01 * kDegToRad) {
          diags.error(codes::kOverlappingEdges,
                      fmt::format("{} and {} leave node {} in the same direction ({:.4f}° apart): "
                                  "the rods would lie inside each other",
                                  s.rod_name(at_nodes[i][x]),
                                  s.rod_name(at_nodes[i][y]),
                                  s.nodes[i].id - 1 + first_index,
                                  angle * kRadToDeg),
                      s.rods[static_cast<std::size_t>(at_nodes[i][y])].where);
        }
      }
    }
  }
  if (errors_since()) return std::nullopt;
  return s;
}

Structure scaled(const Structure& s, double factor) {
  Structure out = s;
  for (Node& n : out.nodes) n.position *= factor;
  return out;
}

}  // namespace fabkit::rods
