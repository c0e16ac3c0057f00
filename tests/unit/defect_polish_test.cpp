// defect_polish.h: the polish drives the constrained angle defects to zero
// by small moves, keeps pins, the limit and the faces' orientation, and
// returns its start when it cannot or need not move.
#include "deformation/defect_polish.h"

#include "core/measures.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <atomic>

#include <cmath>
#include <random>

namespace developable {
namespace {

// The cylinder with every coordinate moved by up to `amplitude`.
test::Mesh noisy_cylinder(double amplitude, unsigned seed) {
  test::Mesh m = test::cylinder(10, 30);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v)
    for (int k = 0; k < 3; ++k) m.positions(v, k) += noise(random);
  return m;
}

double largest_defect(const Positions& positions, const Triangles& triangles, const std::vector<bool>& mask) {
  return angle_defects(positions, triangles, mask).cwiseAbs().maxCoeff();
}

// The polish of every interior vertex of `m` from its own positions.
PolishResult polish_interior(const test::Mesh& m, const PolishOptions& options) {
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  return polish_defects(m.positions, m.positions, face_normals(m.positions, m.triangles), m.triangles, interior, {},
                        options, Progress{});
}

TEST(DefectPolish, DrivesTheDefectsOfANoisyDevelopableToZero) {
  const auto m = noisy_cylinder(0.01, 1);
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  ASSERT_GT(largest_defect(m.positions, m.triangles, interior), 1e-3);
  const Normals normals = face_normals(m.positions, m.triangles);
  const PolishResult r =
      polish_defects(m.positions, m.positions, normals, m.triangles, interior, {}, PolishOptions{}, Progress{});
  EXPECT_GT(r.iterations, 0);
  EXPECT_LT(largest_defect(r.positions, m.triangles, interior), 1e-6);
  EXPECT_LT(r.residual_after, 1e-3 * r.residual_before);
  // Small moves: about the noise, far below the edge length (~0.2).
  EXPECT_LT((r.positions - m.positions).rowwise().norm().maxCoeff(), 0.05);
  const Normals after = face_normals(r.positions, m.triangles);
  for (Eigen::Index f = 0; f < after.rows(); ++f) EXPECT_GT(after.row(f).dot(normals.row(f)), 0.0);
}

// spread_damping: while defects are large the steps stay damped, nearer the
// gradient, which spreads the motion: the vertex the polish moves farthest
// moves less than with Gauss-Newton's steps throughout (over eight noisy
// cylinders), and once the defects are small the steps finish as flat.
TEST(DefectPolish, SpreadDampingMovesSingleVerticesLess) {
  double plain_far = 0.0, damped_far = 0.0;
  int fewer = 0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const auto m = noisy_cylinder(0.02, seed);
    const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
    const Normals normals = face_normals(m.positions, m.triangles);
    PolishOptions spread;
    spread.spread_damping = 1e-3;
    const PolishResult plain =
        polish_defects(m.positions, m.positions, normals, m.triangles, interior, {}, PolishOptions{}, Progress{});
    const PolishResult damped =
        polish_defects(m.positions, m.positions, normals, m.triangles, interior, {}, spread, Progress{});
    EXPECT_LT(largest_defect(damped.positions, m.triangles, interior), 1e-6) << seed;
    EXPECT_TRUE(turned_over_faces(face_normals(damped.positions, m.triangles), normals).empty()) << seed;
    const double p = (plain.positions - m.positions).rowwise().norm().maxCoeff();
    const double d = (damped.positions - m.positions).rowwise().norm().maxCoeff();
    plain_far += p;
    damped_far += d;
    fewer += d < p;
  }
  EXPECT_LT(damped_far, 0.97 * plain_far);
  EXPECT_GE(fewer, 6);
}

