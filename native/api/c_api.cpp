// The C ABI (developable.h): checks the caller's buffers and counts,
// converts them and the parameters, turns the faces so that neighbours agree
// (orientation.h; the per-face outputs go back in the caller's winding),
// calls the pipeline, and catches everything. The checks of the mesh and the
// options, the memory budget and the diagnosis of polygon soups live in the
// pipeline (check_input, run_pipeline), where C++ callers get them too; a
// C++ caller of run_pipeline or unfold turns the faces itself (orient_faces).
#include "api/developable.h"

#include "core/mesh_input.h"
#include "core/orientation.h"
#include "pattern/pattern_layout.h"
#include "pattern/pattern_svg.h"
#include "pattern/unfold.h"
#include "pipeline/memory_budget.h"
#include "pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>

#ifndef DEVELOPABLE_VERSION
#define DEVELOPABLE_VERSION "0.0.0"
#endif

struct dev_result {
  developable::PipelineResult pipeline;
  std::string orientation_note;  // what dev_run turned (orientation_note), "" for nothing
};

struct dev_pattern {
  developable::UnfoldResult unfolded;  // the faces as the engine ran them (orientation.h)
  std::vector<bool> turned;            // per face: turned over against the caller's winding
  developable::Layout layout;
  bool laid_out = false;
  std::vector<std::string> files;
  dev_pattern_stats stats{};
};

