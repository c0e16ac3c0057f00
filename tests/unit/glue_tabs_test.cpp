// glue_tabs.h from the promises in its header: trapezoids and triangles on
// straight runs, bisectors at corners, tabs halved or dropped where they
// would cross the piece or each other, bad input.
#include "pattern/glue_tabs.h"

#include "core/types.h"

#include <gtest/gtest.h>

namespace developable {
namespace {

using Vec2 = Eigen::Vector2d;
using Loop = std::vector<Vec2>;

void expect_points(const Loop& got, const Loop& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) EXPECT_LT((got[i] - want[i]).norm(), 1e-12) << i;
}

const Loop kSquare{{0, 0}, {10, 0}, {10, 10}, {0, 10}};

TEST(GlueTabs, TrapezoidOnAnEdgeOutsideThePiece) {
  const TabbedOutline t = add_glue_tabs(kSquare, {{0, 1}}, 2.0);
  EXPECT_EQ(t.tabs, 1);
  EXPECT_EQ(t.dropped, 0);
  expect_points(t.cut_line, {{0, 0}, {2, -2}, {8, -2}, {10, 0}, {10, 10}, {0, 10}});
  ASSERT_EQ(t.folds.size(), 1u);
  expect_points(t.folds[0], {{0, 0}, {10, 0}});
  // The other orientation: the tab is still outside.
  Loop clockwise(kSquare.rbegin(), kSquare.rend());  // (0,10) (10,10) (10,0) (0,0)
  const TabbedOutline c = add_glue_tabs(clockwise, {{2, 1}}, 2.0);
  expect_points(c.cut_line, {{0, 10}, {10, 10}, {10, 0}, {8, -2}, {2, -2}, {0, 0}});
}

TEST(GlueTabs, ShortRunGetsATriangleAndACornerTheBisector) {
  const TabbedOutline t = add_glue_tabs({{0, 0}, {3, 0}, {3, 3}, {0, 3}}, {{0, 1}}, 2.0);
  expect_points(t.cut_line, {{0, 0}, {1.5, -1.5}, {3, 0}, {3, 3}, {0, 3}});
  // Round the corner (10, 0): along its bisector, 2 out.
  const TabbedOutline c = add_glue_tabs(kSquare, {{0, 2}}, 2.0);
  EXPECT_EQ(c.tabs, 1);
  const Vec2 corner = Vec2(10, 0) + 2.0 * Vec2(1, -1).normalized();
  bool found = false;
  for (const Vec2& p : c.cut_line) found = found || (p - corner).norm() < 1e-12;
  EXPECT_TRUE(found);
  EXPECT_EQ(c.cut_line.size(), 3u + 3u);  // 3 corners kept, 3 top points between the run's ends
}

// A U whose slot (x from 5 to 9, from y = 6 up) is 4 wide.
const Loop kU{{0, 0}, {14, 0}, {14, 20}, {9, 20}, {9, 6}, {5, 6}, {5, 20}, {0, 20}};

TEST(GlueTabs, TabThatWouldCrossThePieceIsHalvedOrDropped) {
  // On the slot's right wall (edge 3, from (9, 20) down to (9, 6)): 6 high
  // it would cross the left wall, 3 high it fits.
  const TabbedOutline halved = add_glue_tabs(kU, {{3, 1}}, 6.0);
  EXPECT_EQ(halved.tabs, 1);
  double reach = 9.0;  // how far into the slot
  for (const Vec2& p : halved.cut_line)
    if (p.x() > 5.0 && p.y() > 6.0 && p.y() < 20.0) reach = std::min(reach, p.x());
  EXPECT_DOUBLE_EQ(reach, 6.0);
  const TabbedOutline dropped = add_glue_tabs(kU, {{3, 1}}, 12.0);
  EXPECT_EQ(dropped.tabs, 0);
  EXPECT_EQ(dropped.dropped, 1);
  expect_points(dropped.cut_line, kU);
  EXPECT_TRUE(dropped.folds.empty());
}

TEST(GlueTabs, TabsDoNotCrossEachOther) {
  // Both walls of the slot, 2.5 high, the first run given first: the right
  // wall's (edge 3) reaches x = 6.5; the left wall's (edge 5, from (5, 6)
  // up) would reach 7.5, across it, so it is halved to x = 6.25. Given the
  // other way round, the left wall's keeps 7.5 and the right wall's is
  // halved to 7.75. At 3 the halved one still crosses (6.5 against 6):
  // dropped.
  const auto reaches = [](const TabbedOutline& t, double x) {
    bool found = false;
    for (const Vec2& p : t.cut_line) found = found || (std::abs(p.x() - x) < 1e-12 && p.y() > 6.0 && p.y() < 20.0);
    return found;
  };
  const TabbedOutline t = add_glue_tabs(kU, {{3, 1}, {5, 1}}, 2.5);
  EXPECT_EQ(t.tabs, 2);
  EXPECT_EQ(t.tabbed, std::vector<bool>({true, true}));
  EXPECT_TRUE(reaches(t, 6.5));   // the right wall's tab, 2.5 high
  EXPECT_TRUE(reaches(t, 6.25));  // the left wall's, halved
  EXPECT_FALSE(reaches(t, 7.5));  // not at full height
  const TabbedOutline swapped = add_glue_tabs(kU, {{5, 1}, {3, 1}}, 2.5);
  EXPECT_TRUE(reaches(swapped, 7.5));
  EXPECT_TRUE(reaches(swapped, 7.75));
  EXPECT_FALSE(reaches(swapped, 6.5));
  const TabbedOutline crowded = add_glue_tabs(kU, {{3, 1}, {5, 1}}, 3.0);
  EXPECT_EQ(crowded.tabs, 1);
  EXPECT_EQ(crowded.dropped, 1);
  EXPECT_EQ(crowded.tabbed, std::vector<bool>({true, false}));
  ASSERT_EQ(crowded.folds.size(), 1u);
  expect_points(crowded.folds[0], {{9, 20}, {9, 6}});
}

TEST(GlueTabs, ZeroLengthEdgeInARunChangesNothing) {
  // A repeated corner (a zero-length edge has no outward side of its own):
  // the same trapezoid as without it.
  const Loop repeated{{0, 0}, {5, 0}, {5, 0}, {10, 0}, {10, 10}, {0, 10}};
  const TabbedOutline t = add_glue_tabs(repeated, {{0, 3}}, 2.0);
  EXPECT_EQ(t.tabs, 1);
  expect_points(t.cut_line, {{0, 0}, {2, -2}, {5, -2}, {8, -2}, {10, 0}, {10, 10}, {0, 10}});
}

TEST(GlueTabs, BadInputIsAnInvalidArgument) {
  const auto status = [](const Loop& loop, std::vector<TabRun> runs, double h) {
    try {
      add_glue_tabs(loop, std::move(runs), h);
    } catch (const EngineError& e) {
      return e.status();
    }
    return Status::ok;
  };
  EXPECT_EQ(status(kSquare, {{0, 1}}, 0.0), Status::invalid_argument);
  EXPECT_EQ(status(kSquare, {{0, 1}}, NAN), Status::invalid_argument);
  EXPECT_EQ(status({{0, 0}, {1, 0}}, {{0, 1}}, 1.0), Status::invalid_argument);
  EXPECT_EQ(status(kSquare, {{4, 1}}, 1.0), Status::invalid_argument);
  EXPECT_EQ(status(kSquare, {{0, 0}}, 1.0), Status::invalid_argument);
  EXPECT_EQ(status(kSquare, {{0, 2}, {1, 1}}, 1.0), Status::invalid_argument);
  EXPECT_EQ(status(kSquare, {{3, 2}, {0, 1}}, 1.0), Status::invalid_argument);  // 3, 0 and 0
  EXPECT_EQ(status(kSquare, {}, 1.0), Status::ok);
}

}  // namespace
}  // namespace developable
