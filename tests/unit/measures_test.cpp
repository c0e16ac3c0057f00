// Stage 2, measures.h: normals, areas, AE, angle defects on meshes whose
// values are known in closed form.
#include "core/measures.h"
#include "core/mesh_input.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <random>

namespace developable {
namespace {

// A vertex dragged across its neighbours turns its faces over; putting back
// the folded faces' corners, ring by ring, restores the plane, and with no
// round allowed it reports faces still folded.
TEST(Measures, PutBackFoldedCornersUnfoldsAPlane) {
  const auto m = test::plane(7, 9);
  const Normals reference = face_normals(m.positions, m.triangles);
  const CreaseGuard off(m.triangles, reference, {}, 0.0);
  Positions dragged = m.positions;
  const Eigen::Index v = 4 * 9 + 4;                     // an interior vertex
  dragged.row(v) += Eigen::RowVector3d(1.7, 1.3, 0.0);  // several cells across
  ASSERT_FALSE(turned_over_faces(face_normals(dragged, m.triangles), reference).empty());
  Positions none = dragged;
  EXPECT_FALSE(put_back_folded_corners(none, m.positions, m.triangles, reference, off, 0));
  EXPECT_TRUE(none == dragged);
  Positions fixed = dragged;
  EXPECT_TRUE(put_back_folded_corners(fixed, m.positions, m.triangles, reference, off, 10));
  EXPECT_TRUE(turned_over_faces(face_normals(fixed, m.triangles), reference).empty());
  EXPECT_TRUE(fixed.row(v) == m.positions.row(v));
}

TEST(Measures, FlatGridHasZeroDefectEverywhere) {
  const auto m = test::plane(7, 9);
  const auto interior = interior_vertices(m.positions, m.triangles);
  const Eigen::VectorXd defect = angle_defects(m.positions, m.triangles, interior);
  int interior_count = 0;
  for (Eigen::Index v = 0; v < defect.size(); ++v) {
    EXPECT_NEAR(defect[v], 0.0, 1e-12) << "vertex " << v;
    interior_count += interior[v];
  }
  EXPECT_EQ(interior_count, 5 * 7);  // the grid's inner vertices
}

TEST(Measures, CubeCornerDefectIsHalfPi) {
  const auto m = test::cube();
  const auto interior = interior_vertices(m.positions, m.triangles);
  const Eigen::VectorXd defect = angle_defects(m.positions, m.triangles, interior);
  for (Eigen::Index v = 0; v < 8; ++v) {
    EXPECT_TRUE(interior[v]);
    EXPECT_NEAR(defect[v], M_PI / 2, 1e-12) << "vertex " << v;
  }
}

TEST(Measures, GaussBonnetOnClosedMeshes) {
  // The defects of a closed genus-0 surface sum to 2 pi chi = 4 pi, whatever
  // the shape: the cube and a randomly perturbed cube.
  for (unsigned seed = 0; seed < 5; ++seed) {
    auto m = test::cube();
    if (seed > 0) test::add_noise(m.positions, 0.2, seed);
    const auto interior = interior_vertices(m.positions, m.triangles);
    EXPECT_NEAR(angle_defects(m.positions, m.triangles, interior).sum(), 4 * M_PI, 1e-10) << "seed " << seed;
  }
}

TEST(Measures, BoundaryVerticesGetZeroDefect) {
  auto m = test::cone();
  const auto interior = interior_vertices(m.positions, m.triangles);
  const Eigen::VectorXd defect = angle_defects(m.positions, m.triangles, interior);
  const auto boundary = boundary_vertices(m.positions, m.triangles);
  for (Eigen::Index v = 0; v < defect.size(); ++v) {
    EXPECT_NE(interior[v], boundary[v]);
    if (!interior[v]) {
      EXPECT_EQ(defect[v], 0.0);
    }
  }
}

TEST(Measures, NormalsAreasAndEdgeLengthOfThePlane) {
  const auto m = test::plane(3, 3);  // 2 x 2 cells of 0.5 x 0.5
  const Normals n = face_normals(m.positions, m.triangles);
  const Eigen::VectorXd a = face_areas(m.positions, m.triangles);
  for (Eigen::Index f = 0; f < n.rows(); ++f) {
    EXPECT_NEAR((n.row(f) - Eigen::RowVector3d(0, 0, 1)).norm(), 0.0, 1e-15);
    EXPECT_NEAR(a[f], 0.125, 1e-15);
  }
  // 12 axis edges of 0.5 and 4 diagonals of 0.5 sqrt 2
  EXPECT_NEAR(average_edge_length(m.positions, m.triangles), (12 * 0.5 + 4 * 0.5 * std::sqrt(2.0)) / 16, 1e-15);
}

TEST(Measures, ZeroAreaTriangleGetsTheZeroNormal) {
  Positions p(3, 3);
  p << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  Triangles t(1, 3);
  t << 0, 1, 2;
  EXPECT_EQ(face_normals(p, t).row(0).norm(), 0.0);
  EXPECT_EQ(face_areas(p, t)[0], 0.0);
}

TEST(Measures, DefectStatsOverInteriorOnly) {
  Eigen::VectorXd d(4);
  d << 0.1, -0.3, 5.0, 0.2;
  const DefectStats s = defect_stats(d, {true, true, false, true});
  EXPECT_EQ(s.interior_count, 3);
  EXPECT_NEAR(s.mean_abs, 0.2, 1e-15);
  EXPECT_EQ(s.max_abs, 0.3);
}

TEST(Measures, TurnedOverFacesAreThoseMoreThan90DegreesOffOrCollapsed) {
  Normals reference(4, 3), normals(4, 3);
  reference << 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0;
  normals << 0, 0.6, 0.8, 0, 0, 0, 0, 0, 0, 0, 0, -1;             // 37 degrees; (below); collapsed; unchecked
  normals.row(1) = Eigen::RowVector3d(0, 1, -0.01).normalized();  // just past 90 degrees
  const std::vector<Eigen::Index> turned = turned_over_faces(normals, reference);
  EXPECT_EQ(turned, (std::vector<Eigen::Index>{1, 2}));
}

// CreaseGuard: a plane bent gently stays unreported; one vertex pushed out
// of it creases the edges of its star; an edge between two groups may fold;
// growth 0 switches the guard off.
TEST(Measures, CreaseGuardReportsTheFacesOfEdgesThatSharpened) {
  const auto m = test::plane(6, 6);
  const Normals flat = face_normals(m.positions, m.triangles);
  const CreaseGuard guard(m.triangles, flat, {}, 20.0 * M_PI / 180.0);
  EXPECT_TRUE(guard.active());
  Positions bent = m.positions;
  for (Eigen::Index v = 0; v < bent.rows(); ++v) bent(v, 2) = 0.1 * bent(v, 0) * bent(v, 0);  // a gentle cylinder
  EXPECT_TRUE(guard.creased_faces(face_normals(bent, m.triangles)).empty());

  const Eigen::Index tip = 2 * 6 + 2;  // an interior vertex
  Positions pushed = m.positions;
  pushed(tip, 2) += 0.5;  // its star becomes a steep cone
  const std::vector<Eigen::Index> creased = guard.creased_faces(face_normals(pushed, m.triangles));
  ASSERT_FALSE(creased.empty());
  EXPECT_TRUE(std::is_sorted(creased.begin(), creased.end()));
  for (Eigen::Index f : creased) {
    bool touches = false;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index v = m.triangles(f, c);
      touches =
          touches || (m.positions.row(v) - m.positions.row(tip)).norm() < 0.3;  // the star and its edge neighbours
    }
    EXPECT_TRUE(touches) << f;
  }

