// orientation.h: faces turned so that neighbours agree. Closed-form cases: a
// consistently wound mesh comes back untouched; faces flipped at random come
// back turned, exactly those (or, past half of a component, exactly the
// others); a Möbius strip gets one cut straight across, which opening makes an
// orientable disc.
#include "core/orientation.h"
#include "core/mesh_input.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <algorithm>
#include <map>
#include <numeric>
#include <random>
#include <set>

namespace developable {
namespace {

// A Möbius strip: `around` columns of cells round a circle of radius R,
// `across` cells over the width w, half a turn of the ruling over the round
// (x = (R + s cos(t/2)) cos t, (R + s cos(t/2)) sin t, s sin(t/2)). Every
// cell (a, b, d), (a, d, c) as the grid winds them; the last column joins the
// first upside down, so the `across` edges of column 0 are the ones whose
// faces run them the same way. `jitter` (a fraction of a cell) moves the
// vertices along the surface and `diagonals` picks each cell's diagonal at
// random, for an irregular triangulation.
test::Mesh moebius(int across, int around, double radius, double width, double jitter = 0.0, bool diagonals = false,
                   unsigned seed = 1) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  test::Mesh m;
  const int rows = across + 1;
  m.positions.resize(rows * around, 3);
  for (int j = 0; j < around; ++j)
    for (int i = 0; i < rows; ++i) {
      const bool rim = i == 0 || i == across;
      const double t = 2.0 * M_PI * (j + u(random)) / around;
      const double s = width * ((i + (rim ? 0.0 : u(random))) / across - 0.5);
      const double r = radius + s * std::cos(t / 2);
      m.positions.row(j * rows + i) << r * std::cos(t), r * std::sin(t), s * std::sin(t / 2);
    }
  m.triangles.resize(2 * across * around, 3);
  std::bernoulli_distribution coin(0.5);
  int f = 0;
  for (int j = 0; j < around; ++j)
    for (int i = 0; i < across; ++i) {
      const bool last = j + 1 == around;
      const int a = j * rows + i, c = j * rows + i + 1;
      const int b = last ? across - i : (j + 1) * rows + i, d = last ? across - i - 1 : (j + 1) * rows + i + 1;
      if (diagonals && coin(random)) {
        m.triangles.row(f++) << a, b, c;
        m.triangles.row(f++) << b, d, c;
      } else {
        m.triangles.row(f++) << a, b, d;
        m.triangles.row(f++) << a, d, c;
      }
    }
  return m;
}

// A Klein bottle (closed, one-sided): `rows` x `cols` vertices of the
// figure-8 immersion, the last column joined to the first upside down; each
// cell's diagonal at random.
test::Mesh klein_bottle(int rows, int cols, unsigned seed) {
  std::mt19937 random(seed);
  std::bernoulli_distribution coin(0.5);
  test::Mesh m;
  m.positions.resize(rows * cols, 3);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) {
      const double t = 2 * M_PI * j / cols, u = 2 * M_PI * i / rows;
      const double r = 2.0 + std::cos(t / 2) * std::sin(u) - std::sin(t / 2) * std::sin(2 * u);
      m.positions.row(j * rows + i) << r * std::cos(t), r * std::sin(t),
          std::sin(t / 2) * std::sin(u) + std::cos(t / 2) * std::sin(2 * u);
    }
  m.triangles.resize(2 * rows * cols, 3);
  int f = 0;
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) {
      const bool last = j + 1 == cols;
      const int a = j * rows + i, c = j * rows + (i + 1) % rows;
      const int b = last ? (rows - i) % rows : (j + 1) * rows + i;
      const int d = last ? (2 * rows - i - 1) % rows : (j + 1) * rows + (i + 1) % rows;
      if (coin(random)) {
        m.triangles.row(f++) << a, b, c;
        m.triangles.row(f++) << b, d, c;
      } else {
        m.triangles.row(f++) << a, b, d;
        m.triangles.row(f++) << a, d, c;
      }
    }
  return m;
}