// Large systems go to conjugate gradients (direct_rows); their inexact
// steps reach the same flat, fold-free result here.
// A mesh that is flat but for one bump (a deformed iterate) is polished on
// the bump's neighbourhood alone: vertices farther away stay exactly where
// they are, and the result is the polish of a cut-out of the neighbourhood,
// bit for bit (the far mesh cannot change it).
TEST(DefectPolish, ALocalDefectIsPolishedOnItsNeighbourhood) {
  auto m = test::cylinder(16, 48);
  const Eigen::Index bumped = 8 * 48 + 20;
  m.positions.row(bumped) *= 1.01;  // out along the radius by 1 % of it
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  ASSERT_TRUE(interior[static_cast<size_t>(bumped)]);
  const Normals normals = face_normals(m.positions, m.triangles);
  const PolishResult whole =
      polish_defects(m.positions, m.positions, normals, m.triangles, interior, {}, PolishOptions{}, Progress{});
  EXPECT_GT(whole.iterations, 0);
  EXPECT_LT(largest_defect(whole.positions, m.triangles, interior), 1e-6);

  // Rings around the bump: ring[v] = edge distance, up to 6.
  const Eigen::Index n = m.positions.rows();
  std::vector<int> ring(static_cast<size_t>(n), -1);
  ring[static_cast<size_t>(bumped)] = 0;
  for (int r = 0; r < 6; ++r)
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
      bool at_r = false;
      for (int c = 0; c < 3; ++c) at_r = at_r || ring[static_cast<size_t>(m.triangles(f, c))] == r;
      if (!at_r) continue;
      for (int c = 0; c < 3; ++c)
        if (ring[static_cast<size_t>(m.triangles(f, c))] < 0) ring[static_cast<size_t>(m.triangles(f, c))] = r + 1;
    }
  for (Eigen::Index v = 0; v < n; ++v)
    if (ring[static_cast<size_t>(v)] < 0 || ring[static_cast<size_t>(v)] > 3) {
      EXPECT_TRUE(whole.positions.row(v) == m.positions.row(v)) << v;
    }

  // The cut-out: faces within 6 rings, in their order, its vertices in theirs.
  std::vector<int> local_of(static_cast<size_t>(n), -1);
  std::vector<Eigen::Index> global_of, faces;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    bool inside = true;
    for (int c = 0; c < 3; ++c) inside = inside && ring[static_cast<size_t>(m.triangles(f, c))] >= 0;
    if (inside) faces.push_back(f);
  }
  for (Eigen::Index v = 0; v < n; ++v)
    if (ring[static_cast<size_t>(v)] >= 0) {
      local_of[static_cast<size_t>(v)] = static_cast<int>(global_of.size());
      global_of.push_back(v);
    }
  const auto cut_n = static_cast<Eigen::Index>(global_of.size());
  Positions cut(cut_n, 3);
  std::vector<bool> cut_interior(static_cast<size_t>(cut_n));
  for (Eigen::Index i = 0; i < cut_n; ++i) {
    const Eigen::Index v = global_of[static_cast<size_t>(i)];
    cut.row(i) = m.positions.row(v);
    cut_interior[static_cast<size_t>(i)] = ring[static_cast<size_t>(v)] < 6;  // the rim has lost faces
  }
  Triangles cut_triangles(static_cast<Eigen::Index>(faces.size()), 3);
  Normals cut_normals(cut_triangles.rows(), 3);
  for (Eigen::Index i = 0; i < cut_triangles.rows(); ++i) {
    for (int c = 0; c < 3; ++c)
      cut_triangles(i, c) = local_of[static_cast<size_t>(m.triangles(faces[static_cast<size_t>(i)], c))];
    cut_normals.row(i) = normals.row(faces[static_cast<size_t>(i)]);
  }
  const PolishResult local =
      polish_defects(cut, cut, cut_normals, cut_triangles, cut_interior, {}, PolishOptions{}, Progress{});
  EXPECT_EQ(local.iterations, whole.iterations);
  for (Eigen::Index i = 0; i < cut_n; ++i)
    EXPECT_TRUE(local.positions.row(i) == whole.positions.row(global_of[static_cast<size_t>(i)])) << i;
}

double rms_distance(const Positions& a, const Positions& b) {
  return std::sqrt((a - b).rowwise().squaredNorm().mean());
}

// The mesh the give-up tests polish, from and against its own positions.
struct GiveUpCase {
  test::Mesh m = noisy_cylinder(0.01, 3);
  std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  Normals normals = face_normals(m.positions, m.triangles);

  PolishResult polish(const PolishOptions& options) const {
    return polish_defects(m.positions, m.positions, normals, m.triangles, interior, {}, options, Progress{});
  }
};

// give_up_move: a polish that has moved the mesh farther from its reference
// than the limit (RMS over the whole mesh) stops there, said; one with room
// runs as without it.
TEST(DefectPolish, GivesUpOnceItHasMovedTheMeshTooFar) {
  const GiveUpCase c;
  const PolishResult full = c.polish(PolishOptions{});
  const double moved = rms_distance(full.positions, c.m.positions);
  ASSERT_GT(full.iterations, 1);
  ASSERT_GT(moved, 0.0);
  PolishOptions tight, loose;
  tight.give_up_move = 0.5 * moved;
  loose.give_up_move = 2.0 * moved;
  const PolishResult stopped = c.polish(tight);
  EXPECT_TRUE(stopped.gave_up);
  EXPECT_LT(stopped.iterations, full.iterations);
  EXPECT_GT(rms_distance(stopped.positions, c.m.positions), tight.give_up_move);
  const PolishResult same = c.polish(loose);
  EXPECT_FALSE(same.gave_up);
  EXPECT_EQ(same.positions, full.positions);
}

