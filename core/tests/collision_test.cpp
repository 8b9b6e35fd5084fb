// Distances and penetration depths between convex pieces, against hand-computed geometry.
#include "fabkit/core/collision.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace fabkit::collision {
namespace {

Mat4 at(const Vec3& t, double turn_deg = 0) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(turn_deg * M_PI / 180, Vec3::UnitZ()).matrix();
  m.topRightCorner<3, 1>() = t;
  return m;
}

// The box from `lo` to `hi`.
TriangleMesh block(const Vec3& lo, const Vec3& hi) {
  Mat4 m = Mat4::Identity();
  m.topRightCorner<3, 1>() = (lo + hi) / 2;
  return shapes::box(hi - lo).transformed(m);
}

Body one(const TriangleMesh& piece, int tag = -1) {
  const std::vector<TriangleMesh> pieces{piece};
  const std::vector<int> tags{tag};
  return Body(pieces, tags);
}

// Two 10 mm cubes (centred on their origins) 25 mm apart along x: a 15 mm gap.
TEST(Collision, GapBetweenSeparatedCubes) {
  const Body a = one(block(Vec3(-5, -5, -5), Vec3(5, 5, 5)));
  const Body b = one(block(Vec3(-5, -5, -5), Vec3(5, 5, 5)));
  const Proximity p = piece_distance(a, 0, at(Vec3::Zero()), b, 0, at(Vec3(25, 3, 0)));
  EXPECT_NEAR(p.distance, 15.0, 1e-6);
  EXPECT_NEAR(p.normal.x(), 1.0, 1e-6);
  EXPECT_NEAR((p.point_b - p.point_a).norm(), 15.0, 1e-6);
  EXPECT_GE(piece_gap_bound(a, 0, at(Vec3::Zero()), b, 0, at(Vec3(25, 3, 0))), 0.0);
  EXPECT_LE(piece_gap_bound(a, 0, at(Vec3::Zero()), b, 0, at(Vec3(25, 3, 0))), 15.0 + 1e-9);
}

// Overlapping by 0.3 mm along z: the depth is the overlap, the normal separates them.
TEST(Collision, ShallowOverlapDepthAndNormal) {
  const Body a = one(block(Vec3(-50, -50, -5), Vec3(50, 50, 5)));
  const Body b = one(block(Vec3(-5, -5, -5), Vec3(5, 5, 5)));
  const Proximity p = piece_distance(a, 0, at(Vec3::Zero()), b, 0, at(Vec3(1, 2, 9.7)));
  EXPECT_NEAR(p.distance, -0.3, 1e-3);
  EXPECT_NEAR(p.normal.z(), 1.0, 1e-3);
}

// A deep overlap: a small cube sunk 4 mm into a slab's top is pushed out the top (the
// shortest way), not through the slab.
TEST(Collision, DeepOverlapTakesTheShortestWayOut) {
  const Body a = one(block(Vec3(-50, -50, -20), Vec3(50, 50, 0)));
  const Body b = one(block(Vec3(-5, -5, -5), Vec3(5, 5, 5)));
  const Proximity p = piece_distance(a, 0, at(Vec3::Zero()), b, 0, at(Vec3(0, 0, 1)));
  EXPECT_NEAR(p.distance, -4.0, 1e-3);
  EXPECT_NEAR(p.normal.z(), 1.0, 1e-3);
}

// Distance does not depend on where the pair is in the world or how it is turned.
TEST(Collision, InvariantUnderRigidMotionOfBoth) {
  const Body a = one(block(Vec3(-5, -5, -5), Vec3(5, 5, 5)));
  const Body b = one(block(Vec3(-2, -2, -2), Vec3(2, 2, 2)));
  const double d0 = piece_distance(a, 0, at(Vec3::Zero()), b, 0, at(Vec3(12, 0, 0))).distance;
  Mat4 world = at(Vec3(1000, -300, 40), 37);
  const double d1 =
      piece_distance(a, 0, world * at(Vec3::Zero()), b, 0, world * at(Vec3(12, 0, 0))).distance;
  EXPECT_NEAR(d0, 5.0, 1e-6);
  EXPECT_NEAR(d1, d0, 1e-6);
}