// The edges of two faces that both run them the same way, as (from, to).
std::set<std::pair<int, int>> run_twice(const Triangles& t) {
  std::map<std::pair<int, int>, int> runs;
  for (Eigen::Index f = 0; f < t.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++runs[{t(f, k), t(f, (k + 1) % 3)}];
  std::set<std::pair<int, int>> out;
  for (const auto& [edge, count] : runs)
    if (count == 2) out.insert(edge);
  return out;
}

// orientation's cut is exactly the edges its faces run twice, and opening
// the mesh along it leaves every edge agreeing.
void expect_exact_cut(const Positions& p, const FaceOrientation& o) {
  std::set<std::pair<int, int>> cut;
  for (const auto& e : o.cut) cut.insert({e[0], e[1]});
  EXPECT_EQ(cut, run_twice(o.triangles));
  const OpenedMesh opened = open_along_cut(p, o);
  EXPECT_TRUE(run_twice(opened.triangles).empty());
  EXPECT_EQ(orient_faces(opened.positions, opened.triangles).orientability, Orientability::consistent);
}

// The faces `flip` turned over, (a, b, c) -> (a, c, b).
Triangles flipped(Triangles t, const std::vector<bool>& flip) {
  for (Eigen::Index f = 0; f < t.rows(); ++f)
    if (flip[static_cast<size_t>(f)]) std::swap(t(f, 1), t(f, 2));
  return t;
}

// Every directed edge once at most: each edge of two faces agrees.
bool consistent(const Triangles& t) {
  std::set<std::pair<int, int>> seen;
  for (Eigen::Index f = 0; f < t.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (!seen.insert({t(f, k), t(f, (k + 1) % 3)}).second) return false;
  return true;
}

// `share` of the faces (rounded down), picked at random.
std::vector<bool> random_faces(Eigen::Index count, double share, unsigned seed) {
  std::vector<int> order(static_cast<size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  std::vector<bool> out(static_cast<size_t>(count), false);
  for (size_t i = 0; i < static_cast<size_t>(share * static_cast<double>(count)); ++i)
    out[static_cast<size_t>(order[i])] = true;
  return out;
}

TEST(Orientation, ConsistentMeshesComeBackUntouched) {
  for (const auto& m : {test::plane(), test::cylinder(), test::cone(), test::cube()}) {
    const FaceOrientation o = orient_faces(m.positions, m.triangles);
    EXPECT_EQ(o.orientability, Orientability::consistent);
    EXPECT_EQ(o.turned_count, 0);
    EXPECT_TRUE(o.cut.empty());
    EXPECT_EQ(o.triangles, m.triangles);
  }
}

TEST(Orientation, FlippedFacesAreTurnedBackExactly) {
  for (const auto& m : {test::plane(8, 9), test::cylinder(), test::cube()})
    for (unsigned seed : {1u, 2u, 3u}) {
      // Under half flipped: turned back, exactly those, to the twin.
      const std::vector<bool> flip = random_faces(m.triangles.rows(), 0.3, seed);
      const FaceOrientation o = orient_faces(m.positions, flipped(m.triangles, flip));
      EXPECT_EQ(o.orientability, Orientability::inconsistent);
      EXPECT_EQ(o.turned, flip);
      EXPECT_EQ(o.triangles, m.triangles);
      EXPECT_TRUE(o.cut.empty());
      // Over half flipped: the others are turned, to the flipped twin.
      const std::vector<bool> most = random_faces(m.triangles.rows(), 0.7, seed);
      const FaceOrientation other = orient_faces(m.positions, flipped(m.triangles, most));
      std::vector<bool> rest(most.size());
      for (size_t f = 0; f < most.size(); ++f) rest[f] = !most[f];
      EXPECT_EQ(other.turned, rest);
      EXPECT_EQ(other.triangles, flipped(m.triangles, std::vector<bool>(most.size(), true)));
    }
}

TEST(Orientation, EachComponentOnItsOwn) {
  // Two planes side by side: all of the first flipped, a third of the second.
  const test::Mesh one = test::plane(6, 7);
  const Eigen::Index n = one.positions.rows(), nf = one.triangles.rows();
  Positions p(2 * n, 3);
  p << one.positions, one.positions.rowwise() + Eigen::RowVector3d(3, 0, 0);
  Triangles t(2 * nf, 3);
  t << one.triangles, one.triangles.array() + static_cast<int>(n);
  std::vector<bool> flip = random_faces(2 * nf, 0.33, 7);
  for (Eigen::Index f = 0; f < nf; ++f) flip[static_cast<size_t>(f)] = true;
  const FaceOrientation o = orient_faces(p, flipped(t, flip));
  for (Eigen::Index f = 0; f < 2 * nf; ++f)
    EXPECT_EQ(o.turned[static_cast<size_t>(f)], f >= nf && flip[static_cast<size_t>(f)]) << f;
  EXPECT_TRUE(consistent(o.triangles));
  // A tie keeps the component's first face: half of a two-face square.
  Positions square(4, 3);
  square << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  Triangles two(2, 3);
  two << 0, 1, 2, 0, 3, 2;
  EXPECT_EQ(orient_faces(square, two).turned, (std::vector<bool>{false, true}));
}

TEST(Orientation, MoebiusStripGetsOneCutAcross) {
  const double width = 0.3;
  for (bool irregular : {false, true}) {
    const test::Mesh m = moebius(6, 60, 1.0, width, irregular ? 0.25 : 0.0, irregular, 5);
    ASSERT_NO_THROW(validate_mesh(m.positions, m.triangles));
    const FaceOrientation o = orient_faces(m.positions, m.triangles);
    EXPECT_EQ(o.orientability, Orientability::non_orientable);
    EXPECT_EQ(o.non_orientable_components, 1);
    // Every edge agrees but the cut's, whose two faces both run it from -> to.
    std::map<std::pair<int, int>, int> runs;
    for (Eigen::Index f = 0; f < o.triangles.rows(); ++f)
      for (int k = 0; k < 3; ++k) ++runs[{o.triangles(f, k), o.triangles(f, (k + 1) % 3)}];
    int twice = 0;
    for (const auto& [edge, count] : runs) twice += count == 2;
    EXPECT_EQ(twice, static_cast<int>(o.cut.size()));
    for (const auto& e : o.cut) EXPECT_EQ((runs[{e[0], e[1]}]), 2);
    // One chain from rim to rim, no longer than the shortest column of
    // rungs (each column is a cut), on the grid exactly the width.
    const OpenedMesh opened = open_along_cut(m.positions, o);
    const std::vector<CutChain> chains = cut_chains(m.positions, o, opened);
    ASSERT_EQ(chains.size(), 1u);
    EXPECT_EQ(chains[0].edges.size(), o.cut.size());
    EXPECT_NEAR(chains[0].length, o.cut_length, 1e-12);
    double column = std::numeric_limits<double>::infinity();
    for (int j = 0; j < 60; ++j) {
      double sum = 0.0;
      for (int i = 0; i < 6; ++i) sum += (m.positions.row(7 * j + i + 1) - m.positions.row(7 * j + i)).norm();
      column = std::min(column, sum);
    }
    EXPECT_LE(o.cut_length, column * (1 + 1e-12)) << o.cut.size() << " edges";
    EXPECT_GE(o.cut_length, (irregular ? 0.9 : 1.0 - 1e-12) * width);
    if (!irregular) {
      EXPECT_NEAR(o.cut_length, width, 1e-12);
      EXPECT_EQ(o.cut.size(), 6u);
    }
    const std::vector<bool> rim = boundary_vertices(m.positions, m.triangles);
    EXPECT_TRUE(rim[chains[0].edges.front()[0]]);
    EXPECT_TRUE(rim[chains[0].edges.back()[1]]);
    for (size_t i = 0; i < chains[0].edges.size(); ++i) {
      if (i > 0) {
        EXPECT_EQ(chains[0].edges[i][0], chains[0].edges[i - 1][1]);
      }
      for (int face : chains[0].faces[i]) {  // both run the edge from -> to
        bool runs_it = false;
        for (int k = 0; k < 3; ++k)
          runs_it |=
              o.triangles(face, k) == chains[0].edges[i][0] && o.triangles(face, (k + 1) % 3) == chains[0].edges[i][1];
        EXPECT_TRUE(runs_it);
      }
    }
  }
}

TEST(Orientation, OpeningTheStripMakesAnOrientableDisc) {
  const test::Mesh m = moebius(5, 40, 1.0, 0.4, 0.2, true, 9);
  const FaceOrientation o = orient_faces(m.positions, m.triangles);
  const OpenedMesh opened = open_along_cut(m.positions, o);
  ASSERT_NO_THROW(validate_mesh(opened.positions, opened.triangles));
  EXPECT_TRUE(consistent(opened.triangles));
  EXPECT_EQ(orient_faces(opened.positions, opened.triangles).orientability, Orientability::consistent);
  // A disc: V - E + F = 1; the cut's vertices (its edges + 1) are doubled.
  const Eigen::Index added = opened.positions.rows() - m.positions.rows();
  EXPECT_EQ(added, static_cast<Eigen::Index>(o.cut.size()) + 1);
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < opened.triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = opened.triangles(f, k), b = opened.triangles(f, (k + 1) % 3);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  EXPECT_EQ(opened.positions.rows() - static_cast<Eigen::Index>(edges.size()) + opened.triangles.rows(), 1);
  for (Eigen::Index v = 0; v < opened.positions.rows(); ++v) {
    const int original = opened.original[static_cast<size_t>(v)];
    EXPECT_EQ(opened.positions.row(v), m.positions.row(original));
    if (v < m.positions.rows()) {
      EXPECT_EQ(original, v);
    }
  }
  for (Eigen::Index f = 0; f < o.triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(opened.original[opened.triangles(f, k)], o.triangles(f, k));
  // Without a cut the mesh is the one orientation runs.
  const test::Mesh plane = test::plane();
  const FaceOrientation none = orient_faces(plane.positions, plane.triangles);
  EXPECT_EQ(open_along_cut(plane.positions, none).triangles, plane.triangles);
  EXPECT_TRUE(cut_chains(plane.positions, none, open_along_cut(plane.positions, none)).empty());
}

TEST(Orientation, KleinBottleGetsOneClosedCut) {
  // No rim: the cut is a loop, the tree's shortened face by face; the
  // shortest loop once round is a column (the one-sided way round).
  const int rows = 16, cols = 24;
  const test::Mesh m = klein_bottle(rows, cols, 3);
  ASSERT_NO_THROW(validate_mesh(m.positions, m.triangles));
  const FaceOrientation o = orient_faces(m.positions, m.triangles);
  EXPECT_EQ(o.orientability, Orientability::non_orientable);
  expect_exact_cut(m.positions, o);
  const std::vector<CutChain> chains = cut_chains(m.positions, o, open_along_cut(m.positions, o));
  ASSERT_EQ(chains.size(), 1u);
  EXPECT_EQ(chains[0].edges.back()[1], chains[0].edges.front()[0]);  // closed
  double column = std::numeric_limits<double>::infinity();
  for (int j = 0; j < cols; ++j) {
    double sum = 0.0;
    for (int i = 0; i < rows; ++i)
      sum += (m.positions.row(j * rows + i) - m.positions.row(j * rows + (i + 1) % rows)).norm();
    column = std::min(column, sum);
  }
  EXPECT_GE(o.cut_length, column * (1 - 1e-12));
  EXPECT_LE(o.cut_length, 1.5 * column);  // measured 1.45 (1.9 without the face by face shortening)
}

TEST(Orientation, MoebiusStripWithAHoleStillGetsAnExactCut) {
  // A hole nearly as wide as the strip gives a second rim; a path from one
  // rim to the other across a bridge beside the hole is no cut on its own,
  // and where the shortest crossing path is none the shortened tree's cut
  // stays.
  const test::Mesh strip = moebius(8, 40, 1.0, 0.4, 0.2, true, 2);
  double column = std::numeric_limits<double>::infinity();  // the shortest column of rungs: a cut
  for (int j = 0; j < 40; ++j) {
    double sum = 0.0;
    for (int i = 0; i < 8; ++i) sum += (strip.positions.row(9 * j + i + 1) - strip.positions.row(9 * j + i)).norm();
    column = std::min(column, sum);
  }
  for (int hole : {0, 10, 20, 30}) {
    std::vector<int> kept;
    for (Eigen::Index f = 0; f < strip.triangles.rows(); ++f) {
      const Eigen::Index cell = f / 2, j = cell / 8, i = cell % 8;
      if (!(j >= hole && j < hole + 4 && i >= 1 && i < 7)) kept.push_back(static_cast<int>(f));
    }
    Triangles t(static_cast<Eigen::Index>(kept.size()), 3);
    for (size_t i = 0; i < kept.size(); ++i) t.row(static_cast<Eigen::Index>(i)) = strip.triangles.row(kept[i]);
    ASSERT_NO_THROW(validate_mesh(strip.positions, t));
    const FaceOrientation o = orient_faces(strip.positions, flipped(t, random_faces(t.rows(), 0.4, 1)));
    EXPECT_EQ(o.orientability, Orientability::non_orientable);
    expect_exact_cut(strip.positions, o);
    // Measured up to 1.4; a path to the hole taken for a cut: up to 3.7.
    EXPECT_LE(o.cut_length, 1.5 * column) << "hole at column " << hole;
  }
}

TEST(Orientation, CallerWindingRestored) {
  Normals normals(3, 3);
  normals << 0, 0, 1, 0, 1, 0, 1, 0, 0;
  to_caller_normals(normals, {false, true, false});
  EXPECT_EQ(normals.row(1), Eigen::RowVector3d(0, -1, 0));
  EXPECT_EQ(normals.row(0), Eigen::RowVector3d(0, 0, 1));
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> corners(6, 2);
  corners << 0, 0, 1, 0, 0, 1, 5, 5, 6, 5, 5, 6;
  const auto back = to_caller_corners(corners, {false, true});
  EXPECT_EQ(back.topRows(3), corners.topRows(3));
  EXPECT_EQ(back.row(3), corners.row(3));
  EXPECT_EQ(back.row(4), corners.row(5));
  EXPECT_EQ(back.row(5), corners.row(4));
}

TEST(Orientation, NoteSaysWhatIsTurned) {
  const test::Mesh plane = test::plane(4, 4);
  EXPECT_EQ(orientation_note(orient_faces(plane.positions, plane.triangles)), "");
  std::vector<bool> one(static_cast<size_t>(plane.triangles.rows()), false), two = one;
  one[3] = two[3] = two[5] = true;
  EXPECT_EQ(orientation_note(orient_faces(plane.positions, flipped(plane.triangles, one))).substr(0, 66),
            "1 of 18 triangles is wound the other way round from the neighbours");
  EXPECT_EQ(orientation_note(orient_faces(plane.positions, flipped(plane.triangles, two))).substr(0, 15),
            "2 of 18 triangl");
  const test::Mesh strip = moebius(6, 60, 1.0, 0.3);
  const std::string note = orientation_note(orient_faces(strip.positions, strip.triangles));
  EXPECT_NE(note.find("one-sided"), std::string::npos) << note;
  EXPECT_NE(note.find("a cut of 6 edges (length 0.3)"), std::string::npos) << note;
}

TEST(Orientation, MeshesTheInputCheckRefusesComeBackAsGiven) {
  const test::Mesh m = test::plane(4, 4);
  Triangles bad = flipped(m.triangles, random_faces(m.triangles.rows(), 0.3, 4));
  bad(0, 0) = 99;
  EXPECT_EQ(orient_faces(m.positions, bad).triangles, bad);
  Positions nan = m.positions;
  nan(3, 1) = std::nan("");
  const Triangles some = flipped(m.triangles, random_faces(m.triangles.rows(), 0.3, 4));
  EXPECT_EQ(orient_faces(nan, some).turned_count, 0);
  // Three faces on one edge join none of them across it; no crash.
  Positions fin(5, 3);
  fin << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1;
  Triangles three(3, 3);
  three << 0, 1, 2, 0, 1, 3, 0, 1, 4;
  EXPECT_EQ(orient_faces(fin, three).orientability, Orientability::consistent);
}

}  // namespace
}  // namespace developable
