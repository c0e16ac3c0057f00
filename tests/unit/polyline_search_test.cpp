// polyline_search.h: the chart search is exact (against a scan of every
// segment) whatever the warm start, and extends open ends.
#include "ideal_curve/polyline_search.h"

#include <gtest/gtest.h>

#include <random>

namespace developable {
namespace {

TEST(PolylineSearch, ExactAgainstAScanOfEverySegment) {
  std::mt19937 random(3);
  std::normal_distribution<double> g(0.0, 0.1);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<ChartPolyline> lines(1 + trial % 3);
    for (auto& line : lines) {
      Eigen::Vector2d p(u(random), u(random));
      const int n = 2 + static_cast<int>(random() % 100);
      for (int i = 0; i < n; ++i) {
        line.points.push_back(p);
        line.params.push_back(double(i) / (n - 1));
        p += Eigen::Vector2d(g(random), g(random));
      }
      line.closed = random() % 2 == 0;
    }
    const ChartPolylineSearch search(lines);
    for (int i = 0; i < 300; ++i) {
      const Eigen::Vector2d q(u(random), u(random));
      double best = INFINITY;
      for (const auto& line : lines) {
        const size_t n = line.points.size(), segs = line.closed ? n : n - 1;
        for (size_t s = 0; s < segs; ++s) {
          const Eigen::Vector2d a = line.points[s], b = line.points[(s + 1) % n];
          const double f = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
          best = std::min(best, (a + f * (b - a) - q).squaredNorm());
        }
      }
      int warm = static_cast<int>(random() % 50) - 5;
      const auto hit = search.nearest(q, warm);
      EXPECT_NEAR(hit.dist2, best, 1e-14) << "trial " << trial;
      EXPECT_GE(hit.curve, 0);
    }
  }
}

TEST(PolylineSearch, OpenEndsExtendTheParameter) {
  const std::vector<ChartPolyline> lines{{{Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0)}, {0.0, 1.0}, false}};
  const ChartPolylineSearch search(lines);
  int warm = 0;
  EXPECT_NEAR(search.nearest(Eigen::Vector2d(1.5, 0.2), warm).param, 1.5, 1e-15);
  EXPECT_NEAR(search.nearest(Eigen::Vector2d(-0.25, 0.0), warm).param, -0.25, 1e-15);
  EXPECT_NEAR(search.nearest(Eigen::Vector2d(0.3, 2.0), warm).param, 0.3, 1e-15);
  EXPECT_EQ(ChartPolylineSearch({}).nearest(Eigen::Vector2d(0, 0), warm).curve, -1);
}

}  // namespace
}  // namespace developable
