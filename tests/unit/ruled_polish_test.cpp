// ruled_polish.h: on a doubly curved mesh split into pieces the polish makes
// vertices flat and ruled (not flat by zigzags), keeps pins, the limit, the
// faces' orientation and the crease guard; it returns its start when nothing
// is scored; sizes that disagree are refused.
#include "deformation/ruled_polish.h"

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

struct Split {
  test::Mesh mesh = test::sphere(4);  // 2048 faces
  std::vector<int> pieces;
  std::vector<bool> inside;
  VertexFaces table = vertex_faces(mesh.triangles, mesh.positions.rows());
  std::vector<bool> interior = interior_vertices(mesh.positions, mesh.triangles);

  // Eight pieces: the octants.
  Split() {
    for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
      Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
      for (int k = 0; k < 3; ++k) c += mesh.positions.row(mesh.triangles(f, k));
      pieces.push_back((c[0] > 0) + 2 * (c[1] > 0) + 4 * (c[2] > 0));
    }
    inside = interior;
    const VertexFaces& t = table;
    for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v)
      for (const int* f = t.begin(v); f != t.end(v); ++f)
        if (pieces[static_cast<size_t>(*f)] != pieces[static_cast<size_t>(*t.begin(v))])
          inside[static_cast<size_t>(v)] = false;
  }

  // Flat-and-ruled and crumpled shares over the inside vertices.
  VertexShares shares(const Positions& p) const {
    const Eigen::VectorXd defects = angle_defects(p, mesh.triangles, inside);
    return vertex_shares(defects, ruling_spreads(p, mesh.triangles, face_normals(p, mesh.triangles), table, inside),
                         inside);
  }
};

TEST(RuledPolish, MakesVerticesFlatAndRuledNotCrumpled) {
  const Split s;
  const Normals normals = face_normals(s.mesh.positions, s.mesh.triangles);
  RuledPolishOptions options;
  options.limit = 0.03;
  const CreaseGuard guard(s.mesh.triangles, normals, s.pieces, 20.0 * M_PI / 180.0);
  options.crease_guard = guard;
  const RuledPolishResult r =
      polish_ruled(s.mesh.positions, s.mesh.positions, normals, s.mesh.triangles, s.inside, {}, options, {});
  ASSERT_GT(r.iterations, 0);
  const VertexShares before = s.shares(s.mesh.positions), after = s.shares(r.positions);
  EXPECT_EQ(before.ruled, 0.0);  // no vertex of a sphere is flat
  EXPECT_GT(after.ruled, 0.3);   // flat and ruled
  EXPECT_LT(after.crumpled, 0.03);
  for (Eigen::Index v = 0; v < s.mesh.positions.rows(); ++v)
    EXPECT_LE((r.positions.row(v) - s.mesh.positions.row(v)).norm(), options.limit * (1.0 + 1e-12));
  const Normals after_normals = face_normals(r.positions, s.mesh.triangles);
  EXPECT_TRUE(turned_over_faces(after_normals, normals).empty());
  EXPECT_TRUE(guard.creased_faces(after_normals).empty());
  // The same input gives the same mesh.
  EXPECT_EQ(
      polish_ruled(s.mesh.positions, s.mesh.positions, normals, s.mesh.triangles, s.inside, {}, options, {}).positions,
      r.positions);
}

// A cylinder patch (radius 1) with noise at 15 % of its edge length.
struct NoisyBand {
  test::Mesh band = test::grid(
      24, 36, false, [](double u, double v) { return Eigen::Vector3d(std::cos(2.0 * v), std::sin(2.0 * v), 1.5 * u); });
  Positions clean = band.positions;
  double edge = average_edge_length(clean, band.triangles);
  NoisyBand() { test::add_noise(band.positions, 0.15 * edge, 7); }
};

