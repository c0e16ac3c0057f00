// Linear-solver benchmark of the deformation's decoupled system (issue #5;
// driven by bench/solvers.py, which writes docs/solvers.md).
//
// Input: mesh sizes in faces on the command line. For each, a closed noisy
// cylinder band like devkit/meshes.py's noisy_cylinder (radius 1, height pi,
// rows - 1 = cols / 2, cols^2 faces, uniform noise of 0.03 grid spacings;
// own random numbers, so not the same noise as numpy's, but the decoupled
// matrix depends only on the triangles). NormalGuidedDeformation is set up as
// the refit pipeline does (native/pipeline.cpp: decoupled, kRefitCentroidWeight,
// default omega = 5, unit row weights, no pins, targets = face normals), which gives
// the engine's n x n SPD matrix A (n = vertices) and, from one engine step x1,
// the right-hand side b = A x1 of the first iteration (n x 3).
//
// Output: JSON objects, one per line, on stdout: first the versions built
// against (compiler, eigen, cholmod, metis), then one for each (size, solver):
//   faces, vertices, matrix_nnz    the mesh and nnz(A) (both triangles)
//   solver, ordering               which factorisation, fill-reducing ordering
//   analyse_ms                     symbolic analysis (ordering, elimination tree)
//   factor_ms                      numeric factorisation
//   solve_ms                       one solve for the three columns of b
//   factor_nnz                     entries of L, diagonal included
//   residual                       max over the columns of |A x - b| / |b| (2-norms)
// Times are wall-clock milliseconds, medians over --factor-repeats analyse +
// factorise runs and --solve-repeats solves.
//
// Usage: solver_bench [--factor-repeats N] [--solve-repeats N] FACES...
#include "core/measures.h"
#include "core/mesh_input.h"
#include "deformation/deformation.h"
#include "pipeline/pipeline.h"

#include <Eigen/CholmodSupport>
#ifdef DEVELOPABLE_HAVE_METIS
#include <Eigen/MetisSupport>
#include <iostream>  // Eigen/MetisSupport uses std::cerr without including it
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

using developable::Positions;
using developable::Triangles;
using SparseMatrix = Eigen::SparseMatrix<double>;

constexpr double kPi = 3.14159265358979323846;

struct Band {
  Positions positions;
  Triangles triangles;
};

// The closed band of devkit/meshes.py noisy_cylinder (same triangles in the
// same order as its grid_triangles(rows, cols, wrap=True)).
Band noisy_cylinder(long faces) {
  int cols = std::max(8, static_cast<int>(std::lround(std::sqrt(static_cast<double>(faces)))));
  cols += cols % 2;
  const int rows = cols / 2 + 1;
  const double noise = 0.03 * 2.0 * kPi / cols;
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> uniform(-noise, noise);

  Band band;
  band.positions.resize(static_cast<Eigen::Index>(rows) * cols, 3);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const double t = 2.0 * kPi * j / cols, z = kPi * i / (rows - 1);
      band.positions.row(static_cast<Eigen::Index>(i) * cols + j) << std::cos(t), std::sin(t), z;
    }
  }
  for (Eigen::Index k = 0; k < band.positions.size(); ++k) band.positions.data()[k] += uniform(random);

  band.triangles.resize(static_cast<Eigen::Index>(rows - 1) * cols * 2, 3);
  Eigen::Index f = 0;
  for (int i = 0; i + 1 < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const int a = i * cols + j, b = i * cols + (j + 1) % cols;
      const int c = (i + 1) * cols + j, d = (i + 1) * cols + (j + 1) % cols;
      if ((i + j) % 2 == 0) {
        band.triangles.row(f++) << a, b, d;
        band.triangles.row(f++) << a, d, c;
      } else {
        band.triangles.row(f++) << a, b, c;
        band.triangles.row(f++) << b, d, c;
      }
    }
  }
  return band;
}

double elapsed_ms(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t half = values.size() / 2;
  return values.size() % 2 ? values[half] : 0.5 * (values[half - 1] + values[half]);
}

