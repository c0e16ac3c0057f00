// segmentation.h: deterministic labels, 0 .. k-1 and edge-connected, one
// patch for a developable sheet, a split at a crease.
#include "segmentation/segmentation.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace developable {
namespace {

// A sheet folded along x = 0.5 by `angle` (rad): two planes meeting at a crease.
test::Mesh folded_sheet(double angle) {
  return test::grid(12, 15, false, [=](double u, double v) {
    const double x = v - 0.5;
    if (x <= 0.0) return Eigen::Vector3d(x, u, 0.0);
    return Eigen::Vector3d(x * std::cos(angle), u, x * std::sin(angle));
  });
}

// Every patch edge-connected and the ids exactly 0 .. k-1.
void expect_valid_labels(const test::Mesh& m, const std::vector<int>& label) {
  ASSERT_EQ(label.size(), static_cast<size_t>(m.triangles.rows()));
  const int k = *std::max_element(label.begin(), label.end()) + 1;
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (int f = 0; f < m.triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = m.triangles(f, c), b = m.triangles(f, (c + 1) % 3);
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  std::vector<int> root(label.size());
  for (size_t f = 0; f < root.size(); ++f) root[f] = static_cast<int>(f);
  std::function<int(int)> find = [&](int x) { return root[x] == x ? x : root[x] = find(root[x]); };
  for (const auto& [edge, faces] : edge_faces)
    if (faces.size() == 2 && label[faces[0]] == label[faces[1]]) root[find(faces[0])] = find(faces[1]);
  std::map<int, std::set<int>> components;
  for (size_t f = 0; f < label.size(); ++f) components[label[f]].insert(find(static_cast<int>(f)));
  EXPECT_EQ(static_cast<int>(components.size()), k);
  for (const auto& [patch, roots] : components) EXPECT_EQ(roots.size(), 1u) << "patch " << patch;
}

TEST(Segmentation, SameInputSameLabels) {
  auto m = test::cylinder(20, 40);
  test::add_noise(m.positions, 0.05, 9);
  const auto first = segment_mesh(m.positions, m.triangles, {}, {});
  EXPECT_EQ(segment_mesh(m.positions, m.triangles, {}, {}), first);
  expect_valid_labels(m, first);
}

TEST(Segmentation, DevelopableSheetsStayOnePatch) {
  for (const auto& m : {test::plane(12, 15), test::cylinder(12, 40), test::cone(12, 40)}) {
    const auto label = segment_mesh(m.positions, m.triangles, {}, {});
    EXPECT_EQ(*std::max_element(label.begin(), label.end()), 0);
  }
}

TEST(Segmentation, FoldedSheetSplitsAtTheCrease) {
  for (double degrees : {40.0, 90.0, 150.0}) {
    const auto m = folded_sheet(degrees * M_PI / 180.0);
    const auto label = segment_mesh(m.positions, m.triangles, {}, {});
    expect_valid_labels(m, label);
    std::set<std::pair<bool, int>> side_label;
    for (int f = 0; f < m.triangles.rows(); ++f) {
      const double x =
          (m.positions(m.triangles(f, 0), 0) + m.positions(m.triangles(f, 1), 0) + m.positions(m.triangles(f, 2), 0)) /
          3;
      side_label.insert({x > 0.0, label[f]});
    }
    // Two patches, one per side of the crease.
    EXPECT_EQ(side_label.size(), 2u) << degrees << " degrees";
    EXPECT_EQ(*std::max_element(label.begin(), label.end()), 1) << degrees << " degrees";
  }
}

TEST(Segmentation, TargetPatchCountIsMet) {
  auto m = test::cylinder(20, 40);
  SegmentationOptions options;
  options.target_patches = 4;
  const auto label = segment_mesh(m.positions, m.triangles, options, {});
  EXPECT_EQ(*std::max_element(label.begin(), label.end()) + 1, 4);
  expect_valid_labels(m, label);
}

TEST(Segmentation, Refusals) {
  const auto m = test::plane();
  SegmentationOptions bad;
  bad.max_fit_error = -1.0;
  EXPECT_THROW(segment_mesh(m.positions, m.triangles, bad, {}), EngineError);
  EXPECT_THROW(segment_mesh(m.positions, Triangles(0, 3), {}, {}), EngineError);
}

TEST(Segmentation, CancelIsHonoured) {
  const auto m = test::cylinder(20, 40);
  const Progress stop{[](double, const char*, void*) { return false; }, nullptr};
  try {
    segment_mesh(m.positions, m.triangles, {}, stop);
    ADD_FAILURE() << "not cancelled";
  } catch (const EngineError& e) {
    EXPECT_EQ(e.status(), Status::cancelled);
  }
}

}  // namespace
}  // namespace developable
