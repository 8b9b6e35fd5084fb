#include "fabkit/hacks/part_solid.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <string_view>
#include <system_error>

#include "fabkit/core/file_io.h"
#include "fabkit/core/mesh_boolean.h"
#include "fabkit/hacks/diagnostic_codes.h"

namespace fabkit::hacks {
namespace {

// Disjoint sets over 0..n-1 (path halving), for vertices joined by faces and for pieces
// joined by overlapping bounds.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

struct Bounds {
  Vec3 lo;
  Vec3 hi;
  // Closed intervals: pieces that only touch (a basket's wall standing on its floor) are
  // unioned too, so that the shared face disappears.
  bool overlaps(const Bounds& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
};

// Slivers under 10 µm are removed from the union, so that it stays a solid in float32 files.
const BooleanOptions kForFiles{.min_feature_mm = 0.01, .deadline = std::nullopt};

// Pieces are drawn to meet flush (a rod's end on a bracket's face, one hook's end cap on the
// next hook's), but computed along different paths (rotations, sin and cos), so what should
// coincide misses by a few ulps; an exact union then sees a gap or overlap a few ulps thick
// and makes slivers of it. Snapping every vertex to a 2^-14 mm (0.06 µm) grid makes such faces
// coincide exactly, which the exact union handles cleanly.
constexpr double kSnapGrid = 1.0 / 16384;

TriangleMesh snapped(TriangleMesh m) {
  for (Vec3& v : m.vertices) {
    for (int k = 0; k < 3; ++k) v[k] = std::round(v[k] / kSnapGrid) * kSnapGrid + 0.0;
  }
  return m;
}

std::string part_name(const Part& part) {
  return part.type_name.empty() ? std::string("part") : "part " + part.type_name;
}

}  // namespace

std::vector<TriangleMesh> mesh_pieces(const TriangleMesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  DisjointSets sets(n);
  for (const auto& f : mesh.faces) {
    sets.unite(static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[1]));
    sets.unite(static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[2]));
  }
  std::vector<TriangleMesh> pieces;
  std::vector<int> piece_of_root(n, -1);
  std::vector<int> new_index(n, -1);
  for (const auto& f : mesh.faces) {
    const std::size_t root = sets.find(static_cast<std::size_t>(f[0]));
    if (piece_of_root[root] < 0) {
      piece_of_root[root] = static_cast<int>(pieces.size());
      pieces.emplace_back();
    }
    TriangleMesh& piece = pieces[static_cast<std::size_t>(piece_of_root[root])];
    Eigen::Vector3i tri;
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(f[k]);
      if (new_index[v] < 0) {
        new_index[v] = static_cast<int>(piece.vertices.size());
        piece.vertices.push_back(mesh.vertices[v]);
      }
      tri[k] = new_index[v];
    }
    piece.faces.push_back(tri);
  }
  return pieces;
}

PartSolid part_solid(const Part& part) {
  PartSolid out;
  std::vector<TriangleMesh> pieces = mesh_pieces(part.mesh);
  for (TriangleMesh& piece : pieces) piece = snapped(std::move(piece));
  out.pieces = static_cast<int>(pieces.size());
  const std::string who = part_name(part);
  auto as_it_is = [&](std::string why) {
    out.diagnostics.warning(
        codes::kNotASolid,
        fmt::format("{}: exported as its display mesh, not one solid: {}", who, why));
    out.mesh = part.mesh;
    out.shells = out.pieces;
    out.exact = false;
    return out;
  };
  // The union is defined only for closed, outward, non-self-intersecting operands; a piece
  // that is not (a user's open scan) leaves the part as it is, with the reason.
  std::vector<Bounds> bounds;
  bounds.reserve(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const SolidCheck c = check_solid(pieces[i]);
    if (!c.valid_solid()) {
      return as_it_is(fmt::format(
          "piece {} of {} is not a closed solid ({})", i + 1, pieces.size(), c.problems()));
    }
    bounds.push_back({pieces[i].bounds_min(), pieces[i].bounds_max()});
  }
  // Pieces whose bounds are apart cannot intersect: only each group of overlapping pieces is
  // unioned, and the groups are put side by side.
  DisjointSets groups(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    for (std::size_t j = i + 1; j < pieces.size(); ++j) {
      if (bounds[i].overlaps(bounds[j])) groups.unite(i, j);
    }
  }
  TriangleMesh solid;
  for (std::size_t root = 0; root < pieces.size(); ++root) {
    if (groups.find(root) != root) continue;
    std::vector<TriangleMesh> members;
    for (std::size_t i = root; i < pieces.size(); ++i) {
      if (groups.find(i) == root) members.push_back(pieces[i]);
    }
    if (members.size() == 1) {
      solid.append(members.front());
      continue;
    }
    Diagnostics d;
    const std::optional<TriangleMesh> u = mesh_union(members, who, d, kForFiles);
    if (!u) return as_it_is(d.empty() ? std::string("the union failed") : d.begin()->message);
    solid.append(*u);
  }
  out.mesh = std::move(solid);
  out.shells = static_cast<int>(mesh_pieces(out.mesh).size());
  out.exact = true;
  return out;
}