// A bound that comes late (PolishOptions::late_give_up_move: least motion's
// polish of the input runs beside the polish that sets it) gives the verdict
// one known from the start gives: the largest move is kept from the first
// step, so a polish that ends before the bound comes still shows it went past.
TEST(DefectPolish, ALateGiveUpBoundGivesTheSameVerdict) {
  const GiveUpCase c;
  const PolishResult full = c.polish(PolishOptions{});
  const double moved = rms_distance(full.positions, c.m.positions);
  const double bound = 0.5 * moved;
  PolishOptions early;
  early.give_up_move = bound;
  const PolishResult stopped = c.polish(early);
  ASSERT_TRUE(stopped.gave_up);

  std::atomic<double> late_bound{bound};  // known before the first step
  PolishOptions late;
  late.late_give_up_move = &late_bound;
  const PolishResult known = c.polish(late);
  EXPECT_TRUE(known.gave_up);
  EXPECT_EQ(known.iterations, stopped.iterations);
  EXPECT_EQ(known.positions, stopped.positions);

  late_bound = 0.0;  // never known while it runs: it runs to the end
  const PolishResult unknown = c.polish(late);
  EXPECT_FALSE(unknown.gave_up);
  EXPECT_EQ(unknown.positions, full.positions);
  EXPECT_GT(unknown.largest_move, bound);
  EXPECT_GE(unknown.largest_move, moved * (1.0 - 1e-12));  // its last step at least (rounding aside)
  EXPECT_EQ(full.largest_move, 0.0);                       // no bound, nothing kept
}

// On a submesh the vertices outside it count too: a reference offset from
// the whole mesh by d puts every vertex about d away, so a limit just under
// d is passed at the first step, though the bump's few vertices alone would
// be far under it.
TEST(DefectPolish, GivingUpCountsTheVerticesOutsideTheSubmesh) {
  auto m = test::cylinder(16, 48);
  m.positions.row(8 * 48 + 20) *= 1.01;
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  const Normals normals = face_normals(m.positions, m.triangles);
  const double d = 1e-3;
  Positions reference = m.positions;
  reference.col(2).array() += d;
  PolishOptions options;
  options.give_up_move = 0.999 * d;
  const PolishResult r =
      polish_defects(m.positions, reference, normals, m.triangles, interior, {}, options, Progress{});
  EXPECT_TRUE(r.gave_up);
  EXPECT_EQ(r.iterations, 1);
}

TEST(DefectPolish, ConjugateGradientsAboveTheDirectRowsMoveAsLittle) {
  const auto m = noisy_cylinder(0.01, 2);
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  const Normals normals = face_normals(m.positions, m.triangles);
  PolishOptions iterative;
  iterative.direct_rows = 10;  // far below the ~250 constrained vertices
  const PolishResult direct = polish_interior(m, PolishOptions{});
  const PolishResult r = polish_interior(m, iterative);
  EXPECT_GT(r.iterations, 0);
  EXPECT_NE(r.positions, direct.positions);  // the other solver really ran
  EXPECT_LT(largest_defect(r.positions, m.triangles, interior), 1e-6);
  // Truncated conjugate gradients (kIterativeSteps) take other steps to
  // another flat mesh, as near the start: RMS within a tenth of the direct
  // steps', the farthest vertex within half again.
  const auto rms = [&](const Positions& p) { return std::sqrt((p - m.positions).rowwise().squaredNorm().mean()); };
  const auto largest = [&](const Positions& p) { return (p - m.positions).rowwise().norm().maxCoeff(); };
  EXPECT_LT(rms(r.positions), 1.1 * rms(direct.positions));
  EXPECT_LT(largest(r.positions), 1.5 * largest(direct.positions));
  EXPECT_TRUE(turned_over_faces(face_normals(r.positions, m.triangles), normals).empty());
}

// settled_defect: a polish solved by conjugate gradients stops in fewer
// steps, once every defect it works on is flat and their RMS is below the
// bound, not at target_defect; a factored one goes on.
TEST(DefectPolish, AnIterativePolishStopsOnceSettled) {
  const auto m = noisy_cylinder(0.01, 3);
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  PolishOptions iterative;
  iterative.direct_rows = 10;  // far below the ~250 constrained vertices
  const PolishResult full = polish_interior(m, iterative);
  PolishOptions settled = iterative;
  settled.settled_defect = 1e-4;
  const PolishResult r = polish_interior(m, settled);
  EXPECT_GT(r.iterations, 0);
  EXPECT_LT(r.iterations, full.iterations);
  EXPECT_LT(largest_defect(r.positions, m.triangles, interior), kFlatDefect);
  EXPECT_LT(r.residual_after, 1e-4);
  EXPECT_GT(r.residual_after, full.residual_after);
  PolishOptions factored;
  factored.settled_defect = 1e-4;
  EXPECT_LT(polish_interior(m, factored).residual_after, 1e-7);
}