// The fit to the reference: a cylinder patch with noise at 15 % of its edge
// length polished flat and ruled ends 0.53 of the input's RMS distance from
// the cylinder without the fit, 0.36 with it.
TEST(RuledPolish, TheFitHoldsANoisySheetNearItsShape) {
  const NoisyBand sheet;
  const test::Mesh& band = sheet.band;
  const double edge = sheet.edge;
  const Normals normals = face_normals(band.positions, band.triangles);
  const std::vector<bool> interior = interior_vertices(band.positions, band.triangles);
  const VertexFaces table = vertex_faces(band.triangles, band.positions.rows());
  // RMS distance of the interior vertices from the cylinder r = 1.
  const auto off_cylinder = [&](const Positions& p) {
    double sum = 0.0;
    int count = 0;
    for (Eigen::Index v = 0; v < p.rows(); ++v) {
      if (!interior[static_cast<size_t>(v)]) continue;
      sum += std::pow(p.row(v).head<2>().norm() - 1.0, 2);
      ++count;
    }
    return std::sqrt(sum / count);
  };
  RuledPolishOptions options;
  options.limit = 2.0 * edge;
  const RuledPolishResult drifting =
      polish_ruled(band.positions, band.positions, normals, band.triangles, interior, {}, options, {});
  options.fit_weight = 0.05;
  const RuledPolishResult fitted =
      polish_ruled(band.positions, band.positions, normals, band.triangles, interior, {}, options, {});
  const Eigen::VectorXd defects = angle_defects(fitted.positions, band.triangles, interior);
  const VertexShares shares = vertex_shares(
      defects,
      ruling_spreads(fitted.positions, band.triangles, face_normals(fitted.positions, band.triangles), table, interior),
      interior);
  EXPECT_GT(shares.ruled, 0.95);
  EXPECT_LT(off_cylinder(fitted.positions), 0.5 * off_cylinder(band.positions));
  EXPECT_LT(off_cylinder(fitted.positions), 0.8 * off_cylinder(drifting.positions));
}

// The objective the polish lowers: next to nothing on a developable sheet,
// more with noise, lower after the polish, and the fit's sum of squares on
// top where the positions left the reference.
TEST(RuledPolish, ItsObjectiveMeasuresWhatTheStepsLower) {
  const NoisyBand sheet;
  const test::Mesh& band = sheet.band;
  const Positions& clean = sheet.clean;
  const double edge = sheet.edge;
  const std::vector<bool> interior = interior_vertices(band.positions, band.triangles);
  RuledPolishOptions options;
  const auto objective = [&](const Positions& p, const Positions& reference) {
    return ruled_polish_objective(p, reference, band.triangles, interior, options);
  };
  const double noisy = objective(band.positions, band.positions);
  EXPECT_LT(objective(clean, clean), 1e-6 * noisy);
  const RuledPolishResult polished =
      polish_ruled(band.positions, band.positions, face_normals(band.positions, band.triangles), band.triangles,
                   interior, {}, options, {});
  ASSERT_GT(polished.iterations, 0);
  EXPECT_LT(objective(polished.positions, band.positions), 0.5 * noisy);
  // The fit: (wF / AE)^2 times the sum of squared moves, AE the reference's.
  options.fit_weight = 0.3;
  const double fit = std::pow(0.3 / edge, 2) * (band.positions - clean).squaredNorm();
  EXPECT_NEAR(objective(band.positions, clean), noisy + fit, 1e-9 * (noisy + fit));
  EXPECT_THROW(ruled_polish_objective(band.positions, clean.topRows(3), band.triangles, interior, options),
               EngineError);
}

TEST(RuledPolish, KeepsPinsAndReturnsItsStartWithNothingScored) {
  const Split s;
  const Normals normals = face_normals(s.mesh.positions, s.mesh.triangles);
  RuledPolishOptions options;
  options.limit = 0.03;
  options.max_iterations = 5;
  std::vector<bool> pinned(static_cast<size_t>(s.mesh.positions.rows()), false);
  for (size_t v = 0; v < pinned.size(); v += 3) pinned[v] = true;
  const RuledPolishResult r =
      polish_ruled(s.mesh.positions, s.mesh.positions, normals, s.mesh.triangles, s.inside, pinned, options, {});
  for (size_t v = 0; v < pinned.size(); ++v) {
    if (pinned[v]) {
      EXPECT_EQ(r.positions.row(static_cast<Eigen::Index>(v)), s.mesh.positions.row(static_cast<Eigen::Index>(v)));
    }
  }
  const std::vector<bool> none(pinned.size(), false);
  const RuledPolishResult idle =
      polish_ruled(s.mesh.positions, s.mesh.positions, normals, s.mesh.triangles, none, {}, options, {});
  EXPECT_EQ(idle.iterations, 0);
  EXPECT_EQ(idle.positions, s.mesh.positions);
  EXPECT_THROW(
      polish_ruled(s.mesh.positions, s.mesh.positions, normals.topRows(2), s.mesh.triangles, s.inside, {}, options, {}),
      EngineError);
}

}  // namespace
}  // namespace developable