std::optional<Mat4> float32_safe_placement(const TriangleMesh& solid, const Mat4& placement) {
  // Nudges of 2^-12 mm (0.24 µm, about one float step at 2 m): rounding then falls differently
  // at the wedge, and nothing a printer or a person can see moves.
  constexpr double kNudge = 1.0 / 4096;
  const Vec3 nudges[] = {Vec3::Zero(),
                         Vec3(kNudge, 2 * kNudge, 3 * kNudge),
                         Vec3(-3 * kNudge, kNudge, -2 * kNudge),
                         Vec3(2 * kNudge, -3 * kNudge, kNudge)};
  for (const Vec3& nudge : nudges) {
    Mat4 moved = placement;
    moved.topRightCorner<3, 1>() += nudge;
    if (check_solid(rounded_to_float32(solid.transformed(moved))).valid_solid()) return moved;
  }
  return std::nullopt;
}

namespace {

// Raised whenever part_solid() would compute a different solid from the same display mesh
// (snapping, sliver removal, the union itself), so that solids kept on disk by an older
// fabkit are recomputed rather than reused.
constexpr std::uint64_t kSolidVersion = 1;
// First bytes of a solid file; the byte-order mark makes a file from a machine of the other
// endianness a miss rather than garbage.
constexpr std::string_view kSolidMagic = "fabkit part solid\n";
constexpr std::uint32_t kByteOrderMark = 0x01020304;

// FNV-1a, 64 bits: a cache key and a checksum, not a defence against someone who writes the
// cache directory on purpose (their own files).
class Fnv1a {
 public:
  void add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= bytes[i];
      hash_ *= 0x100000001b3ULL;
    }
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// Reads the bytes of one value at a time, failing (and staying failed) at the end.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  template <class T>
  bool get(T& value) {
    if (!ok_ || bytes_.size() - at_ < sizeof(T)) return ok_ = false;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return true;
  }
  bool skip(std::string_view expected) {
    if (!ok_ || bytes_.substr(at_, expected.size()) != expected) return ok_ = false;
    at_ += expected.size();
    return true;
  }
  std::size_t remaining() const { return bytes_.size() - at_; }
  std::size_t position() const { return at_; }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
  bool ok_ = true;
};

std::uint64_t checksum(std::string_view bytes) {
  Fnv1a h;
  h.add(bytes.data(), bytes.size());
  return h.value();
}

}  // namespace

std::uint64_t part_solid_key(const TriangleMesh& display_mesh) {
  Fnv1a h;
  h.add(&kSolidVersion, sizeof kSolidVersion);
  const std::uint64_t nv = display_mesh.vertices.size(), nf = display_mesh.faces.size();
  h.add(&nv, sizeof nv);
  h.add(&nf, sizeof nf);
  for (const Vec3& v : display_mesh.vertices) h.add(v.data(), 3 * sizeof(double));
  for (const auto& f : display_mesh.faces) h.add(f.data(), 3 * sizeof(int));
  return h.value();
}

PartSolidCache::PartSolidCache(std::filesystem::path directory)
    : directory_(std::move(directory)) {}