// stall_flat_share: where the constrained vertices can become flat only by
// giving their curvature to the others (a third of a sphere's lower half
// and all of its top constrained, as the nearly flat rounds constrain
// theirs) within a small limit, a polish solved by conjugate gradients gains
// flat vertices a few at a time; with the share it stalls sooner, nearly as
// flat; a factored one keeps the strict rule, step for step.
TEST(DefectPolish, AnIterativePolishStallsOnSlowFlatGains) {
  test::Mesh m = test::sphere(3);
  test::add_noise(m.positions, 0.003, 4);
  std::vector<bool> constrained(static_cast<size_t>(m.positions.rows()));
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v)
    constrained[static_cast<size_t>(v)] = m.positions(v, 2) > 0.3 || v % 3 == 0;
  const Normals normals = face_normals(m.positions, m.triangles);
  const auto polish = [&](PolishOptions options) {
    options.limit = 0.05;
    return polish_defects(m.positions, m.positions, normals, m.triangles, constrained, {}, options, Progress{});
  };
  PolishOptions iterative;
  iterative.direct_rows = 10;  // far below the ~300 constrained vertices
  const PolishResult strict = polish(iterative);
  PolishOptions slow = iterative;
  slow.stall_flat_share = 0.5;  // any window that does not halve sum K^2 stalls
  const PolishResult r = polish(slow);
  EXPECT_GT(r.iterations, 0);
  EXPECT_LT(2 * r.iterations, strict.iterations);
  EXPECT_LT(r.residual_after, 1.05 * strict.residual_after);
  EXPECT_LT(r.residual_after, r.residual_before);
  PolishOptions factored;
  factored.stall_flat_share = 0.5;
  const PolishResult f = polish(factored);
  const PolishResult f_strict = polish(PolishOptions{});
  EXPECT_EQ(f.iterations, f_strict.iterations);
  EXPECT_EQ(f.positions, f_strict.positions);
}

TEST(DefectPolish, KeepsPinsAndTheLimit) {
  const auto m = noisy_cylinder(0.01, 2);
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  std::vector<bool> pinned(static_cast<size_t>(m.positions.rows()), false);
  for (size_t v = 0; v < pinned.size(); v += 7) pinned[v] = true;
  PolishOptions options;
  options.limit = 0.002;
  const PolishResult r = polish_defects(m.positions, m.positions, face_normals(m.positions, m.triangles), m.triangles,
                                        interior, pinned, options, Progress{});
  EXPECT_GT(r.iterations, 0);
  EXPECT_LT(r.residual_after, r.residual_before);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    if (pinned[static_cast<size_t>(v)]) {
      EXPECT_TRUE(r.positions.row(v) == m.positions.row(v));
    }
    EXPECT_LE((r.positions.row(v) - m.positions.row(v)).norm(), options.limit * (1 + 1e-12));
  }
}

// pull_steps: from a developable start (the clean cylinder), the projection's
// steps move the mesh toward the reference (a noisy copy) as far as the
// defects allow, and the polish then leaves it developable: nearer the
// reference than its start, no face turned over. Without them there is
// nothing to do (the start is flat).
TEST(DefectPolish, PullStepsProjectTheReferenceOntoDevelopableMeshes) {
  const test::Mesh clean = test::cylinder(10, 30);
  const auto noisy = noisy_cylinder(0.01, 5);
  const std::vector<bool> interior = interior_vertices(clean.positions, clean.triangles);
  const Normals normals = face_normals(noisy.positions, noisy.triangles);
  const auto rms = [](const Positions& a, const Positions& b) {
    return std::sqrt((a - b).rowwise().squaredNorm().mean());
  };
  PolishOptions plain;
  plain.active_defect = 0.0;
  const PolishResult unpulled =
      polish_defects(clean.positions, noisy.positions, normals, clean.triangles, interior, {}, plain, Progress{});
  EXPECT_EQ(unpulled.iterations, 0);
  PolishOptions pulled = plain;
  pulled.pull_steps = 5;
  const PolishResult r =
      polish_defects(clean.positions, noisy.positions, normals, clean.triangles, interior, {}, pulled, Progress{});
  EXPECT_GE(r.iterations, 5);
  EXPECT_LT(largest_defect(r.positions, clean.triangles, interior), 1e-6);
  const double before = rms(clean.positions, noisy.positions), after = rms(r.positions, noisy.positions);
  EXPECT_LT(after, 0.9 * before) << before << " -> " << after;
  EXPECT_TRUE(turned_over_faces(face_normals(r.positions, clean.triangles), normals).empty());
  // The limit holds in the projection's steps too.
  pulled.limit = 0.002;
  const PolishResult limited =
      polish_defects(clean.positions, noisy.positions, normals, clean.triangles, interior, {}, pulled, Progress{});
  for (Eigen::Index v = 0; v < clean.positions.rows(); ++v)
    EXPECT_LE((limited.positions.row(v) - noisy.positions.row(v)).norm(),
              std::max(pulled.limit, (clean.positions.row(v) - noisy.positions.row(v)).norm()) * (1 + 1e-12));
}

