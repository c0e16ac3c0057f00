// seam_allowance.h from the promises in its header: the cut line of a piece
// with a seam allowance, on convex and concave outlines, a slot that closes,
// random star-shaped outlines, and bad input.
#include "pattern/seam_allowance.h"

#include "core/types.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace developable {
namespace {

using Vec2 = Eigen::Vector2d;
using Loop = std::vector<Vec2>;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double area(const Loop& loop) {
  double twice = 0.0;
  for (size_t i = 0; i < loop.size(); ++i) twice += cross2(loop[i], loop[(i + 1) % loop.size()]);
  return 0.5 * twice;
}

double segment_distance(const Vec2& x, const Vec2& a, const Vec2& b) {
  const Vec2 e = b - a;
  const double t = std::clamp(e.dot(x - a) / e.squaredNorm(), 0.0, 1.0);
  return (a + t * e - x).norm();
}

// Distance from x to the outline (its edges).
double outline_distance(const Loop& outline, const Vec2& x) {
  double best = INFINITY;
  for (size_t i = 0; i < outline.size(); ++i)
    best = std::min(best, segment_distance(x, outline[i], outline[(i + 1) % outline.size()]));
  return best;
}

bool inside(const Loop& loop, const Vec2& x) {
  bool in = false;
  for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++)
    if ((loop[i].y() > x.y()) != (loop[j].y() > x.y()) &&
        x.x() < (loop[j].x() - loop[i].x()) * (x.y() - loop[i].y()) / (loop[j].y() - loop[i].y()) + loop[i].x())
      in = !in;
  return in;
}

bool proper_crossing(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = cross2(b - a, c - a), d2 = cross2(b - a, d - a);
  const double d3 = cross2(d - c, a - c), d4 = cross2(d - c, b - c);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0;
}

bool simple(const Loop& loop) {
  const size_t n = loop.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;
      if (proper_crossing(loop[i], loop[(i + 1) % n], loop[j], loop[(j + 1) % n])) return false;
    }
  return true;
}

// The header's promise: every corner at `distance` from the outline within
// `tolerance`, every point of the cut line (sampled along its edges) at least
// `distance` - `tolerance` from it and outside it, same orientation, simple.
void expect_offset(const Loop& outline, const OffsetOutline& offset, double distance, double tolerance) {
  EXPECT_FALSE(offset.from_hull);
  const Loop& cut = offset.points;
  ASSERT_GE(cut.size(), 3u);
  EXPECT_EQ(area(cut) > 0, area(outline) > 0);
  EXPECT_GT(std::abs(area(cut)), std::abs(area(outline)));
  EXPECT_TRUE(simple(cut));
  for (size_t i = 0; i < cut.size(); ++i) {
    EXPECT_NEAR(outline_distance(outline, cut[i]), distance, tolerance) << "corner " << i;
    for (double t : {0.25, 0.5, 0.75}) {
      const Vec2 x = cut[i] + t * (cut[(i + 1) % cut.size()] - cut[i]);
      EXPECT_GE(outline_distance(outline, x), distance - tolerance) << "edge " << i;
      EXPECT_FALSE(inside(outline, x)) << "edge " << i;
    }
  }
}