  // Every face its own group: no edge is watched.
  std::vector<int> groups(static_cast<size_t>(m.triangles.rows()));
  for (size_t f = 0; f < groups.size(); ++f) groups[f] = static_cast<int>(f);
  EXPECT_FALSE(CreaseGuard(m.triangles, flat, groups, 0.3).active());
  EXPECT_FALSE(CreaseGuard(m.triangles, flat, {}, 0.0).active());
}

// A guard restricted to some faces is the guard its constructor builds on
// the submesh of those faces: it finds the same creased faces, renumbered.
TEST(Measures, CreaseGuardRestrictedIsTheGuardOfTheSubmesh) {
  const auto m = test::plane(9, 9);
  const Normals reference = face_normals(m.positions, m.triangles);
  std::vector<int> groups(static_cast<size_t>(m.triangles.rows()));
  for (size_t f = 0; f < groups.size(); ++f)
    groups[f] = m.positions(m.triangles(static_cast<Eigen::Index>(f), 0), 0) < 0.5;
  const double growth = 10.0 * M_PI / 180.0;
  const CreaseGuard whole(m.triangles, reference, groups, growth);

  // Every other face of the first 100, and the faces of one corner of the plane.
  std::vector<Eigen::Index> faces;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    if ((f < 100 && f % 2 == 0) || m.positions(m.triangles(f, 0), 1) > 0.6) faces.push_back(f);
  std::vector<int> local_vertex(static_cast<size_t>(m.positions.rows()), -1);
  int vertices = 0;
  Triangles local(static_cast<Eigen::Index>(faces.size()), 3);
  Normals local_reference(local.rows(), 3);
  std::vector<int> local_groups;
  for (Eigen::Index i = 0; i < local.rows(); ++i) {
    const Eigen::Index f = faces[static_cast<size_t>(i)];
    for (int c = 0; c < 3; ++c) {
      int& v = local_vertex[static_cast<size_t>(m.triangles(f, c))];
      if (v < 0) v = vertices++;
      local(i, c) = v;
    }
    local_reference.row(i) = reference.row(f);
    local_groups.push_back(groups[static_cast<size_t>(f)]);
  }
  const CreaseGuard restricted = whole.restricted(faces, m.triangles.rows());
  const CreaseGuard built(local, local_reference, local_groups, growth);

  std::mt19937 random(5);
  std::uniform_real_distribution<double> tilt(-0.3, 0.3);
  Normals noisy = local_reference;
  for (Eigen::Index i = 0; i < noisy.rows(); ++i) noisy.row(i) += Eigen::RowVector3d(tilt(random), tilt(random), 0.0);
  const std::vector<Eigen::Index> creased = built.creased_faces(noisy);
  ASSERT_FALSE(creased.empty());
  ASSERT_LT(creased.size(), faces.size());
  EXPECT_EQ(restricted.creased_faces(noisy), creased);
  EXPECT_FALSE(CreaseGuard().restricted(faces, m.triangles.rows()).active());
}

// The measures that share their faces out to spare cores give, on several
// chunks of faces and any number of cores, what they give on the calling
// thread alone; the turned and creased faces are those a face-by-face look
// finds, ascending; a collapsed face turns no corner.
TEST(Measures, OnSpareCoresTheSameBitForBit) {
  auto m = test::plane(120, 110);  // 26k faces: several chunks
  const Normals flat = face_normals(m.positions, m.triangles);
  const auto interior = interior_vertices(m.positions, m.triangles);
  std::mt19937 random(11);
  std::normal_distribution<double> noise(0.0, 0.4);
  Positions noisy = m.positions;
  for (Eigen::Index v = 0; v < noisy.rows(); ++v) noisy(v, 2) += noise(random) / 120.0;
  noisy.row(m.triangles(500, 1)) = noisy.row(m.triangles(500, 0));           // a collapsed face
  for (Eigen::Index v = 0; v < noisy.rows(); v += 997) noisy(v, 2) += 0.05;  // steep spikes: creases, turned faces
  const CreaseGuard guard(m.triangles, flat, {}, 20.0 * M_PI / 180.0);

  const Normals normals = face_normals(noisy, m.triangles);
  const Eigen::VectorXd defects = angle_defects(noisy, m.triangles, interior);
  const std::vector<Eigen::Index> turned = turned_over_faces(normals, flat);
  const std::vector<Eigen::Index> creased = guard.creased_faces(normals);
  std::vector<Eigen::Index> turned_one_by_one;
  for (Eigen::Index f = 0; f < normals.rows(); ++f)
    if (normals.row(f).dot(flat.row(f)) < 0.0 || normals.row(f).squaredNorm() == 0.0) turned_one_by_one.push_back(f);
  EXPECT_EQ(turned, turned_one_by_one);
  ASSERT_FALSE(turned.empty());
  ASSERT_FALSE(creased.empty());
  EXPECT_TRUE(std::is_sorted(creased.begin(), creased.end()));
  for (int threads : {2, 3, 8}) {
    SpareCores spare(threads);
    EXPECT_TRUE(face_normals(noisy, m.triangles, &spare) == normals) << threads;
    EXPECT_TRUE(angle_defects(noisy, m.triangles, interior, &spare) == defects) << threads;
    EXPECT_EQ(turned_over_faces(normals, flat, &spare), turned) << threads;
    EXPECT_EQ(guard.creased_faces(normals, &spare), creased) << threads;
    EXPECT_EQ(spare.take(8), static_cast<unsigned>(threads - 1)) << "every core given back";
  }
}

// normal_roughness: zero on a plane, the cylinder's own from its curvature,
// raised by noise, the same at any scale.
TEST(Measures, NormalRoughnessIsZeroFlatAndGrowsWithNoise) {
  const auto flat = test::plane();
  const auto flat_table = vertex_faces(flat.triangles, flat.positions.rows());
  EXPECT_NEAR(normal_roughness(face_normals(flat.positions, flat.triangles), flat.triangles, flat_table), 0.0, 1e-12);

  auto m = test::cylinder(10, 30);
  const auto table = vertex_faces(m.triangles, m.positions.rows());
  const double smooth = normal_roughness(face_normals(m.positions, m.triangles), m.triangles, table);
  EXPECT_GT(smooth, 0.0);
  EXPECT_LT(smooth, 2.0 * M_PI / 30);  // below the turn between neighbouring columns
  Positions scaled = 1000.0 * m.positions;
  EXPECT_NEAR(normal_roughness(face_normals(scaled, m.triangles), m.triangles, table), smooth, 1e-12);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> noise(-0.02, 0.02);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v)
    for (int k = 0; k < 3; ++k) m.positions(v, k) += noise(random);
  EXPECT_GT(normal_roughness(face_normals(m.positions, m.triangles), m.triangles, table), 1.5 * smooth);
}