TEST(DefectPolish, OnlyConstrainedVerticesCount) {
  // Constraining half the vertices flattens those; the polish never reads the others.
  const auto m = noisy_cylinder(0.01, 3);
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  std::vector<bool> half = interior;
  for (size_t v = 0; v < half.size(); ++v) half[v] = half[v] && (v % 2 == 0);
  const PolishResult r = polish_defects(m.positions, m.positions, face_normals(m.positions, m.triangles), m.triangles,
                                        half, {}, PolishOptions{}, Progress{});
  EXPECT_LT(largest_defect(r.positions, m.triangles, half), 1e-6);
}

TEST(DefectPolish, ReturnsItsStartWhenNothingIsToDo) {
  const auto plane = test::plane();
  const std::vector<bool> interior = interior_vertices(plane.positions, plane.triangles);
  const Normals normals = face_normals(plane.positions, plane.triangles);
  // Developable already: no vertex is active.
  PolishResult r = polish_defects(plane.positions, plane.positions, normals, plane.triangles, interior, {},
                                  PolishOptions{}, Progress{});
  EXPECT_EQ(r.iterations, 0);
  EXPECT_TRUE(r.positions == plane.positions);
  // Everything pinned, or nothing constrained.
  const auto m = noisy_cylinder(0.01, 4);
  const Normals n = face_normals(m.positions, m.triangles);
  const std::vector<bool> all(static_cast<size_t>(m.positions.rows()), true), none(all.size(), false);
  r = polish_defects(m.positions, m.positions, n, m.triangles, interior_vertices(m.positions, m.triangles), all,
                     PolishOptions{}, Progress{});
  EXPECT_EQ(r.iterations, 0);
  EXPECT_TRUE(r.positions == m.positions);
  r = polish_defects(m.positions, m.positions, n, m.triangles, none, {}, PolishOptions{}, Progress{});
  EXPECT_EQ(r.iterations, 0);
}

TEST(DefectPolish, CurvatureItCannotRemoveStays) {
  // A cube's corners carry pi/2 each; within a limit of a hundredth of an
  // edge the polish can only lower their sum of squares a little, and it
  // never turns a face over.
  const auto m = test::cube();
  const std::vector<bool> all(8, true);
  const Normals normals = face_normals(m.positions, m.triangles);
  PolishOptions options;
  options.limit = 0.01;
  const PolishResult r = polish_defects(m.positions, m.positions, normals, m.triangles, all, {}, options, Progress{});
  EXPECT_GT(largest_defect(r.positions, m.triangles, all), 1.0);
  const Normals after = face_normals(r.positions, m.triangles);
  for (Eigen::Index f = 0; f < after.rows(); ++f) EXPECT_GT(after.row(f).dot(normals.row(f)), 0.0);
}

TEST(DefectPolish, RefusesSizesThatDisagreeAndCancels) {
  const auto m = noisy_cylinder(0.01, 5);
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  const Normals normals = face_normals(m.positions, m.triangles);
  try {
    polish_defects(m.positions, m.positions.topRows(5), normals, m.triangles, interior, {}, PolishOptions{},
                   Progress{});
    FAIL() << "no error";
  } catch (const EngineError& e) {
    EXPECT_EQ(e.status(), Status::internal_error);
  }
  const ProgressFn stop = [](double, const char*, void*) { return false; };
  try {
    polish_defects(m.positions, m.positions, normals, m.triangles, interior, {}, PolishOptions{},
                   Progress{stop, nullptr});
    FAIL() << "not cancelled";
  } catch (const EngineError& e) {
    EXPECT_EQ(e.status(), Status::cancelled);
  }
}

}  // namespace
}  // namespace developable