// Entries of L with its diagonal. Eigen's LDLT stores L without its unit
// diagonal, its LLT with it; CHOLMOD reports the count of its analysis.
template <typename Ordering>
double factor_nnz(const Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Ordering>& solver) {
  return static_cast<double>(solver.matrixL().nestedExpression().nonZeros() + solver.rows());
}
double factor_nnz(const Eigen::SimplicialLLT<SparseMatrix>& solver) {
  return static_cast<double>(solver.matrixL().nestedExpression().nonZeros());
}
template <typename Derived>
double factor_nnz(Eigen::CholmodBase<SparseMatrix, Eigen::Lower, Derived>& solver) {
  return solver.cholmod().lnz;
}

// The ordering CHOLMOD's analysis kept (by default it tries AMD, and METIS
// too when AMD's fill is high).
template <typename Derived>
std::string cholmod_ordering(Eigen::CholmodBase<SparseMatrix, Eigen::Lower, Derived>& solver) {
  const cholmod_common& common = solver.cholmod();
  switch (common.method[common.selected].ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_AMD:
      return "amd";
    case CHOLMOD_METIS:
      return "metis";
    case CHOLMOD_NESDIS:
      return "nesdis";
    case CHOLMOD_COLAMD:
      return "colamd";
    default:
      return "other";
  }
}

struct Problem {
  Band band;
  SparseMatrix matrix;
  Positions rhs;
};

struct Options {
  int factor_repeats = 3;
  int solve_repeats = 11;
};

// Times `solver` (analyzePattern, factorize, then `solve(solver, b)`, which
// returns x in its own layout) on the problem and prints its JSON line;
// `ordering(solver)` names the solver's ordering.
template <typename Solver, typename Solve, typename Ordering>
void measure(const char* name, const Problem& problem, const Options& options, Solver& solver, Solve solve,
             Ordering ordering) {
  std::vector<double> analyse, factor, solves;
  for (int r = 0; r < options.factor_repeats; ++r) {
    auto start = std::chrono::steady_clock::now();
    solver.analyzePattern(problem.matrix);
    analyse.push_back(elapsed_ms(start));
    start = std::chrono::steady_clock::now();
    solver.factorize(problem.matrix);
    factor.push_back(elapsed_ms(start));
    if (solver.info() != Eigen::Success) {
      std::fprintf(stderr, "solver_bench: %s failed to factor the matrix\n", name);
      std::exit(1);
    }
  }
  auto x = solve(solver, problem.rhs);  // untimed: warms the caches up
  for (int r = 0; r < options.solve_repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    x = solve(solver, problem.rhs);
    solves.push_back(elapsed_ms(start));
  }
  const Eigen::MatrixX3d b = problem.rhs;
  const Eigen::MatrixX3d residual = problem.matrix * Eigen::MatrixX3d(x) - b;
  const double relative = residual.colwise().norm().cwiseQuotient(b.colwise().norm()).maxCoeff();
  std::printf(
      "{\"faces\": %ld, \"vertices\": %ld, \"matrix_nnz\": %ld, \"solver\": \"%s\", "
      "\"ordering\": \"%s\", \"analyse_ms\": %.3f, \"factor_ms\": %.3f, \"solve_ms\": %.3f, "
      "\"factor_nnz\": %.0f, \"residual\": %.3e, \"factor_repeats\": %d, \"solve_repeats\": %d}\n",
      static_cast<long>(problem.band.triangles.rows()), static_cast<long>(problem.matrix.rows()),
      static_cast<long>(problem.matrix.nonZeros()), name, ordering(solver).c_str(), median(analyse), median(factor),
      median(solves), factor_nnz(solver), relative, options.factor_repeats, options.solve_repeats);
  std::fflush(stdout);
}