// A rod drawn as a coarse hexagonal prism but given its two end circles as rims is a real
// cylinder: its gap to a wall is the same whichever way it is spun about its axis (the prism
// alone is not), and the normal is the wall's.
TEST(Collision, ARoundRodIsTheSameCylinderWhateverItsSpin) {
  const std::vector<TriangleMesh> prism{shapes::cylinder(10, 60, 6)};
  const std::vector<int> tags{-1};
  Arc low, high;
  low.radius = high.radius = 10;
  low.centre = Vec3(0, 0, -30);
  high.centre = Vec3(0, 0, 30);
  const std::vector<std::vector<Arc>> rims{{low, high}};
  const Body rod(prism, tags, rims);
  const Body faceted(prism, tags);
  const Body wall = one(block(Vec3(15, -50, -50), Vec3(40, 50, 50)));
  double faceted_low = 1e9, faceted_high = -1e9;
  for (double spin = 0; spin < 60; spin += 7) {
    const Proximity p = piece_distance(rod, 0, at(Vec3::Zero(), spin), wall, 0, at(Vec3::Zero()));
    EXPECT_NEAR(p.distance, 5.0, 1e-6) << spin;
    EXPECT_NEAR(p.normal.x(), 1.0, 1e-6) << spin;
    const double f =
        piece_distance(faceted, 0, at(Vec3::Zero(), spin), wall, 0, at(Vec3::Zero())).distance;
    faceted_low = std::min(faceted_low, f);
    faceted_high = std::max(faceted_high, f);
  }
  // Sunk 0.3 mm into the wall, the depth is the overlap.
  const Proximity sunk = piece_distance(rod, 0, at(Vec3(5.3, 0, 0), 17), wall, 0, at(Vec3::Zero()));
  EXPECT_NEAR(sunk.distance, -0.3, 1e-3);
  EXPECT_NEAR(sunk.normal.x(), 1.0, 1e-3);
  // The prism's gap swings between 15 − 10 and 15 − 10·cos 30°.
  EXPECT_GT(faceted_high - faceted_low, 1.0);
  EXPECT_NEAR(rod.piece_max(0).x(), 10, 1e-9);
  EXPECT_NEAR(rod.piece_min(0).y(), -10, 1e-9);
}

// A rod of radius 10 and length 60 along z, drawn as an octagonal prism with its two end
// circles as rims: a real cylinder to the queries.
Body round_rod() {
  const std::vector<TriangleMesh> prism{shapes::cylinder(10, 60, 8)};
  const std::vector<int> tags{-1};
  Arc low, high;
  low.radius = high.radius = 10;
  low.centre = Vec3(0, 0, -30);
  high.centre = Vec3(0, 0, 30);
  const std::vector<std::vector<Arc>> rims{{low, high}};
  return Body(prism, tags, rims);
}

// The distance bounds hold whatever the shapes and poses: apart, the lower is at most the gap
// and the upper at least it; overlapping, the lower is at most minus the depth. Boxes, a slanted
// slab and a round rod with rims, under seeded random rigid motions. Two faces squarely apart
// along the line of their centres get the gap itself from both.
TEST(Collision, DistanceBoundsHoldTheSignedDistance) {
  const Body cube = one(block(Vec3(-5, -5, -5), Vec3(5, 5, 5)));
  const DistanceBounds square =
      piece_distance_bounds(cube, 0, at(Vec3::Zero()), cube, 0, at(Vec3(25, 0, 0)));
  EXPECT_NEAR(square.lower, 15.0, 1e-9);
  EXPECT_NEAR(square.upper, 15.0, 1e-9);
  const Body slab = one(block(Vec3(-40, -2, -8), Vec3(40, 2, 8)));
  const Body rod = round_rod();
  const std::vector<const Body*> bodies{&cube, &slab, &rod};
  std::mt19937 draw(20261207);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto pose = [&](double reach_mm) {
    Mat4 m = Mat4::Identity();
    const Eigen::Quaterniond q(unit(draw), unit(draw), unit(draw), unit(draw));
    m.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
    m.topRightCorner<3, 1>() = reach_mm * Vec3(unit(draw), unit(draw), unit(draw));
    return m;
  };
  int apart = 0, overlapping = 0, settled_far = 0, settled_near = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const Body& a = *bodies[static_cast<std::size_t>(trial % 3)];
    const Body& b = *bodies[static_cast<std::size_t>((trial / 3) % 3)];
    const Mat4 ta = pose(10.0);
    const Mat4 tb = pose(trial % 2 ? 60.0 : 20.0);
    const DistanceBounds bounds = piece_distance_bounds(a, 0, ta, b, 0, tb);
    const double distance = piece_distance(a, 0, ta, b, 0, tb).distance;
    EXPECT_LE(bounds.lower, distance + 1e-6) << "trial " << trial;
    if (distance > 0) {
      EXPECT_GE(bounds.upper, distance - 1e-6) << "trial " << trial;
      ++apart;
    } else {
      ++overlapping;
    }
    // What the bounds settle against a 25 mm cut-off without an exact query.
    if (bounds.lower > 25.0) ++settled_far;
    if (bounds.lower > 0 && bounds.upper <= 25.0) ++settled_near;
  }
  EXPECT_GT(apart, 100);
  EXPECT_GT(overlapping, 50);
  EXPECT_GT(settled_far, 50);
  EXPECT_GT(settled_near, 20);
}

