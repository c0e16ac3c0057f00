// crease_lines.h: a noisy fold is cut along its line and nowhere else; a
// noisy plane or cylinder is not cut; a noisy mitred pipe is cut all around
// its mitre, across the sides where its crease fades into the noise (the
// gaps bridged), and under loud noise too (its line grown over weak
// candidates); boundary edges are never cut.
#include "segmentation/crease_lines.h"

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "core/union_find.h"
#include "crease_meshes.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>

namespace developable {
namespace {

struct Lines {
  std::vector<MeshEdge> edges;
  std::vector<bool> cut;
  CreaseStrengths strengths;
};

Lines lines_of(const test::Mesh& m) {
  const VertexFaces connectivity = vertex_faces(m.triangles, m.positions.rows());
  const Normals normals = face_normals(m.positions, m.triangles);
  Lines l;
  l.edges = mesh_edges(m.triangles, connectivity);
  l.strengths = crease_strengths(m.positions, m.triangles, normals, connectivity, l.edges);
  l.cut = crease_lines(m.positions, m.triangles, normals, connectivity, l.edges, l.strengths);
  return l;
}

// The faces' pieces across the edges not cut, by root face.
std::vector<int> pieces_of(const test::Mesh& m, const Lines& l) {
  UnionFind pieces(static_cast<size_t>(m.triangles.rows()));
  for (size_t e = 0; e < l.edges.size(); ++e)
    if (l.edges[e].g >= 0 && !l.cut[e]) pieces.unite(l.edges[e].f, l.edges[e].g);
  std::vector<int> roots;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) roots.push_back(pieces.find(static_cast<int>(f)));
  return roots;
}

int cut_count(const Lines& l) {
  int n = 0;
  for (bool c : l.cut) n += c;
  return n;
}

TEST(CreaseLines, ANoisyFoldIsCutAlongItsLineAndNowhereElse) {
  const int rows = 21, cols = 21, fold = (rows - 1) / 2;
  for (unsigned seed : {1u, 2u, 3u}) {
    test::Mesh m = test::folded_plane(rows, cols, 0.3);
    test::add_noise(m.positions, 0.03 / (cols - 1), seed);
    const Lines l = lines_of(m);
    for (size_t e = 0; e < l.edges.size(); ++e) {
      const bool on_fold = l.edges[e].a / cols == fold && l.edges[e].b / cols == fold;
      EXPECT_EQ(l.cut[e], on_fold) << "seed " << seed << ", edge " << l.edges[e].a << "-" << l.edges[e].b;
    }
    EXPECT_EQ(cut_count(l), cols - 1);
  }
}

TEST(CreaseLines, NoCutWithoutACrease) {
  test::Mesh plane = test::plane(25, 25);
  test::add_noise(plane.positions, 0.05 / 24, 4);
  EXPECT_EQ(cut_count(lines_of(plane)), 0);
  // A cylinder's rulings are creases of the facet angle, all alike.
  test::Mesh cylinder = test::cylinder(21, 32, 1.0);
  test::add_noise(cylinder.positions, 0.03 * 2.0 * M_PI / 32, 4);
  EXPECT_EQ(cut_count(lines_of(cylinder)), 0);
  EXPECT_EQ(cut_count(lines_of(test::cylinder(21, 32, 1.0))), 0);
}

TEST(CreaseLines, AMitredPipeIsCutAllAroundItsMitre) {
  // A 30 degree mitre: its dihedral angle falls from 30 degrees at the
  // inside and outside of the bend to 0 at the sides, under the noise.
  for (unsigned seed : {1u, 2u, 3u}) {
    const double turn = 30.0 * M_PI / 180.0;
    const int cols = 48;
    test::Mesh m = test::mitred_pipe(33, cols, turn);
    test::add_noise(m.positions, 0.02 * 2.0 * M_PI / cols, seed);
    const Lines l = lines_of(m);
    // Two pieces, each (but for faces along the mitre where the cut runs a
    // row off at the sides, where the cylinders are tangent) one cylinder.
    const std::vector<int> roots = pieces_of(m, l);
    std::map<int, std::pair<int, int>> sides;  // root -> faces below, above the mitre
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
      auto& [below, above] = sides[roots[static_cast<size_t>(f)]];
      ++(test::below_mitre(m, f, turn) ? below : above);
    }
    ASSERT_EQ(sides.size(), 2u) << "seed " << seed;
    int mixed = 0;
    for (const auto& [root, counts] : sides) mixed += std::min(counts.first, counts.second);
    EXPECT_LT(mixed, 0.01 * m.triangles.rows()) << "seed " << seed;
    for (size_t e = 0; e < l.edges.size(); ++e) {
      if (l.edges[e].g < 0) {
        EXPECT_FALSE(l.cut[e]);
      }
    }
  }
}

TEST(CreaseLines, UnderLoudNoiseAMitresLineIsGrownAllAround) {
  // At 4 % noise the 30 degree mitre's edges score 2-5: the strong candidates
  // are stretches a few edges long, too weak alone to be lines. Grown from
  // their ends over the weak candidates, they meet (without the growth 2 of
  // these 8 seeds were cut in two).
  const double turn = 30.0 * M_PI / 180.0;
  const int cols = 48;
  int halved = 0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    test::Mesh m = test::mitred_pipe(33, cols, turn);
    test::add_noise(m.positions, 0.04 * 2.0 * M_PI / cols, seed);
    const std::vector<int> roots = pieces_of(m, lines_of(m));
    halved += std::set<int>(roots.begin(), roots.end()).size() == 2;
  }
  EXPECT_GE(halved, 6);
}

}  // namespace
}  // namespace developable