TEST(SeamAllowance, SquareGetsRoundCornersAndTheAreaOfItsOffset) {
  const Loop square{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const OffsetOutline cut = offset_outline(square, 2.0, 0.01);
  expect_offset(square, cut, 2.0, 0.01);
  // Steiner: area + perimeter d + pi d^2, less the chords' sag.
  EXPECT_NEAR(area(cut.points), 100.0 + 40.0 * 2.0 + M_PI * 4.0, 0.05);
}

TEST(SeamAllowance, KeepsTheOutlinesOrientation) {
  Loop clockwise{{0, 0}, {0, 10}, {10, 10}, {10, 0}};
  const OffsetOutline cut = offset_outline(clockwise, 1.0, 0.01);
  EXPECT_LT(area(cut.points), 0.0);
  expect_offset(clockwise, cut, 1.0, 0.01);
}

TEST(SeamAllowance, ReflexCornerIsCutWhereTheShiftedEdgesCross) {
  const Loop ell{{0, 0}, {20, 0}, {20, 8}, {8, 8}, {8, 20}, {0, 20}};
  const OffsetOutline cut = offset_outline(ell, 3.0, 0.01);
  expect_offset(ell, cut, 3.0, 0.01);
  // The reflex corner (8, 8) gives the sharp corner (11, 11) of the cut line.
  double nearest = INFINITY;
  for (const Vec2& p : cut.points) nearest = std::min(nearest, (p - Vec2(11, 11)).norm());
  EXPECT_LT(nearest, 1e-9);
}

TEST(SeamAllowance, SlotNarrowerThanTwiceTheAllowanceIsBridged) {
  // A U: two arms 4 apart. With 1 the slot stays open; with 3 it closes and
  // the cut line runs across its mouth, leaving no loop inside.
  const Loop u{{0, 0}, {14, 0}, {14, 20}, {9, 20}, {9, 6}, {5, 6}, {5, 20}, {0, 20}};
  const OffsetOutline open = offset_outline(u, 1.0, 0.01);
  expect_offset(u, open, 1.0, 0.01);
  bool reaches_in = false;
  for (const Vec2& p : open.points) reaches_in = reaches_in || (p.x() > 5.5 && p.x() < 8.5 && p.y() < 10);
  EXPECT_TRUE(reaches_in);
  const OffsetOutline closed = offset_outline(u, 3.0, 0.01);
  expect_offset(u, closed, 3.0, 0.01);
  for (const Vec2& p : closed.points) EXPECT_FALSE(p.x() > 5.5 && p.x() < 8.5 && p.y() < 20) << p.transpose();
}

TEST(SeamAllowance, RandomStarShapedOutlines) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> radius(3.0, 10.0), jitter(-0.3, 0.3);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 8 + trial * 4;
    Loop star;
    for (int i = 0; i < n; ++i) {
      const double angle = 2 * M_PI * (i + 0.5 + jitter(random)) / n;
      const double r = radius(random);
      star.emplace_back(r * std::cos(angle), r * std::sin(angle));
    }
    for (double d : {0.2, 1.0, 4.0}) {
      SCOPED_TRACE(testing::Message() << "trial " << trial << " distance " << d);
      expect_offset(star, offset_outline(star, d, 0.005), d, 0.005);
    }
  }
}

TEST(SeamAllowance, RepeatedCornersAndAClosingCornerAreIgnored) {
  const Loop square{{0, 0}, {10, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}};
  const OffsetOutline cut = offset_outline(square, 1.0, 0.01);
  expect_offset(Loop{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, cut, 1.0, 0.01);
}

TEST(SeamAllowance, BadInputIsAnInvalidArgument) {
  const Loop square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const auto status = [](const Loop& loop, double d, double tol) {
    try {
      offset_outline(loop, d, tol);
    } catch (const EngineError& e) {
      return e.status();
    }
    return Status::ok;
  };
  EXPECT_EQ(status(square, 0.0, 0.01), Status::invalid_argument);
  EXPECT_EQ(status(square, -1.0, 0.01), Status::invalid_argument);
  EXPECT_EQ(status(square, NAN, 0.01), Status::invalid_argument);
  EXPECT_EQ(status(square, 1.0, 0.0), Status::invalid_argument);
  EXPECT_EQ(status(Loop{{0, 0}, {1, 0}}, 1.0, 0.01), Status::invalid_argument);
  EXPECT_EQ(status(Loop{{0, 0}, {1, 0}, {2, 0}}, 1.0, 0.01), Status::invalid_argument);
  EXPECT_EQ(status(Loop{{0, 0}, {1, NAN}, {1, 1}}, 1.0, 0.01), Status::invalid_argument);
}

}  // namespace
}  // namespace developable
