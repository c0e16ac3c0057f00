// plane_geometry.h from the promises in its header.
#include "pattern/plane_geometry.h"

#include <gtest/gtest.h>

#include <random>

namespace developable {
namespace {

using Vec2 = Eigen::Vector2d;

TEST(ConvexHull, SquareWithInsideAndEdgePointsGivesItsFourCornersCounterClockwise) {
  const std::vector<Vec2> hull = convex_hull({{1, 1}, {0, 0}, {2, 0}, {1, 0}, {2, 2}, {0, 2}, {0.5, 1.5}});
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_EQ(hull[0], Vec2(0, 0));
  EXPECT_EQ(hull[1], Vec2(2, 0));
  EXPECT_EQ(hull[2], Vec2(2, 2));
  EXPECT_EQ(hull[3], Vec2(0, 2));
}

TEST(ConvexHull, RandomPointsAreAllOnTheInnerSideOfEveryEdge) {
  std::mt19937 random(3);
  std::normal_distribution<double> coordinate;
  std::vector<Vec2> points(500);
  for (Vec2& p : points) p = Vec2(coordinate(random), coordinate(random));
  const std::vector<Vec2> hull = convex_hull(points);
  ASSERT_GE(hull.size(), 3u);
  for (size_t i = 0; i < hull.size(); ++i) {
    const Vec2 a = hull[i], b = hull[(i + 1) % hull.size()], c = hull[(i + 2) % hull.size()];
    EXPECT_GT(cross2(b - a, c - b), 0.0);  // a strict left turn: no corner on an edge
    for (const Vec2& p : points) EXPECT_GE(cross2(b - a, p - a), -1e-12);
  }
}

TEST(PlaneGeometry, AreaCrossingsAndInside) {
  const std::vector<Vec2> square{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  EXPECT_DOUBLE_EQ(signed_area(square), 4.0);
  EXPECT_DOUBLE_EQ(signed_area({{0, 0}, {0, 2}, {2, 2}, {2, 0}}), -4.0);
  EXPECT_TRUE(segments_cross({0, 0}, {2, 2}, {0, 2}, {2, 0}));
  EXPECT_FALSE(segments_cross({0, 0}, {2, 2}, {2, 2}, {3, 0}));  // touching ends
  EXPECT_FALSE(segments_cross({0, 0}, {2, 0}, {1, 0}, {3, 0}));  // collinear overlap
  EXPECT_FALSE(segments_cross({0, 0}, {1, 1}, {0, 2}, {2, 0}));  // would meet past an end
  EXPECT_TRUE(inside_polygon(square, {1, 1}));
  EXPECT_FALSE(inside_polygon(square, {3, 1}));
  EXPECT_FALSE(
      inside_polygon({{0, 0}, {4, 0}, {4, 4}, {3, 4}, {3, 1}, {1, 1}, {1, 4}, {0, 4}}, {2, 3}));  // in the U's slot
}

TEST(ConvexHull, FewOrCollinearPoints) {
  EXPECT_EQ(convex_hull({{1, 0}, {0, 0}}), (std::vector<Vec2>{{0, 0}, {1, 0}}));
  EXPECT_EQ(convex_hull({{2, 2}, {0, 0}, {1, 1}}), (std::vector<Vec2>{{0, 0}, {2, 2}}));
}

}  // namespace
}  // namespace developable