// ruling_spreads: the normals around every vertex of a plane or a cylinder
// lie on one great circle; a cone's trace a small circle, whose short arcs
// stay well under the ruled threshold; normals tilted two ways at once (a
// crumpled zigzag) do not, and vertex_shares counts those as crumpled.
TEST(Measures, RulingSpreadIsZeroWhereTheSurfaceBendsAboutOneAxis) {
  for (const auto& m : {test::plane(), test::cylinder(10, 30)}) {
    const auto table = vertex_faces(m.triangles, m.positions.rows());
    const auto interior = interior_vertices(m.positions, m.triangles);
    EXPECT_LT(
        ruling_spreads(m.positions, m.triangles, face_normals(m.positions, m.triangles), table, interior).maxCoeff(),
        1e-6);
  }
  const auto cone = test::cone(10, 30);
  const auto table = vertex_faces(cone.triangles, cone.positions.rows());
  const Eigen::VectorXd spreads =
      ruling_spreads(cone.positions, cone.triangles, face_normals(cone.positions, cone.triangles), table,
                     interior_vertices(cone.positions, cone.triangles));
  EXPECT_LT(spreads.maxCoeff(), 0.2 * kRuledSpread);

  // The plane's connectivity with its faces' normals tilted by 0.2 rad in
  // random directions (two normals always share a great circle; the six of
  // a star, tilted every way, do not).
  const auto plane = test::plane();
  const auto plane_table = vertex_faces(plane.triangles, plane.positions.rows());
  const auto interior = interior_vertices(plane.positions, plane.triangles);
  Normals zigzag(plane.triangles.rows(), 3);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> direction(0.0, 2.0 * M_PI);
  for (Eigen::Index f = 0; f < zigzag.rows(); ++f) {
    const double a = direction(random);
    zigzag.row(f) = Eigen::RowVector3d(0.2 * std::cos(a), 0.2 * std::sin(a), 1.0).normalized();
  }
  const Eigen::VectorXd crumpled = ruling_spreads(plane.positions, plane.triangles, zigzag, plane_table, interior);
  for (Eigen::Index v = 0; v < crumpled.size(); ++v) {
    if (interior[static_cast<size_t>(v)])
      EXPECT_GT(crumpled[v], kRuledSpread) << "vertex " << v;
    else
      EXPECT_EQ(crumpled[v], 0.0);
  }
  const VertexShares shares = vertex_shares(Eigen::VectorXd::Zero(crumpled.size()), crumpled, interior);
  EXPECT_EQ(shares.flat, 1.0);
  EXPECT_EQ(shares.ruled, 0.0);
  EXPECT_EQ(shares.crumpled, 1.0);
}

