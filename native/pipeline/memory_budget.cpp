#include "pipeline/memory_budget.h"

#include "ideal_curve/ideal_curve.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#if defined(_WIN32)
#include <windows.h>
#else
#include <unistd.h>
#endif

namespace developable {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;
constexpr double kGiB = 1024.0 * kMiB;

// Measured peaks (Release, 2 cores; docs/hardening.md) per face, with the
// safety factor folded in:
//   decoupled  ~450 B/face at 10k..640k faces        -> 800 B/face
//   coupled    4.1 KB/face at 10k, 4.8 KB/face at 160k faces, growing
//              with the Cholesky fill-in (~ log of the size)
//              -> 3 KB * (1 + log2(faces / 1e4) / 8) * 1.6
// plus the copies of the input (positions and triangles, a few times) and
// the effect-field grid of one patch (~100 B per cell, 2 live at once).
constexpr double kDecoupledBytesPerFace = 800.0;
constexpr double kCoupledBytesPerFace = 3000.0 * 1.6;
constexpr double kBytesPerVertex = 24.0 * 10;              // positions: input, result, iterates, normals
constexpr double kBytesPerTriangle = 12.0 * 4 + 36.0 * 2;  // copies, directed edges, sort
constexpr double kBytesPerGridCell = 2 * 100.0;
// The angle-defect polishes (defect_polish.h): J and J J^T (about 20 entries
// a row each, one row per vertex, ~ half a vertex per face), their index
// tables and copies of the positions, two at a time (least motion's
// candidates run side by side), and the candidates' results; and the factor
// of a system of up to 20k rows (one per vertex), about 200 entries a row.
// A noisy 1M-face cylinder peaked at 2496 MiB with least motion's
// candidates, 1062 without: 1.5 KB/face, with the safety factor 2.4 KB.
// Since the polish's tables are smaller and one crease guard serves a run,
// 1511 MiB with one polish beside the deformation's system and two after
// it (docs/method.md, "Scans of any size" and "Least motion ahead of the
// deformation"); the bound is left where it was, above what runs take.
constexpr double kPolishBytesPerFace = 2400.0;
constexpr double kPolishFactorBytesPerRow = 200.0 * 12.0;
constexpr double kPolishFactorRows = 20000.0;
// Anderson acceleration of the refit mode's iterations (anderson_acceleration.h,
// meshes above 25000 scored vertices): two rings of 5 differences of the
// positions, the last residual and step, the iterate before the step and the
// mix (the 1M-face cone's peak 742 -> 908 MB).
constexpr double kAccelerationBytesPerVertex = 24.0 * 14;
constexpr double kFixedBytes = 32.0 * kMiB;  // thread stacks, tables, allocator slack

}  // namespace

double estimated_peak_bytes(int64_t vertices, int64_t triangles, const PipelineOptions& options) {
  const double n = static_cast<double>(std::max<int64_t>(vertices, 0));
  const double m = static_cast<double>(std::max<int64_t>(triangles, 0));
  const bool coupled = formulation_of(options) == Formulation::coupled;
  double per_face = kDecoupledBytesPerFace;
  if (coupled) per_face = kCoupledBytesPerFace * (1.0 + std::max(0.0, std::log2(m / 1e4)) / 8.0);
  const double grid = static_cast<double>(
      options.curve_options.grid_resolution > 0 ? options.curve_options.grid_resolution : automatic_grid_resolution(m));
  const bool polish = polish_enabled(options);
  if (polish) per_face += kPolishBytesPerFace;
  const double per_vertex = kBytesPerVertex + (options.mode == Mode::refit ? kAccelerationBytesPerVertex : 0.0);
  const double factor = polish ? std::min(n, kPolishFactorRows) * kPolishFactorBytesPerRow : 0.0;
  return kFixedBytes + factor + n * per_vertex + m * (kBytesPerTriangle + per_face) + grid * grid * kBytesPerGridCell;
}

double memory_budget_bytes() {
  if (const char* text = std::getenv("DEVELOPABLE_MEMORY_BUDGET_MB")) {
    char* end = nullptr;
    const double mib = std::strtod(text, &end);
    if (end != text && std::isfinite(mib) && mib > 0.0) return mib * kMiB;
  }
#if defined(_WIN32)
  MEMORYSTATUSEX status;
  status.dwLength = sizeof status;
  if (!GlobalMemoryStatusEx(&status) || status.ullTotalPhys == 0) return 8.0 * kGiB;
  return 0.5 * static_cast<double>(status.ullTotalPhys);
#else
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 8.0 * kGiB;
  return 0.5 * static_cast<double>(pages) * static_cast<double>(page_size);
#endif
}

void check_memory_budget(int64_t vertices, int64_t triangles, const PipelineOptions& options) {
  const double need = estimated_peak_bytes(vertices, triangles, options);
  const double budget = memory_budget_bytes();
  if (need <= budget) return;
  std::ostringstream s;
  s.precision(3);
  s << "the mesh is too large for the memory budget: " << vertices << " vertices and " << triangles
    << " triangles need about " << need / kGiB << " GiB, the budget is " << budget / kGiB
    << " GiB (half of the physical memory, or DEVELOPABLE_MEMORY_BUDGET_MB)";
  const bool coupled = formulation_of(options) == Formulation::coupled;
  if (coupled)
    s << "; the decoupled solver in refit mode needs about ten times less";
  else
    s << "; decimate the mesh or process it in parts";
  throw EngineError(Status::out_of_memory, s.str());
}

}  // namespace developable