// A round rod rolling around a box's edge: the gap is the axis's distance to the edge less the
// radius and the normal points from the axis to the edge, changing smoothly as it rolls (what
// a relaxation resting a roll on an edge needs), down to touching.
TEST(Collision, ARoundRodAgainstAnEdgeHasTheExactGapAndNormal) {
  const Body rod = round_rod();
  // The block's edge along z through (20, 0).
  const Body block_body = one(block(Vec3(20, 0, -50), Vec3(60, 40, 50)));
  for (double a = 185; a < 265; a += 11) {
    const double r = a * M_PI / 180;
    const Vec3 towards_edge(-std::cos(r), -std::sin(r), 0);  // from the axis to the edge
    for (const double gap : {3.0, 1e-3, 1e-10}) {
      const Vec3 axis = Vec3(20, 0, 0) - (10 + gap) * towards_edge;
      const Proximity p = piece_distance(rod, 0, at(axis), block_body, 0, at(Vec3::Zero()));
      SCOPED_TRACE(testing::Message() << "angle " << a << " gap " << gap);
      EXPECT_NEAR(p.distance, gap, 1e-6);
      EXPECT_NEAR(p.normal.dot(towards_edge), 1.0, 1e-8);
    }
  }
}

// The same rod and edge 220 m from the world's origin: the gap and the normal are as exact as
// near it (world coordinates of 10⁵ mm carry round-off of 10⁻¹¹ mm, GJK's tolerance for round
// pieces is 10⁻¹² mm; a design that far out must still rest as it does near the origin).
TEST(Collision, FarFromTheOriginTheGapAndNormalAreAsExact) {
  const Body rod = round_rod();
  const Body block_body = one(block(Vec3(20, 0, -50), Vec3(60, 40, 50)));
  const Mat4 world = at(Vec3(100000.25, -200000.5, 321), 12.5);
  const Mat3 turn = world.topLeftCorner<3, 3>();
  for (double a = 185; a < 265; a += 11) {
    const double r = a * M_PI / 180;
    const Vec3 towards_edge(-std::cos(r), -std::sin(r), 0);
    for (const double gap : {3.0, 1e-3, 1e-10}) {
      const Vec3 axis = Vec3(20, 0, 0) - (10 + gap) * towards_edge;
      const Proximity p =
          piece_distance(rod, 0, world * at(axis), block_body, 0, world * at(Vec3::Zero()));
      SCOPED_TRACE(testing::Message() << "angle " << a << " gap " << gap);
      EXPECT_NEAR(p.distance, gap, 1e-6);
      EXPECT_NEAR(p.normal.dot(turn * towards_edge), 1.0, 1e-8);
      const Vec3 edge_point =
          world.topLeftCorner<3, 3>() * Vec3(20, 0, 0) + world.topRightCorner<3, 1>();
      EXPECT_LT((p.point_b - edge_point).head<2>().norm(), 1e-6);
    }
  }
}

