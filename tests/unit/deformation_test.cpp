// Stage 7, deformation.h: solve_three_columns is "bit-identical to
// solver.solve(b)"; the MLS weights; a step keeps pins bit for bit and
// leaves a surface alone whose targets are its own normals.
#include "deformation/deformation.h"

#include "core/measures.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace developable {
namespace {

bool same_bits(const Positions& a, const Positions& b) {
  return a.rows() == b.rows() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

Positions random_rows(Eigen::Index rows, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> g;
  Positions b(rows, 3);
  for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = g(random);
  return b;
}

TEST(Deformation, SolveThreeColumnsIsBitIdenticalToEigensSolve) {
  for (unsigned seed = 0; seed < 4; ++seed) {
    auto m = test::cylinder(10 + 3 * seed, 20 + 5 * seed);
    test::add_noise(m.positions, 0.01, seed);
    std::vector<bool> pinned(m.positions.rows(), false);
    pinned[0] = seed % 2 == 1;
    const NormalGuidedDeformation deformation(m.triangles, pinned, Eigen::VectorXd::Ones(m.triangles.rows()), 5.0, 0.3,
                                              Formulation::decoupled, face_normals(m.positions, m.triangles));
    CholeskySolver solver(deformation.system_matrix());
    ASSERT_EQ(solver.info(), Eigen::Success);
    const Positions b = random_rows(deformation.system_matrix().rows(), seed);
    const Positions eigen = solver.solve(b);
    EXPECT_TRUE(same_bits(solve_three_columns(solver, b), eigen)) << "seed " << seed;
  }
}

TEST(Deformation, MlsWeightsAreOneWithoutPinsAndDoNotDependOnScale) {
  auto m = test::plane(9, 9);
  const double ae = average_edge_length(m.positions, m.triangles);
  const Eigen::VectorXd free = mls_row_weights(m.positions, m.triangles, std::vector<bool>(81, false), ae);
  EXPECT_TRUE((free.array() == 1.0).all());
  std::vector<bool> pinned(81, false);
  pinned[40] = true;  // the centre
  const Eigen::VectorXd w = mls_row_weights(m.positions, m.triangles, pinned, ae);
  const Eigen::VectorXd scaled = mls_row_weights(m.positions * 1000.0, m.triangles, pinned, ae * 1000.0);
  EXPECT_LT((w - scaled).cwiseAbs().maxCoeff(), 1e-9 * w.maxCoeff());
  for (Eigen::Index f = 0; f < w.size(); ++f) {
    EXPECT_GE(w[f], 1.0);
    const bool at_pin = (m.triangles.row(f).array() == 40).any();
    if (at_pin) {
      EXPECT_GT(w[f], 1e5);  // 1 + 1 / eps^2 at the pin
    } else {
      EXPECT_LT(w[f], 3.0);
    }
  }
}

TEST(Deformation, PinsKeepTheirBitsAndFreeVerticesMove) {
  for (Formulation formulation : {Formulation::decoupled, Formulation::coupled}) {
    auto m = test::cylinder(8, 16);
    test::add_noise(m.positions, 0.02, 3);
    std::vector<bool> pinned(m.positions.rows(), false);
    for (size_t v = 0; v < pinned.size(); v += 7) pinned[v] = true;
    // Targets: a cylinder's normals (radial), which the noisy mesh misses.
    Normals targets = face_normals(m.positions, m.triangles);
    for (Eigen::Index f = 0; f < targets.rows(); ++f) {
      targets(f, 2) = 0.0;
      targets.row(f).normalize();
    }
    const NormalGuidedDeformation deformation(m.triangles, pinned, Eigen::VectorXd::Ones(m.triangles.rows()), 5.0, 0.3,
                                              formulation, targets);
    const Positions next = deformation.step(m.positions);
    double moved = 0.0;
    for (Eigen::Index v = 0; v < next.rows(); ++v) {
      if (pinned[v]) {
        EXPECT_TRUE(next.row(v) == m.positions.row(v)) << "vertex " << v;
      } else {
        moved = std::max(moved, (next.row(v) - m.positions.row(v)).norm());
      }
    }
    EXPECT_GT(moved, 1e-4);
    EXPECT_TRUE(next.allFinite());
  }
}

TEST(Deformation, OwnNormalsAsTargetsLeaveAPlaneInPlace) {
  const auto m = test::plane(6, 7);
  const Normals normals = face_normals(m.positions, m.triangles);
  for (Formulation formulation : {Formulation::decoupled, Formulation::coupled}) {
    const NormalGuidedDeformation deformation(m.triangles, std::vector<bool>(m.positions.rows(), false),
                                              Eigen::VectorXd::Ones(m.triangles.rows()), 5.0, 1.0, formulation,
                                              normals);
    EXPECT_LT((deformation.step(m.positions, normals) - m.positions).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// A copy sharing the decoupled factor steps as a deformation with a factor of
// its own, bit for bit, and keeps stepping once the original is released;
// a coupled system (whose matrix follows the targets) is not shared.
TEST(Deformation, ASharedFactorStepsAsItsOwn) {
  const auto m = test::plane(6, 7);
  std::vector<bool> pinned(static_cast<size_t>(m.positions.rows()), false);
  pinned[0] = true;
  Positions bent = m.positions;
  for (Eigen::Index v = 0; v < bent.rows(); ++v) bent(v, 2) = 0.1 * bent(v, 0) * bent(v, 0);
  const Normals normals = face_normals(bent, m.triangles);
  const Normals up = face_normals(m.positions, m.triangles);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(m.triangles.rows());
  NormalGuidedDeformation original(m.triangles, pinned, ones, 5.0, 0.3, Formulation::decoupled, normals);
  NormalGuidedDeformation shared = original.sharing_factor();
  original.release();
  shared.set_targets(up);
  NormalGuidedDeformation own(m.triangles, pinned, ones, 5.0, 0.3, Formulation::decoupled, up);
  const Positions a = shared.step(bent, normals), b = own.step(bent, normals);
  ASSERT_EQ(a.rows(), b.rows());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * a.size()), 0);
  NormalGuidedDeformation coupled(m.triangles, pinned, ones, 5.0, 0.3, Formulation::coupled, normals);
  EXPECT_THROW(coupled.sharing_factor(), EngineError);
  shared.release();
  EXPECT_THROW(shared.sharing_factor(), EngineError);
}

TEST(Deformation, AReleasedSystemRefusesToStep) {
  const auto m = test::plane(6, 7);
  const Normals normals = face_normals(m.positions, m.triangles);
  for (Formulation formulation : {Formulation::decoupled, Formulation::coupled}) {
    NormalGuidedDeformation deformation(m.triangles, std::vector<bool>(m.positions.rows(), false),
                                        Eigen::VectorXd::Ones(m.triangles.rows()), 5.0, 1.0, formulation, normals);
    deformation.release();
    EXPECT_EQ(deformation.targets().rows(), 0);
    try {
      deformation.step(m.positions, normals);
      ADD_FAILURE() << "a released system stepped";
    } catch (const EngineError& e) {
      EXPECT_EQ(e.status(), Status::internal_error);
    }
    EXPECT_THROW(deformation.step(m.positions), EngineError);
  }
}

TEST(Deformation, Refusals) {
  const auto m = test::plane(4, 4);
  const Normals normals = face_normals(m.positions, m.triangles);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(m.triangles.rows());
  try {
    NormalGuidedDeformation(m.triangles, std::vector<bool>(16, true), ones, 5.0, 1.0, Formulation::decoupled, normals);
    ADD_FAILURE() << "every vertex pinned was accepted";
  } catch (const EngineError& e) {
    EXPECT_EQ(e.status(), Status::no_free_vertex);
  }
  Eigen::VectorXd bad = ones;
  bad[0] = -1.0;
  EXPECT_THROW(NormalGuidedDeformation(m.triangles, std::vector<bool>(16, false), bad, 5.0, 1.0, Formulation::decoupled,
                                       normals),
               EngineError);
  EXPECT_THROW(NormalGuidedDeformation(m.triangles, std::vector<bool>(16, false), ones, 0.0, 1.0,
                                       Formulation::decoupled, normals),
               EngineError);
}

TEST(Deformation, ZeroNormalWeightsKeepTheShapeAndOnesChangeNothing) {
  auto m = test::cylinder(8, 16);
  test::add_noise(m.positions, 0.02, 3);
  const Normals normals = face_normals(m.positions, m.triangles);
  Normals targets = normals;
  targets.col(2).array() += 0.3;  // targets off the normals: a step moves the mesh
  targets.rowwise().normalize();
  NormalGuidedDeformation deformation(m.triangles, std::vector<bool>(m.positions.rows(), false),
                                      Eigen::VectorXd::Ones(m.triangles.rows()), 5.0, 0.3, Formulation::decoupled,
                                      targets);
  const Positions full = deformation.step(m.positions, normals);
  EXPECT_GT((full - m.positions).cwiseAbs().maxCoeff(), 1e-3);
  deformation.set_normal_weights(Eigen::VectorXd::Ones(m.triangles.rows()));
  EXPECT_TRUE(same_bits(deformation.step(m.positions, normals), full));
  deformation.set_normal_weights(Eigen::VectorXd::Zero(m.triangles.rows()));
  EXPECT_LT((deformation.step(m.positions, normals) - m.positions).cwiseAbs().maxCoeff(), 1e-12);
  Eigen::VectorXd bad = Eigen::VectorXd::Ones(m.triangles.rows());
  bad[1] = 1.5;
  EXPECT_THROW(deformation.set_normal_weights(bad), EngineError);
  EXPECT_THROW(deformation.set_normal_weights(Eigen::VectorXd::Ones(3)), EngineError);
}

}  // namespace
}  // namespace developable