namespace {

using developable::EngineError;
using developable::Status;

// The C values are the C++ enums' (types.h, pipeline.h, deformation.h):
// a status, stop reason or result crosses the boundary by a plain cast.
template <typename Enum>
constexpr int32_t c_value(Enum e) {
  return static_cast<int32_t>(e);
}
static_assert(DEV_STATUS_OK == c_value(Status::ok));
static_assert(DEV_STATUS_EMPTY_INPUT == c_value(Status::empty_input));
static_assert(DEV_STATUS_INDEX_OUT_OF_RANGE == c_value(Status::index_out_of_range));
static_assert(DEV_STATUS_NON_FINITE_COORDINATE == c_value(Status::non_finite_coordinate));
static_assert(DEV_STATUS_DEGENERATE_TRIANGLE == c_value(Status::degenerate_triangle));
static_assert(DEV_STATUS_DUPLICATE_TRIANGLE == c_value(Status::duplicate_triangle));
static_assert(DEV_STATUS_NON_MANIFOLD == c_value(Status::non_manifold));
static_assert(DEV_STATUS_INVALID_ARGUMENT == c_value(Status::invalid_argument));
static_assert(DEV_STATUS_NO_FREE_VERTEX == c_value(Status::no_free_vertex));
static_assert(DEV_STATUS_CANCELLED == c_value(Status::cancelled));
static_assert(DEV_STATUS_NUMERICAL_FAILURE == c_value(Status::numerical_failure));
static_assert(DEV_STATUS_OUT_OF_MEMORY == c_value(Status::out_of_memory));
static_assert(DEV_STATUS_INTERNAL_ERROR == c_value(Status::internal_error));
static_assert(DEV_STATUS_NO_INTERIOR_VERTEX == c_value(Status::no_interior_vertex));
static_assert(DEV_STOP_ALREADY_DEVELOPABLE == c_value(developable::StopReason::already_developable));
static_assert(DEV_STOP_CONVERGED == c_value(developable::StopReason::converged));
static_assert(DEV_STOP_ITERATION_LIMIT == c_value(developable::StopReason::iteration_limit));
static_assert(DEV_STOP_STALLED == c_value(developable::StopReason::stalled));
static_assert(DEV_MODE_REFIT == c_value(developable::Mode::refit));
static_assert(DEV_MODE_PAPER == c_value(developable::Mode::paper));
static_assert(DEV_SEAMS_FREE == c_value(developable::Seams::free));
static_assert(DEV_SEAMS_PINNED == c_value(developable::Seams::pinned));
static_assert(DEV_SOLVER_DECOUPLED == c_value(developable::Formulation::decoupled));
static_assert(DEV_SOLVER_COUPLED == c_value(developable::Formulation::coupled));
static_assert(DEV_RESULT_IMPROVED == c_value(developable::ResultKind::improved));
static_assert(DEV_RESULT_UNCHANGED == c_value(developable::ResultKind::unchanged));
static_assert(DEV_UNCHANGED_NONE == c_value(developable::UnchangedReason::none));
static_assert(DEV_UNCHANGED_ALREADY_DEVELOPABLE == c_value(developable::UnchangedReason::already_developable));
static_assert(DEV_UNCHANGED_DEVELOPABLE_PIECEWISE == c_value(developable::UnchangedReason::developable_piecewise));
static_assert(DEV_UNCHANGED_ALREADY_FLAT == c_value(developable::UnchangedReason::already_flat));
static_assert(DEV_UNCHANGED_NO_VISIBLE_GAIN == c_value(developable::UnchangedReason::no_visible_gain));
static_assert(DEV_UNCHANGED_NO_BETTER_ITERATE == c_value(developable::UnchangedReason::no_better_iterate));
static_assert(DEV_UNCHANGED_REJECTED == c_value(developable::UnchangedReason::rejected));
static_assert(DEV_ORIGIN_INPUT == c_value(developable::ResultOrigin::input));
static_assert(DEV_ORIGIN_DEFORMATION == c_value(developable::ResultOrigin::deformation));
static_assert(DEV_ORIGIN_DEFORMATION_POLISH == c_value(developable::ResultOrigin::deformation_polish));
static_assert(DEV_ORIGIN_NEAR_FLAT_POLISH == c_value(developable::ResultOrigin::near_flat_polish));
static_assert(DEV_ORIGIN_INPUT_POLISH == c_value(developable::ResultOrigin::input_polish));
static_assert(DEV_ORIGIN_SMOOTHED_INPUT_POLISH == c_value(developable::ResultOrigin::smoothed_input_polish));
static_assert(DEV_ORIGIN_SMOOTHED_STEP_POLISH == c_value(developable::ResultOrigin::smoothed_step_polish));
static_assert(DEV_ORIGIN_PROJECTED_INPUT == c_value(developable::ResultOrigin::projected_input));
static_assert(DEV_ORIGIN_THINNED_PIECES == c_value(developable::ResultOrigin::thinned_pieces));
static_assert(DEV_ORIGIN_RULED_FINISH == c_value(developable::ResultOrigin::ruled_finish));
static_assert(DEV_WORSE_MEAN_DEFECT == c_value(developable::worse_mean_defect));
static_assert(DEV_WORSE_MAX_DEFECT == c_value(developable::worse_max_defect));
static_assert(DEV_WORSE_FLAT_SHARE == c_value(developable::worse_flat_share));
static_assert(DEV_WORSE_RULED_SHARE == c_value(developable::worse_ruled_share));
static_assert(DEV_WORSE_TURNED_FACES == c_value(developable::worse_turned_faces));

void write_message(char* message, size_t capacity, const std::string& text) {
  if (message == nullptr || capacity == 0) return;
  const size_t length = std::min(capacity - 1, text.size());
  std::memcpy(message, text.data(), length);
  message[length] = '\0';
}

// Runs `body`, turning every exception into a status and a message.
template <typename Body>
int32_t guarded(char* message, size_t capacity, Body&& body) {
  try {
    body();
    write_message(message, capacity, "ok");
    return DEV_STATUS_OK;
  } catch (const EngineError& e) {
    write_message(message, capacity, e.what());
    return static_cast<int32_t>(e.status());
  } catch (const std::bad_alloc&) {
    write_message(message, capacity, "out of memory: the mesh is too large for this machine");
    return DEV_STATUS_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    write_message(message, capacity, std::string("internal error: ") + e.what());
    return DEV_STATUS_INTERNAL_ERROR;
  } catch (...) {
    write_message(message, capacity, "internal error: unknown exception");
    return DEV_STATUS_INTERNAL_ERROR;
  }
}

void require(bool ok, const char* what) {
  if (!ok) throw EngineError(Status::invalid_argument, what);
}

// Counts as given by the caller, checked before anything is read.
void check_buffers(const double* positions, int64_t n_vertices, const int32_t* triangles, int64_t n_triangles) {
  require(n_vertices >= 0 && n_triangles >= 0, "vertex and triangle counts must not be negative");
  require(n_vertices <= (int64_t{1} << 31) && n_triangles <= (int64_t{1} << 31),
          "the mesh has more than 2^31 vertices or triangles");
  if (n_vertices == 0) throw EngineError(Status::empty_input, "the mesh has no vertices");
  if (n_triangles == 0) throw EngineError(Status::empty_input, "the mesh has no triangles");
  require(positions != nullptr, "positions is a null pointer");
  require(triangles != nullptr, "triangles is a null pointer");
}

developable::Positions copy_positions(const double* data, int64_t n) {
  return Eigen::Map<const developable::Positions>(data, static_cast<Eigen::Index>(n), 3);
}

developable::Triangles copy_triangles(const int32_t* data, int64_t n) {
  return Eigen::Map<const developable::Triangles>(data, static_cast<Eigen::Index>(n), 3);
}

developable::PipelineOptions to_options(const dev_params& p) {
  developable::PipelineOptions o;
  o.omega = p.omega;
  o.tolerance = p.tolerance;
  o.max_iterations = p.max_iterations;
  require(p.mode == DEV_MODE_REFIT || p.mode == DEV_MODE_PAPER, "mode must be DEV_MODE_REFIT or DEV_MODE_PAPER");
  o.mode = p.mode == DEV_MODE_PAPER ? developable::Mode::paper : developable::Mode::refit;
  require(p.solver == DEV_SOLVER_DECOUPLED || p.solver == DEV_SOLVER_COUPLED,
          "solver must be DEV_SOLVER_DECOUPLED or DEV_SOLVER_COUPLED");
  o.solver = p.solver == DEV_SOLVER_COUPLED ? developable::Formulation::coupled : developable::Formulation::decoupled;
  o.pin_boundary = p.pin_boundary != 0;
  o.use_mls_weights = p.use_mls_weights != 0;
  o.stop_relative_change = p.stop_relative_change;
  o.developable_threshold = p.developable_threshold;
  o.segmentation = p.segmentation;
  o.segmentation_options.target_patches = p.target_patches;
  o.segmentation_options.max_fit_error = p.segment_max_error;
  require(p.seams == DEV_SEAMS_FREE || p.seams == DEV_SEAMS_PINNED, "seams must be DEV_SEAMS_FREE or DEV_SEAMS_PINNED");
  o.seams = p.seams == DEV_SEAMS_PINNED ? developable::Seams::pinned : developable::Seams::free;
  o.curve_options.grid_resolution = p.grid_resolution;
  o.target_smoothing = p.target_smoothing;
  o.max_move = p.max_move;
  o.polish = p.polish;
  o.polish_smoothed_input = p.polish_smoothed_input != 0;
  // Not a parameter: the result does not depend on it (tests and benchmarks
  // set it to check that, and servers to share the machine).
  if (const char* threads = std::getenv("DEVELOPABLE_THREADS"); threads != nullptr && *threads != '\0') {
    char* end = nullptr;
    const long count = std::strtol(threads, &end, 10);
    require(*end == '\0' && count >= 0 && count <= 256,
            "DEVELOPABLE_THREADS must be 0 (automatic) or a thread count up to 256");
    o.threads = static_cast<int>(count);
  }
  return o;
}

bool call_progress(double fraction, const char* stage, void* user) {
  auto* callback = static_cast<std::pair<dev_progress_fn, void*>*>(user);
  return callback->first(fraction, stage, callback->second) != 0;
}

template <typename T, typename Source>
int32_t copy_out(const dev_result* result, T* out, int64_t capacity, Source&& source) {
  if (result == nullptr || out == nullptr) return DEV_STATUS_INVALID_ARGUMENT;
  const auto& values = source(result->pipeline);
  const int64_t size = static_cast<int64_t>(values.size());
  if (capacity < size) return DEV_STATUS_INVALID_ARGUMENT;
  std::copy(values.data(), values.data() + size, out);
  return DEV_STATUS_OK;
}

// A string into a fixed char field, truncated to fit, NUL-terminated.
template <size_t N>
void copy_text(char (&out)[N], const std::string& text) {
  std::memset(out, 0, N);
  std::memcpy(out, text.data(), std::min(N - 1, text.size()));
}

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// The unfolding ran on the mesh opened along the cut of its one-sided
// components (orientation.h): its seams name the caller's vertices again, and
// the cut becomes seams of its own, one per run of it between the same two
// pieces, counted as cut edges of its piece. Both faces of such a seam run
// its edges from -> to (a one-sided surface is glued to itself turned over):
// side b's edges do not run the other way round its outline, as a seam's
// usually do.
void rejoin_cut(developable::UnfoldResult& u, const developable::Positions& positions,
                const developable::FaceOrientation& orientation, const developable::OpenedMesh& opened,
                const std::vector<int>& patches) {
  for (auto& seam : u.seams)
    for (auto& edge : seam.edges)
      for (int& v : edge) v = opened.original[static_cast<size_t>(v)];
  const auto flat = [&](int f, int v) -> Eigen::Vector2d {
    const int k = orientation.triangles(f, 0) == v ? 0 : (orientation.triangles(f, 1) == v ? 1 : 2);
    return u.corners.row(3 * f + k).transpose();
  };
  const auto patch_of = [&](int f) { return patches.empty() ? 0 : patches[static_cast<size_t>(f)]; };
  for (const auto& chain : developable::cut_chains(positions, orientation, opened)) {
    size_t seam = u.seams.size();
    for (size_t i = 0; i < chain.edges.size(); ++i) {
      const auto [a, b] = chain.edges[i];
      const auto [fa, fb] = chain.faces[i];
      const int pa = u.piece_of_face[static_cast<size_t>(fa)], pb = u.piece_of_face[static_cast<size_t>(fb)];
      if (seam == u.seams.size() || u.seams[seam].piece_a != pa || u.seams[seam].piece_b != pb) {
        seam = u.seams.size();
        u.seams.emplace_back();
        u.seams[seam].piece_a = pa;
        u.seams[seam].piece_b = pb;
        u.seams[seam].cut = patch_of(fa) == patch_of(fb);
      }
      developable::UnfoldSeam& s = u.seams[seam];
      s.edges.push_back({a, b});
      s.faces.push_back({fa, fb});
      s.length_3d += (positions.row(a) - positions.row(b)).norm();
      s.length_a += (flat(fa, b) - flat(fa, a)).norm();
      s.length_b += (flat(fb, b) - flat(fb, a)).norm();
      if (pa == pb) ++u.pieces[static_cast<size_t>(pa)].cut_edges;
    }
  }
}

}  // namespace