// A solid file: magic, byte-order mark, version, key, the source's vertex and face counts,
// pieces, shells, the solid's vertex and face counts, vertices (doubles), faces (int32), and
// a checksum of everything before it. Only exact solids are kept: a fallback carries
// diagnostics naming the part, and a part that cannot be made a solid is rare.
std::optional<PartSolid> PartSolidCache::load(const TriangleMesh& source,
                                              std::uint64_t hash) const {
  const std::filesystem::path path = directory_ / fmt::format("{:016x}.solid", hash);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  Diagnostics ignored;  // an unreadable cache file is only a miss
  const std::optional<std::string> bytes = read_input_file(path, "solid cache file", ignored);
  if (!bytes || bytes->size() < sizeof(std::uint64_t)) return std::nullopt;
  const std::string_view body(bytes->data(), bytes->size() - sizeof(std::uint64_t));
  std::uint64_t stored_sum = 0;
  std::memcpy(&stored_sum, bytes->data() + body.size(), sizeof stored_sum);
  if (stored_sum != checksum(body)) return std::nullopt;
  Reader r(body);
  std::uint32_t mark = 0;
  std::uint64_t version = 0, key = 0, source_v = 0, source_f = 0, nv = 0, nf = 0;
  std::int32_t pieces = 0, shells = 0;
  if (!r.skip(kSolidMagic) || !r.get(mark) || !r.get(version) || !r.get(key) || !r.get(source_v) ||
      !r.get(source_f) || !r.get(pieces) || !r.get(shells) || !r.get(nv) || !r.get(nf)) {
    return std::nullopt;
  }
  if (mark != kByteOrderMark || version != kSolidVersion || key != hash ||
      source_v != source.vertices.size() || source_f != source.faces.size() ||
      r.remaining() != nv * 3 * sizeof(double) + nf * 3 * sizeof(std::int32_t)) {
    return std::nullopt;
  }
  PartSolid s;
  s.pieces = pieces;
  s.shells = shells;
  s.exact = true;
  s.mesh.vertices.resize(nv);
  s.mesh.faces.resize(nf);
  for (Vec3& v : s.mesh.vertices) {
    for (int k = 0; k < 3; ++k) r.get(v[k]);
  }
  for (auto& f : s.mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      std::int32_t index = 0;
      r.get(index);
      if (index < 0 || static_cast<std::uint64_t>(index) >= nv) return std::nullopt;
      f[k] = index;
    }
  }
  return s;
}

void PartSolidCache::store(const TriangleMesh& source,
                           std::uint64_t hash,
                           const PartSolid& solid) const {
  std::string out(kSolidMagic);
  put(out, kByteOrderMark);
  put(out, kSolidVersion);
  put(out, hash);
  put(out, static_cast<std::uint64_t>(source.vertices.size()));
  put(out, static_cast<std::uint64_t>(source.faces.size()));
  put(out, static_cast<std::int32_t>(solid.pieces));
  put(out, static_cast<std::int32_t>(solid.shells));
  put(out, static_cast<std::uint64_t>(solid.mesh.vertices.size()));
  put(out, static_cast<std::uint64_t>(solid.mesh.faces.size()));
  for (const Vec3& v : solid.mesh.vertices) {
    for (int k = 0; k < 3; ++k) put(out, v[k]);
  }
  for (const auto& f : solid.mesh.faces) {
    for (int k = 0; k < 3; ++k) put(out, static_cast<std::int32_t>(f[k]));
  }
  put(out, checksum(out));
  // A cache that cannot be written (read-only home, full disk) costs time, not correctness:
  // the export goes on with the solid computed here.
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  Diagnostics ignored;
  write_file_atomically(directory_ / fmt::format("{:016x}.solid", hash), out, ignored);
}

const PartSolid& PartSolidCache::solid(const Part& part) {
  auto& bucket = entries_[{part.type_name, part.mesh.faces.size()}];
  for (const std::unique_ptr<Entry>& e : bucket) {
    if (e->params == part.params && e->source.faces == part.mesh.faces &&
        e->source.vertices == part.mesh.vertices) {
      ++reused_;
      return e->solid;
    }
  }
  auto e = std::make_unique<Entry>();
  e->params = part.params;
  e->source = part.mesh;
  const std::uint64_t hash = directory_.empty() ? 0 : part_solid_key(part.mesh);
  std::optional<PartSolid> kept = directory_.empty() ? std::nullopt : load(part.mesh, hash);
  if (kept) {
    e->solid = std::move(*kept);
    ++loaded_;
  } else {
    e->solid = part_solid(part);
    ++computed_;
    if (!directory_.empty() && e->solid.exact) store(part.mesh, hash, e->solid);
  }
  bucket.push_back(std::move(e));
  return bucket.back()->solid;
}

}  // namespace fabkit::hacks
