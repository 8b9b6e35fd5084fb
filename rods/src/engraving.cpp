#include "fabkit/rods/engraving.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

#include "fabkit/core/extrude.h"
#include "fabkit/core/glyph_outline.h"
#include "fabkit/core/mesh_query.h"

namespace fabkit::rods {
namespace {

struct Sample {
  Vec3 p;
  Vec3 n;
};

double unit(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

// Cosine-weighted hemisphere directions about +z, the same for every sample (a spiral).
std::vector<Vec3> hemisphere_directions(int count) {
  std::vector<Vec3> dirs;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double r = std::sqrt((i + 0.5) / count);
    const double phi = golden * i;
    dirs.emplace_back(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - r * r)));
  }
  return dirs;
}

Mat3 frame_about(const Vec3& n) {
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 t = helper.cross(n).normalized();
  Mat3 f;
  f.col(0) = t;
  f.col(1) = n.cross(t);
  f.col(2) = n;
  return f;
}

}  // namespace

std::optional<EngravingSpot> choose_engraving_spot(const TriangleMesh& mesh,
                                                   const TriangleMesh& occluders,
                                                   const Vec3& up_hint,
                                                   const EngravingOptions& options) {
  // Area-weighted random samples with their face normals.
  std::vector<double> cumulative;
  std::vector<Vec3> normals;
  double total = 0;
  for (const auto& f : mesh.faces) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(f[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(f[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(f[2])];
    const Vec3 cr = (b - a).cross(c - a);
    total += cr.norm() / 2;
    cumulative.push_back(total);
    normals.push_back(cr.norm() > 0 ? Vec3(cr.normalized()) : Vec3::UnitZ());
  }
  if (total <= 0 || options.samples < 1) return std::nullopt;
  std::mt19937_64 rng(options.seed);
  std::vector<Sample> samples;
  std::vector<Vec3> points;
  samples.reserve(static_cast<std::size_t>(options.samples));
  for (int i = 0; i < options.samples; ++i) {
    const double x = unit(rng) * total;
    const auto fi = static_cast<std::size_t>(std::min<std::ptrdiff_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin(),
        static_cast<std::ptrdiff_t>(cumulative.size()) - 1));
    double u = unit(rng), v = unit(rng);
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    const auto& f = mesh.faces[fi];
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(f[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(f[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(f[2])];
    samples.push_back({a + u * (b - a) + v * (c - a), normals[fi]});
    points.push_back(samples.back().p);
  }
  const auto neighbors = nearest_neighbors(points, options.neighbors);

  // Curvature: distance-weighted mean dihedral angle between a sample's normal and its
  // neighbours' (weights 1 / distance, so the nearest dominate).
  std::vector<double> curvature(samples.size(), 0), radius(samples.size(), 0);
  const double eps = 1e-3;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    double sum = 0, weights = 0;
    for (const int j : neighbors[i]) {
      const double d = (samples[static_cast<std::size_t>(j)].p - samples[i].p).norm();
      const double w = 1 / (d + eps);
      sum += w * std::acos(std::clamp(
                     samples[i].n.dot(samples[static_cast<std::size_t>(j)].n), -1.0, 1.0));
      weights += w;
      radius[i] = std::max(radius[i], d);
    }
    curvature[i] = weights > 0 ? sum / weights : 0;
  }

  // Occlusion, lazily: samples in order of curvature; once the curvature alone reaches the best
  // sum, no later sample can win (occlusion >= 0).
  TriangleMesh scene = mesh;
  scene.append(occluders);
  const MeshRayQuery rays(scene);
  const std::vector<Vec3> dirs = hemisphere_directions(std::max(1, options.occlusion_rays));
  const double size = (mesh.bounds_max() - mesh.bounds_min()).norm();
  std::vector<std::size_t> order(samples.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return curvature[a] < curvature[b];
  });
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_i = order.front();
  double best_occlusion = 0;
  for (const std::size_t i : order) {
    if (curvature[i] >= best) break;
    const Mat3 f = frame_about(samples[i].n);
    const Vec3 origin = samples[i].p + samples[i].n * (1e-6 * size + 1e-6);
    int blocked = 0;
    for (const Vec3& d : dirs) blocked += rays.hits(origin, f * d) ? 1 : 0;
    const double occlusion = static_cast<double>(blocked) / static_cast<double>(dirs.size());
    if (curvature[i] + occlusion < best) {
      best = curvature[i] + occlusion;
      best_i = i;
      best_occlusion = occlusion;
    }
  }
  EngravingSpot spot;
  spot.position = samples[best_i].p;
  spot.normal = samples[best_i].n;
  spot.radius = radius[best_i];
  spot.curvature = curvature[best_i];
  spot.occlusion = best_occlusion;
  Vec3 up = up_hint - up_hint.dot(spot.normal) * spot.normal;
  if (up.norm() < 0.2) {
    const Vec3 other = std::abs(spot.normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    up = other - other.dot(spot.normal) * spot.normal;
  }
  spot.up = up.normalized();
  return spot;
}

std::optional<TriangleMesh> engraving_cutter(const std::string& label,
                                             const EngravingSpot& spot,
                                             double depth,
                                             const EngravingOptions& options,
                                             Diagnostics& diags,
                                             double* text_height,
                                             double* text_area) {
  TextOutlineOptions text;
  text.font_file = options.font_file;
  text.em_size = 10;
  const auto outline = text_outline(label, text, diags);
  if (!outline || outline->rings.empty()) return std::nullopt;
  const Eigen::Vector2d size = outline->max - outline->min;
  const Eigen::Vector2d middle = (outline->max + outline->min) / 2;
  double scale = 0.9 * spot.radius / (0.5 * size.norm());
  scale = std::min(scale, options.max_text_height / size.y());
  // Flatten at a tolerance relative to the final size, then place.
  text.em_size = 10 * scale;
  text.tolerance = std::max(0.005, 0.01 * text.em_size);
  const auto fitted = text_outline(label, text, diags);
  if (!fitted) return std::nullopt;
  std::vector<Ring2> rings;
  for (const auto& ring : fitted->rings) {
    Ring2 r;
    for (const auto& q : ring) r.push_back(q - middle * scale);
    rings.push_back(std::move(r));
  }
  TriangleMesh cutter = extrude_rings(rings, -depth, depth);
  const Vec3 right = spot.up.cross(spot.normal);
  Mat4 place = Mat4::Identity();
  place.block<3, 1>(0, 0) = right;
  place.block<3, 1>(0, 1) = spot.up;
  place.block<3, 1>(0, 2) = spot.normal;
  place.block<3, 1>(0, 3) = spot.position;
  cutter.transform(place);
  if (text_height) *text_height = (fitted->max - fitted->min).y();
  if (text_area) *text_area = fitted->area();
  return cutter;
}

}  // namespace fabkit::rods