extern "C" {

int32_t dev_abi_version(void) { return DEV_ABI_VERSION; }

const char* dev_version_string(void) { return DEVELOPABLE_VERSION; }

void dev_default_params(dev_params* params) {
  if (params == nullptr) return;
  const developable::PipelineOptions o;
  params->omega = o.omega;
  params->tolerance = o.tolerance;
  params->max_iterations = o.max_iterations;
  params->mode = DEV_MODE_REFIT;
  params->pin_boundary = o.pin_boundary ? 1 : 0;
  params->use_mls_weights = o.use_mls_weights ? 1 : 0;
  params->stop_relative_change = o.stop_relative_change;
  params->developable_threshold = o.developable_threshold;
  params->segmentation = o.segmentation;
  params->target_patches = o.segmentation_options.target_patches;
  params->segment_max_error = o.segmentation_options.max_fit_error;
  params->seams = DEV_SEAMS_FREE;
  params->grid_resolution = o.curve_options.grid_resolution;
  params->solver = o.solver == developable::Formulation::coupled ? DEV_SOLVER_COUPLED : DEV_SOLVER_DECOUPLED;
  params->target_smoothing = o.target_smoothing;
  params->max_move = o.max_move;
  params->polish = o.polish;
  params->polish_smoothed_input = o.polish_smoothed_input ? 1 : 0;
}

int32_t dev_validate(const double* positions, int64_t n_vertices, const int32_t* triangles, int64_t n_triangles,
                     char* message, size_t message_capacity) {
  std::string note;  // what the run will turn (orientation.h)
  const int32_t status = guarded(message, message_capacity, [&] {
    check_buffers(positions, n_vertices, triangles, n_triangles);
    const developable::Positions mesh_positions = copy_positions(positions, n_vertices);
    const developable::Triangles mesh_triangles = copy_triangles(triangles, n_triangles);
    developable::validate_mesh(mesh_positions, mesh_triangles);
    note = developable::orientation_note(developable::orient_faces(mesh_positions, mesh_triangles));
  });
  if (status == DEV_STATUS_OK && !note.empty()) write_message(message, message_capacity, "ok: " + note);
  return status;
}

int32_t dev_run(const double* positions, int64_t n_vertices, const int32_t* triangles, int64_t n_triangles,
                const uint8_t* pinned, const dev_params* params, dev_progress_fn progress, void* user,
                dev_result** result, char* message, size_t message_capacity) {
  if (result != nullptr) *result = nullptr;
  return guarded(message, message_capacity, [&] {
    require(result != nullptr, "result is a null pointer");
    check_buffers(positions, n_vertices, triangles, n_triangles);
    dev_params defaults;
    dev_default_params(&defaults);
    const developable::PipelineOptions options = to_options(params != nullptr ? *params : defaults);
    std::vector<bool> pin_mask;
    if (pinned != nullptr) pin_mask.assign(pinned, pinned + n_vertices);
    std::pair<dev_progress_fn, void*> callback{progress, user};
    const developable::Progress report{progress != nullptr ? call_progress : nullptr, &callback};
    auto owned = std::make_unique<dev_result>();
    // The engine runs on faces turned so that neighbours agree (one-sided and
    // inconsistently wound meshes, orientation.h) and hands the target
    // normals back in the caller's winding. The options and the memory budget
    // are checked first, as run_pipeline does, so that neither costs the
    // turning.
    developable::check_options(options);
    developable::check_memory_budget(n_vertices, n_triangles, options);
    const developable::Positions mesh_positions = copy_positions(positions, n_vertices);
    const developable::FaceOrientation orientation =
        developable::orient_faces(mesh_positions, copy_triangles(triangles, n_triangles));
    // A refusal names the caller's triangles: a turned mesh is checked as given first.
    if (orientation.turned_count > 0)
      developable::validate_mesh(mesh_positions, copy_triangles(triangles, n_triangles));
    owned->pipeline = developable::run_pipeline(mesh_positions, orientation.triangles, pin_mask, options, report);
    developable::to_caller_normals(owned->pipeline.target_normals, orientation.turned);
    owned->orientation_note = developable::orientation_note(orientation);
    *result = owned.release();
  });
}

void dev_result_free(dev_result* result) { delete result; }

int32_t dev_result_stats(const dev_result* result, dev_stats* stats) {
  if (result == nullptr || stats == nullptr) return DEV_STATUS_INVALID_ARGUMENT;
  const auto& s = result->pipeline.stats;
  *stats = dev_stats{};
  stats->vertices = s.vertices;
  stats->faces = s.faces;
  stats->interior_vertices = s.interior_vertices;
  stats->patches = s.patches;
  stats->curves = static_cast<int64_t>(result->pipeline.curves.size());
  stats->iterations = s.iterations;
  stats->stop_reason = static_cast<int32_t>(s.stop_reason);
  stats->average_edge_length = s.average_edge_length;
  stats->mean_defect_before = s.mean_defect_before;
  stats->mean_defect_after = s.mean_defect_after;
  stats->max_defect_before = s.max_defect_before;
  stats->max_defect_after = s.max_defect_after;
  stats->change_percent = s.change_percent;
  stats->max_vertex_move = s.max_vertex_move;
  stats->time_decompose_ms = s.time_decompose_ms;
  stats->time_iterate_ms = s.time_iterate_ms;
  stats->time_total_ms = s.time_total_ms;
  stats->result = static_cast<int32_t>(s.result);
  stats->faces_turned_over = static_cast<int64_t>(s.faces_turned_over);
  stats->flat_share_before = s.flat_share_before;
  stats->flat_share_after = s.flat_share_after;
  stats->polish_iterations = s.polish_iterations;
  stats->time_polish_ms = s.time_polish_ms;
  stats->unchanged_reason = static_cast<int32_t>(s.unchanged_reason);
  stats->result_origin = static_cast<int32_t>(s.origin);
  stats->worse_figures = s.worse_figures;
  stats->ruled_share_before = s.shares_before.ruled;
  stats->ruled_share_after = s.shares_after.ruled;
  stats->crumpled_share_before = s.shares_before.crumpled;
  stats->crumpled_share_after = s.shares_after.crumpled;
  stats->move_limit = s.move_limit;
  stats->flat_threshold = developable::kFlatDefect;
  stats->ruled_threshold = developable::kRuledSpread;
  copy_text(stats->result_message, s.result_message);
  copy_text(stats->orientation_note, result->orientation_note);
  return DEV_STATUS_OK;
}

int32_t dev_result_positions(const dev_result* result, double* out, int64_t capacity) {
  return copy_out(
      result, out, capacity, [](const auto& r) -> const auto& { return r.positions; });
}

int32_t dev_result_defect_before(const dev_result* result, double* out, int64_t capacity) {
  return copy_out(
      result, out, capacity, [](const auto& r) -> const auto& { return r.defect_before; });
}

int32_t dev_result_defect_after(const dev_result* result, double* out, int64_t capacity) {
  return copy_out(
      result, out, capacity, [](const auto& r) -> const auto& { return r.defect_after; });
}

int32_t dev_result_interior(const dev_result* result, uint8_t* out, int64_t capacity) {
  if (result == nullptr || out == nullptr) return DEV_STATUS_INVALID_ARGUMENT;
  const auto& interior = result->pipeline.interior;
  if (capacity < static_cast<int64_t>(interior.size())) return DEV_STATUS_INVALID_ARGUMENT;
  for (size_t v = 0; v < interior.size(); ++v) out[v] = interior[v] ? 1 : 0;
  return DEV_STATUS_OK;
}

int32_t dev_result_target_normals(const dev_result* result, double* out, int64_t capacity) {
  return copy_out(
      result, out, capacity, [](const auto& r) -> const auto& { return r.target_normals; });
}

int32_t dev_result_patch_ids(const dev_result* result, int32_t* out, int64_t capacity) {
  return copy_out(
      result, out, capacity, [](const auto& r) -> const auto& { return r.patch_ids; });
}

int64_t dev_result_curve_count(const dev_result* result) {
  return result == nullptr ? 0 : static_cast<int64_t>(result->pipeline.curves.size());
}

int32_t dev_result_curve_info(const dev_result* result, int64_t index, int64_t* n_points, int32_t* patch,
                              int32_t* closed) {
  if (result == nullptr || index < 0 || index >= dev_result_curve_count(result)) return DEV_STATUS_INVALID_ARGUMENT;
  const auto& curve = result->pipeline.curves[static_cast<size_t>(index)];
  if (n_points != nullptr) *n_points = static_cast<int64_t>(curve.curve.points.size());
  if (patch != nullptr) *patch = curve.patch;
  if (closed != nullptr) *closed = curve.curve.closed ? 1 : 0;
  return DEV_STATUS_OK;
}

int32_t dev_result_curve_points(const dev_result* result, int64_t index, double* out, int64_t capacity) {
  if (result == nullptr || out == nullptr || index < 0 || index >= dev_result_curve_count(result))
    return DEV_STATUS_INVALID_ARGUMENT;
  const auto& points = result->pipeline.curves[static_cast<size_t>(index)].curve.points;
  if (capacity < 3 * static_cast<int64_t>(points.size())) return DEV_STATUS_INVALID_ARGUMENT;
  for (size_t i = 0; i < points.size(); ++i)
    for (int axis = 0; axis < 3; ++axis) out[3 * i + axis] = points[i][axis];
  return DEV_STATUS_OK;
}

void dev_default_pattern_params(dev_pattern_params* params) {
  if (params == nullptr) return;
  const developable::LayoutOptions layout;
  const developable::UnfoldOptions unfold;
  *params = dev_pattern_params{};
  params->sheet_width_mm = layout.sheet_width;
  params->sheet_height_mm = layout.sheet_height;
  params->margin_mm = layout.margin;
  params->spacing_mm = layout.spacing;
  params->scale = layout.scale;
  params->unit_mm = layout.unit_mm;
  params->seam_tolerance = unfold.seam_tolerance;
  params->arap_iterations = unfold.arap_iterations;
  params->layout = 1;
  std::memcpy(params->unit_name, layout.unit_name.c_str(), layout.unit_name.size() + 1);
  params->svg_path = nullptr;
  params->face_groups = nullptr;
  params->seam_allowance_mm = layout.seam_allowance;
  params->glue_tabs_mm = layout.glue_tabs;
}

int32_t dev_unfold(const double* positions, int64_t n_vertices, const int32_t* triangles, int64_t n_triangles,
                   const int32_t* patch_ids, const dev_pattern_params* params, dev_progress_fn progress, void* user,
                   dev_pattern** result, char* message, size_t message_capacity) {
  if (result != nullptr) *result = nullptr;
  return guarded(message, message_capacity, [&] {
    const auto start = std::chrono::steady_clock::now();
    require(result != nullptr, "result is a null pointer");
    check_buffers(positions, n_vertices, triangles, n_triangles);
    dev_pattern_params p;
    dev_default_pattern_params(&p);
    if (params != nullptr) p = *params;
    require(std::memchr(p.unit_name, 0, sizeof p.unit_name) != nullptr, "unit_name is not NUL-terminated");
    const developable::Positions mesh_positions = copy_positions(positions, n_vertices);
    const developable::Triangles mesh_triangles = copy_triangles(triangles, n_triangles);
    developable::validate_mesh(mesh_positions, mesh_triangles);
    // Unfolded on faces turned so that neighbours agree, and on a one-sided
    // mesh opened along its cut (orientation.h); the corners go back to the
    // caller's order in the accessors.
    const developable::FaceOrientation orientation = developable::orient_faces(mesh_positions, mesh_triangles);
    const developable::OpenedMesh opened = developable::open_along_cut(mesh_positions, orientation);
    std::vector<int> patches;
    if (patch_ids != nullptr) patches.assign(patch_ids, patch_ids + n_triangles);
    std::vector<int> groups;
    if (p.face_groups != nullptr) groups.assign(p.face_groups, p.face_groups + n_triangles);
    developable::UnfoldOptions unfold_options;
    unfold_options.arap_iterations = p.arap_iterations;
    unfold_options.seam_tolerance = p.seam_tolerance;
    developable::LayoutOptions layout_options;
    layout_options.sheet_width = p.sheet_width_mm;
    layout_options.sheet_height = p.sheet_height_mm;
    layout_options.margin = p.margin_mm;
    layout_options.spacing = p.spacing_mm;
    layout_options.scale = p.scale;
    layout_options.unit_mm = p.unit_mm;
    layout_options.unit_name = p.unit_name;
    layout_options.seam_allowance = p.seam_allowance_mm;
    layout_options.glue_tabs = p.glue_tabs_mm;
    const bool write_svg = p.svg_path != nullptr && p.svg_path[0] != '\0';
    require(p.layout != 0 || !write_svg, "svg_path needs layout");

    std::pair<dev_progress_fn, void*> callback{progress, user};
    const developable::Progress report{progress != nullptr ? call_progress : nullptr, &callback};
    report.report(0.0, "unfolding");
    auto owned = std::make_unique<dev_pattern>();
    owned->unfolded =
        developable::unfold(opened.positions, opened.triangles, patches, unfold_options, groups, report.sub(0.0, 0.8));
    rejoin_cut(owned->unfolded, mesh_positions, orientation, opened, patches);
    owned->turned = orientation.turned;
    dev_pattern_stats& st = owned->stats;
    st.time_unfold_ms = elapsed_ms(start);
    const auto layout_start = std::chrono::steady_clock::now();
    if (p.layout != 0) {
      owned->layout =
          developable::layout_pattern(owned->unfolded, orientation.triangles, layout_options, report.sub(0.8, 1.0));
      owned->laid_out = true;
      if (write_svg) owned->files = developable::write_pattern_svg(owned->layout, owned->unfolded, p.svg_path);
    }
    st.time_layout_ms = elapsed_ms(layout_start);
    const auto& u = owned->unfolded;
    st.faces = n_triangles;
    st.pieces = static_cast<int64_t>(u.pieces.size());
    st.sheets = owned->laid_out ? owned->layout.sheets : 0;
    st.seams = static_cast<int64_t>(u.seams.size());
    st.splits = u.split_count;
    st.svg_files = static_cast<int64_t>(owned->files.size());
    if (owned->laid_out) {
      for (const auto& piece : owned->layout.pieces) st.cut_lines_from_hull += piece.cut_line_from_hull ? 1 : 0;
      st.glue_tabs = owned->layout.glue_tabs;
      st.glue_tabs_dropped = owned->layout.glue_tabs_dropped;
    }
    double strain_sum = 0.0;
    for (const auto& piece : u.pieces) {
      st.cut_edges += piece.cut_edges;
      st.max_strain = std::max(st.max_strain, piece.max_strain);
      st.max_area_change = std::max(st.max_area_change, std::abs(piece.area_change));
      strain_sum += piece.mean_strain * static_cast<double>(piece.faces);
    }
    st.mean_strain = strain_sum / static_cast<double>(n_triangles);
    st.scale = owned->laid_out ? owned->layout.options.scale : 0.0;
    st.time_total_ms = elapsed_ms(start);
    report.report(1.0, "done");
    *result = owned.release();
  });
}

void dev_pattern_free(dev_pattern* pattern) { delete pattern; }

int32_t dev_pattern_stats_get(const dev_pattern* pattern, dev_pattern_stats* stats) {
  if (pattern == nullptr || stats == nullptr) return DEV_STATUS_INVALID_ARGUMENT;
  *stats = pattern->stats;
  return DEV_STATUS_OK;
}

int32_t dev_pattern_corner_uvs(const dev_pattern* pattern, double* out, int64_t capacity) {
  if (pattern == nullptr || out == nullptr) return DEV_STATUS_INVALID_ARGUMENT;
  if (capacity < static_cast<int64_t>(pattern->unfolded.corners.size())) return DEV_STATUS_INVALID_ARGUMENT;
  const auto c = developable::to_caller_corners(pattern->unfolded.corners, pattern->turned);
  std::copy(c.data(), c.data() + c.size(), out);
  return DEV_STATUS_OK;
}

int32_t dev_pattern_sheet_uvs(const dev_pattern* pattern, double* out, int64_t capacity) {
  if (pattern == nullptr || out == nullptr || !pattern->laid_out) return DEV_STATUS_INVALID_ARGUMENT;
  if (capacity < static_cast<int64_t>(pattern->layout.corners.size())) return DEV_STATUS_INVALID_ARGUMENT;
  const auto c = developable::to_caller_corners(pattern->layout.corners, pattern->turned);
  std::copy(c.data(), c.data() + c.size(), out);
  return DEV_STATUS_OK;
}

int32_t dev_pattern_piece_ids(const dev_pattern* pattern, int32_t* out, int64_t capacity) {
  if (pattern == nullptr || out == nullptr) return DEV_STATUS_INVALID_ARGUMENT;
  const auto& ids = pattern->unfolded.piece_of_face;
  if (capacity < static_cast<int64_t>(ids.size())) return DEV_STATUS_INVALID_ARGUMENT;
  std::copy(ids.begin(), ids.end(), out);
  return DEV_STATUS_OK;
}

int32_t dev_pattern_face_strain(const dev_pattern* pattern, double* out, int64_t capacity) {
  if (pattern == nullptr || out == nullptr) return DEV_STATUS_INVALID_ARGUMENT;
  const auto& s = pattern->unfolded.face_strain;
  if (capacity < static_cast<int64_t>(s.size())) return DEV_STATUS_INVALID_ARGUMENT;
  std::copy(s.data(), s.data() + s.size(), out);
  return DEV_STATUS_OK;
}

int32_t dev_pattern_piece_get(const dev_pattern* pattern, int64_t index, dev_pattern_piece* piece) {
  if (pattern == nullptr || piece == nullptr || index < 0 ||
      index >= static_cast<int64_t>(pattern->unfolded.pieces.size()))
    return DEV_STATUS_INVALID_ARGUMENT;
  const auto& p = pattern->unfolded.pieces[static_cast<size_t>(index)];
  *piece = dev_pattern_piece{};
  piece->patch = p.patch;
  piece->sheet = pattern->laid_out ? pattern->layout.pieces[static_cast<size_t>(index)].sheet : -1;
  piece->faces = p.faces;
  piece->cut_edges = p.cut_edges;
  piece->splits = p.splits;
  piece->max_strain = p.max_strain;
  piece->mean_strain = p.mean_strain;
  piece->area_3d = p.area_3d;
  piece->area_flat = p.area_flat;
  piece->area_change = p.area_change;
  piece->outline_length = p.outline_length;
  if (pattern->laid_out) {
    piece->width_mm = pattern->layout.pieces[static_cast<size_t>(index)].size.x();
    piece->height_mm = pattern->layout.pieces[static_cast<size_t>(index)].size.y();
  }
  copy_text(piece->label, developable::piece_label(static_cast<int>(index)));
  return DEV_STATUS_OK;
}

int32_t dev_pattern_seam_get(const dev_pattern* pattern, int64_t index, dev_pattern_seam* seam) {
  if (pattern == nullptr || seam == nullptr || index < 0 ||
      index >= static_cast<int64_t>(pattern->unfolded.seams.size()))
    return DEV_STATUS_INVALID_ARGUMENT;
  const auto& s = pattern->unfolded.seams[static_cast<size_t>(index)];
  *seam = dev_pattern_seam{};
  seam->piece_a = s.piece_a;
  seam->piece_b = s.piece_b;
  seam->cut = s.cut ? 1 : 0;
  seam->edges = static_cast<int64_t>(s.edges.size());
  seam->length_3d = s.length_3d;
  seam->length_a = s.length_a;
  seam->length_b = s.length_b;
  copy_text(seam->label, std::to_string(index + 1));
  return DEV_STATUS_OK;
}

int32_t dev_pattern_seam_edges(const dev_pattern* pattern, int64_t index, int32_t* out, int64_t capacity) {
  if (pattern == nullptr || out == nullptr || index < 0 ||
      index >= static_cast<int64_t>(pattern->unfolded.seams.size()))
    return DEV_STATUS_INVALID_ARGUMENT;
  const auto& edges = pattern->unfolded.seams[static_cast<size_t>(index)].edges;
  if (capacity < 2 * static_cast<int64_t>(edges.size())) return DEV_STATUS_INVALID_ARGUMENT;
  for (size_t i = 0; i < edges.size(); ++i) out[2 * i] = edges[i][0], out[2 * i + 1] = edges[i][1];
  return DEV_STATUS_OK;
}

int32_t dev_pattern_svg_file(const dev_pattern* pattern, int64_t index, char* out, int64_t capacity) {
  if (pattern == nullptr || out == nullptr || index < 0 || index >= static_cast<int64_t>(pattern->files.size()))
    return DEV_STATUS_INVALID_ARGUMENT;
  const std::string& path = pattern->files[static_cast<size_t>(index)];
  if (capacity < static_cast<int64_t>(path.size()) + 1) return DEV_STATUS_INVALID_ARGUMENT;
  std::memcpy(out, path.c_str(), path.size() + 1);
  return DEV_STATUS_OK;
}

}  // extern "C"