// vertex_shares counts the interior only: flat below kFlatDefect, ruled
// below kRuledSpread among the flat, crumpled the flat rest.
TEST(Measures, VertexSharesCountFlatRuledAndCrumpledInteriorVertices) {
  const Eigen::VectorXd defects = (Eigen::VectorXd(5) << 0.0, 2e-3, 5e-4, -5e-4, 1.0).finished();
  const Eigen::VectorXd spreads = (Eigen::VectorXd(5) << 0.0, 0.0, 0.5, 0.01, 0.0).finished();
  const VertexShares shares = vertex_shares(defects, spreads, {true, true, true, true, false});
  EXPECT_DOUBLE_EQ(shares.flat, 0.75);
  EXPECT_DOUBLE_EQ(shares.ruled, 0.5);
  EXPECT_DOUBLE_EQ(shares.crumpled, 0.25);
  const VertexShares none = vertex_shares(defects, spreads, std::vector<bool>(5, false));
  EXPECT_EQ(none.flat + none.ruled + none.crumpled, 0.0);
}

// The noise gain of a vertex's defect: 0 where its star is planar (the
// defect answers noise to second order only); elsewhere the sum of the
// squared gradients of its defect, as finite differences measure them; and
// across a fold it grows with the fold's angle.
TEST(Measures, AngleDefectNoiseGainIsTheSquaredGradientOfTheDefect) {
  const auto flat = test::plane(7, 9);
  const VertexFaces flat_faces = vertex_faces(flat.triangles, flat.positions.rows());
  const Normals flat_normals = face_normals(flat.positions, flat.triangles);
  EXPECT_NEAR(angle_defect_noise_gain(flat.positions, flat.triangles, flat_normals, flat_faces, 4 * 9 + 4), 0.0, 1e-20);

  auto noisy = test::cylinder(8, 24);
  test::add_noise(noisy.positions, 0.02, 5);
  const VertexFaces faces = vertex_faces(noisy.triangles, noisy.positions.rows());
  const Normals normals = face_normals(noisy.positions, noisy.triangles);
  const std::vector<bool> interior = interior_vertices(noisy.positions, noisy.triangles);
  const Eigen::Index v = 3 * 24 + 5;  // an inner ring's vertex
  ASSERT_TRUE(interior[static_cast<size_t>(v)]);
  double squares = 0.0;
  const double step = 1e-6;
  for (Eigen::Index u = 0; u < noisy.positions.rows(); ++u) {
    for (int k = 0; k < 3; ++k) {
      Positions plus = noisy.positions, minus = noisy.positions;
      plus(u, k) += step;
      minus(u, k) -= step;
      const double d =
          (angle_defects(plus, noisy.triangles, interior)[v] - angle_defects(minus, noisy.triangles, interior)[v]) /
          (2.0 * step);
      squares += d * d;
    }
  }
  const double gain = angle_defect_noise_gain(noisy.positions, noisy.triangles, normals, faces, v);
  EXPECT_GT(gain, 0.0);
  EXPECT_NEAR(gain, squares, 1e-6 * squares);

  double previous = 0.0;
  for (const double angle : {0.3, 0.9, 1.5}) {
    const auto m = test::grid(9, 9, false, [=](double a, double b) {
      if (a <= 0.5) return Eigen::Vector3d(b, a, 0.0);
      return Eigen::Vector3d(b, 0.5 + (a - 0.5) * std::cos(angle), (a - 0.5) * std::sin(angle));
    });
    const double g = angle_defect_noise_gain(m.positions, m.triangles, face_normals(m.positions, m.triangles),
                                             vertex_faces(m.triangles, m.positions.rows()), 4 * 9 + 4);
    EXPECT_GT(g, previous) << "fold angle " << angle;
    previous = g;
  }
}

}  // namespace
}  // namespace developable