Problem engine_problem(long faces) {
  Problem problem{noisy_cylinder(faces), {}, {}};
  const Positions& positions = problem.band.positions;
  const Triangles& triangles = problem.band.triangles;
  developable::validate_mesh(positions, triangles);
  const developable::Normals normals = developable::face_normals(positions, triangles);
  const developable::NormalGuidedDeformation deformation(
      triangles, std::vector<bool>(static_cast<size_t>(positions.rows()), false),
      Eigen::VectorXd::Ones(triangles.rows()), developable::PipelineOptions().omega, developable::kRefitCentroidWeight,
      developable::Formulation::decoupled, normals);
  problem.matrix = deformation.system_matrix();
  problem.rhs = problem.matrix * deformation.step(positions, normals);
  return problem;
}

void run(long faces, const Options& options) {
  const Problem problem = engine_problem(faces);
  const auto solve = [](const auto& solver, const Positions& b) -> Eigen::MatrixX3d { return solver.solve(b); };
  const auto named = [](const char* ordering) { return [ordering](const auto&) { return std::string(ordering); }; };
  const auto chosen = [](auto& solver) { return cholmod_ordering(solver); };
  {
    developable::CholeskySolver solver;
    measure("eigen_ldlt", problem, options, solver, solve, named("amd"));
  }
  {
    developable::CholeskySolver solver;
    const auto engine_solve = [](const developable::CholeskySolver& s, const Positions& b) {
      return developable::solve_three_columns(s, b);
    };
    measure("eigen_ldlt_engine_solve", problem, options, solver, engine_solve, named("amd"));
  }
  {
    Eigen::SimplicialLLT<SparseMatrix> solver;
    measure("eigen_llt", problem, options, solver, solve, named("amd"));
  }
#ifdef DEVELOPABLE_HAVE_METIS
  {
    Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::MetisOrdering<int>> solver;
    measure("eigen_ldlt_metis", problem, options, solver, solve, named("metis"));
  }
#endif
  {
    Eigen::CholmodSimplicialLDLT<SparseMatrix> solver;
    measure("cholmod_simplicial_ldlt", problem, options, solver, solve, chosen);
  }
  {
    Eigen::CholmodSimplicialLDLT<SparseMatrix> solver;
    solver.cholmod().nmethods = 1;  // AMD only, like Eigen: the factorisations on a like ordering
    solver.cholmod().method[0].ordering = CHOLMOD_AMD;
    measure("cholmod_simplicial_ldlt_amd", problem, options, solver, solve, chosen);
  }
  {
    Eigen::CholmodSupernodalLLT<SparseMatrix> solver;
    measure("cholmod_supernodal_llt", problem, options, solver, solve, chosen);
  }
}

std::string metis_version() {
#ifdef DEVELOPABLE_HAVE_METIS
  return std::to_string(METIS_VER_MAJOR) + "." + std::to_string(METIS_VER_MINOR) + "." +
         std::to_string(METIS_VER_SUBMINOR);
#else
  return "not found";
#endif
}

int positive(const char* text) {
  const int value = std::atoi(text);
  if (value < 1) {
    std::fprintf(stderr, "solver_bench: expected a positive count, got '%s'\n", text);
    std::exit(2);
  }
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  std::vector<long> sizes;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--factor-repeats") && i + 1 < argc) {
      options.factor_repeats = positive(argv[++i]);
    } else if (!std::strcmp(argv[i], "--solve-repeats") && i + 1 < argc) {
      options.solve_repeats = positive(argv[++i]);
    } else {
      sizes.push_back(positive(argv[i]));
    }
  }
  if (sizes.empty()) {
    std::fprintf(stderr, "usage: solver_bench [--factor-repeats N] [--solve-repeats N] FACES...\n");
    return 2;
  }
#ifdef __clang__
  const char* compiler = "clang " __clang_version__;
#else
  const char* compiler = "gcc " __VERSION__;
#endif
  std::printf("{\"compiler\": \"%s\", \"eigen\": \"%d.%d.%d\", \"cholmod\": \"%d.%d.%d\", \"metis\": \"%s\"}\n",
              compiler, EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION, CHOLMOD_MAIN_VERSION,
              CHOLMOD_SUB_VERSION, CHOLMOD_SUBSUB_VERSION, metis_version().c_str());
  for (long faces : sizes) run(faces, options);
  return 0;
}