// A quarter of a circle as a piece's rim widens its bounds only where the arc goes.
TEST(Collision, AnArcRimBoundsAndSupport) {
  Arc quarter;
  quarter.radius = 10;
  quarter.from = 0;
  quarter.to = M_PI / 2;
  EXPECT_NEAR(
      (quarter.support(Vec3(1, 1, 0)) - Vec3(std::sqrt(50), std::sqrt(50), 0)).norm(), 0, 1e-12);
  // Outside the arc's angles the nearer end is the farthest point along the direction.
  EXPECT_NEAR((quarter.support(Vec3(1, -3, 0)) - Vec3(10, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((quarter.support(Vec3(-3, 1, 0)) - Vec3(0, 10, 0)).norm(), 0, 1e-12);
  const std::vector<TriangleMesh> pieces{block(Vec3(0, 0, -1), Vec3(1, 1, 1))};
  const std::vector<int> tags{-1};
  const std::vector<std::vector<Arc>> rims{{quarter}};
  const Body b(pieces, tags, rims);
  EXPECT_NEAR(b.piece_max(0).x(), 10, 1e-12);
  EXPECT_NEAR(b.piece_max(0).y(), 10, 1e-12);
  EXPECT_NEAR(b.piece_min(0).x(), 0, 1e-12);
  EXPECT_NEAR(b.piece_min(0).y(), 0, 1e-12);
}

// A body keeps its pieces' tags and bounds.
TEST(Collision, BodyKeepsTagsAndBounds) {
  const std::vector<TriangleMesh> pieces{block(Vec3(0, 0, 0), Vec3(1, 2, 3)),
                                         block(Vec3(-4, 0, 0), Vec3(-3, 1, 1))};
  const std::vector<int> tags{7, -1};
  const Body b(pieces, tags);
  ASSERT_EQ(b.piece_count(), 2);
  EXPECT_EQ(b.tag(0), 7);
  EXPECT_EQ(b.tag(1), -1);
  EXPECT_NEAR(b.bounds_min().x(), -4, 1e-12);
  EXPECT_NEAR(b.bounds_max().z(), 3, 1e-12);
  EXPECT_NEAR(b.piece_max(0).y(), 2, 1e-12);
}

// A part's body is built once and kept; a copy of its owner (which may then be edited)
// starts without one, and a change of the pieces builds it again.
TEST(CachedBody, KeptByItsOwnerNotByCopies) {
  struct Owner {
    std::vector<TriangleMesh> pieces;
    std::vector<int> tags;
    CachedBody body;
  };
  Owner original{{block(Vec3(0, 0, 0), Vec3(10, 10, 10))}, {-1}, {}};
  const Body first = original.body.get(original.pieces, original.tags);
  EXPECT_EQ(first.piece_count(), 1);
  EXPECT_EQ(original.body.get(original.pieces, original.tags).bounds_max(), Vec3(10, 10, 10));

  Owner copy = original;
  copy.pieces.push_back(block(Vec3(20, 0, 0), Vec3(30, 10, 10)));
  copy.tags.push_back(3);
  const Body edited = copy.body.get(copy.pieces, copy.tags);
  EXPECT_EQ(edited.piece_count(), 2);
  EXPECT_EQ(edited.tag(1), 3);
  EXPECT_EQ(edited.bounds_max(), Vec3(30, 10, 10));
  EXPECT_EQ(original.body.get(original.pieces, original.tags).piece_count(), 1);

  original.pieces.push_back(block(Vec3(0, 0, 20), Vec3(10, 10, 40)));
  original.tags.push_back(-1);
  EXPECT_EQ(original.body.get(original.pieces, original.tags).bounds_max(), Vec3(10, 10, 40));
}

// Owners of the same pieces (a design's copies of one part) share one set of shapes, built
// once; owners of other pieces, or other tags, do not.
TEST(CachedBody, EqualContentsShareOneBody) {
  const std::vector<TriangleMesh> pieces{block(Vec3(0, 0, 0), Vec3(10, 10, 10)),
                                         block(Vec3(20, 0, 0), Vec3(30, 5, 5))};
  const std::vector<int> tags{-1, 2};
  CachedBody a;
  CachedBody b;
  const std::vector<TriangleMesh> copied = pieces;  // other storage, same numbers
  const Body first = a.get(pieces, tags);
  EXPECT_TRUE(first.shares_shapes_with(b.get(copied, tags)));

  CachedBody c;
  std::vector<TriangleMesh> moved = pieces;
  moved[1].vertices[0].x() += 1e-9;
  EXPECT_FALSE(first.shares_shapes_with(c.get(moved, tags)));
  CachedBody d;
  const Body retagged = d.get(pieces, std::vector<int>{-1, 3});
  EXPECT_FALSE(first.shares_shapes_with(retagged));
  EXPECT_EQ(retagged.tag(1), 3);
}

}  // namespace
}  // namespace fabkit::collision
