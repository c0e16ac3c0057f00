// libFuzzer target over the engine's C ABI (native/developable.h).
//
// The input bytes are decoded into one call of dev_validate and dev_run:
// vertex/triangle counts, positions (finite, NaN, Inf, huge, tiny, denormal),
// indices (in range, negative, past the end), a pin mask, every dev_params
// field (valid and out of range) and a progress callback that cancels after a
// fuzzed number of reports. Two mesh shapes:
//   raw   every number straight from the bytes (mostly refused by the input
//         check: exercises mesh_input.cpp and c_api.cpp);
//   grid  a small grid surface whose heights, scale and a few edits come from
//         the bytes (mostly valid: reaches segmentation, the ideal curves and
//         the deformation).
// The contract checked on every input (a violation calls abort(), which
// libFuzzer reports as a crash and saves):
//   - the status is one of DEV_STATUS_*, the message NUL-terminated and never
//     longer than its buffer, and *result is non-NULL exactly on OK;
//   - on OK every accessor works, every position is finite, pinned vertices
//     keep their input bits, the figures are finite, and the run's note on
//     what it turned is the input check's "ok: ..." message.
// ASan/UBSan (the fuzz build has both) catch the memory and UB errors.
//
// Built by -DDEVELOPABLE_FUZZ=ON with clang (CMakeLists.txt); run by
// scripts/fuzz.sh; the corpus lives in tests/fuzz_corpus/.
#include "api/developable.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

[[noreturn]] void contract_violation(const char* what) {
  std::fprintf(stderr, "fuzz_c_api: contract violated: %s\n", what);
  std::abort();
}

void require(bool ok, const char* what) {
  if (!ok) contract_violation(what);
}

double fuzzed_coordinate(FuzzedDataProvider& data) {
  switch (data.ConsumeIntegralInRange<int>(0, 15)) {
    case 0:
      return std::numeric_limits<double>::quiet_NaN();
    case 1:
      return std::numeric_limits<double>::infinity();
    case 2:
      return -std::numeric_limits<double>::infinity();
    case 3:
      return std::numeric_limits<double>::max();
    case 4:
      return std::numeric_limits<double>::denorm_min();
    case 5:
      return data.ConsumeFloatingPoint<double>();  // anything, incl. huge
    case 6:
      return 1e12 * data.ConsumeFloatingPointInRange<double>(-1.0, 1.0);
    case 7:
      return 1e-12 * data.ConsumeFloatingPointInRange<double>(-1.0, 1.0);
    default:
      return data.ConsumeFloatingPointInRange<double>(-4.0, 4.0);
  }
}

// Parameters are wild (anything, incl. out of range) in one input of four;
// otherwise within their valid ranges, so that most runs get past the checks.
bool wild_parameters = false;

double fuzzed_parameter(FuzzedDataProvider& data, double usual_low, double usual_high) {
  if (!wild_parameters) {
    if (data.ConsumeBool()) return std::pow(10.0, data.ConsumeFloatingPointInRange<double>(-12.0, 12.0));
    return data.ConsumeFloatingPointInRange<double>(usual_low, usual_high);
  }
  switch (data.ConsumeIntegralInRange<int>(0, 9)) {
    case 0:
      return std::numeric_limits<double>::quiet_NaN();
    case 1:
      return std::numeric_limits<double>::infinity();
    case 2:
      return -data.ConsumeFloatingPointInRange<double>(0.0, 10.0);
    case 3:
      return 0.0;
    case 4:
      return data.ConsumeFloatingPoint<double>();
    case 5:
      return std::pow(10.0, data.ConsumeFloatingPointInRange<double>(-12.0, 12.0));
    default:
      return data.ConsumeFloatingPointInRange<double>(usual_low, usual_high);
  }
}

int32_t fuzzed_choice(FuzzedDataProvider& data, int32_t low, int32_t high) {
  // Mostly valid values, sometimes anything.
  if (wild_parameters && data.ConsumeIntegralInRange<int>(0, 3) == 0) return data.ConsumeIntegral<int32_t>();
  return data.ConsumeIntegralInRange<int32_t>(low, high);
}

void fuzz_params(FuzzedDataProvider& data, dev_params& p) {
  dev_default_params(&p);
  wild_parameters = data.ConsumeIntegralInRange<int>(0, 3) == 0;
  // Keep runs short: few iterations and a coarse effect-field grid, so that
  // libFuzzer gets through many inputs a second.
  p.max_iterations = fuzzed_choice(data, 1, 4);
  p.grid_resolution = fuzzed_choice(data, 16, 40);
  if (data.ConsumeBool()) p.omega = fuzzed_parameter(data, 0.1, 50.0);
  if (data.ConsumeBool()) p.tolerance = fuzzed_parameter(data, -1.0, 20.0);
  if (data.ConsumeBool()) p.mode = fuzzed_choice(data, 0, 1);
  if (data.ConsumeBool()) p.solver = fuzzed_choice(data, 0, 1);
  if (data.ConsumeBool()) p.pin_boundary = data.ConsumeIntegral<int32_t>();
  if (data.ConsumeBool()) p.use_mls_weights = data.ConsumeIntegral<int32_t>();
  if (data.ConsumeBool()) p.stop_relative_change = fuzzed_parameter(data, 0.0, 0.1);
  if (data.ConsumeBool()) p.developable_threshold = fuzzed_parameter(data, 0.0, 0.1);
  if (data.ConsumeBool()) p.segmentation = fuzzed_choice(data, -1, 1);
  if (data.ConsumeBool()) p.target_smoothing = fuzzed_choice(data, -1, 3);
  if (data.ConsumeBool()) p.target_patches = fuzzed_choice(data, 0, 6);
  if (data.ConsumeBool()) p.segment_max_error = fuzzed_parameter(data, 0.0, 0.5);
  if (data.ConsumeBool()) p.seams = fuzzed_choice(data, 0, 1);
}

struct Mesh {
  std::vector<double> positions;
  std::vector<int32_t> triangles;
  int64_t vertex_count() const { return static_cast<int64_t>(positions.size() / 3); }
  int64_t triangle_count() const { return static_cast<int64_t>(triangles.size() / 3); }
};

Mesh raw_mesh(FuzzedDataProvider& data) {
  Mesh m;
  const int vertices = data.ConsumeIntegralInRange<int>(0, 40);
  const int triangles = data.ConsumeIntegralInRange<int>(0, 60);
  for (int i = 0; i < 3 * vertices; ++i) m.positions.push_back(fuzzed_coordinate(data));
  for (int i = 0; i < 3 * triangles; ++i) {
    const int kind = data.ConsumeIntegralInRange<int>(0, 15);
    if (kind == 0)
      m.triangles.push_back(data.ConsumeIntegral<int32_t>());
    else
      m.triangles.push_back(data.ConsumeIntegralInRange<int32_t>(-1, vertices));
  }
  return m;
}

// A rows x cols grid (rows, cols >= 2) bent by fuzzed heights, optionally
// closed into a band, at a fuzzed scale, with a few fuzzed edits.
Mesh grid_mesh(FuzzedDataProvider& data) {
  Mesh m;
  const int rows = data.ConsumeIntegralInRange<int>(2, 9);
  const int cols = data.ConsumeIntegralInRange<int>(2, 12);
  const bool band = cols >= 3 && data.ConsumeBool();
  const double scale = std::pow(10.0, data.ConsumeIntegralInRange<int>(-13, 13));
  const double curl = data.ConsumeFloatingPointInRange<double>(-1.0, 1.0);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      double x, y, z;
      if (band) {
        const double t = 2.0 * M_PI * j / cols;
        const double r = 1.0 + 0.3 * data.ConsumeFloatingPointInRange<double>(-1.0, 1.0);
        x = r * std::cos(t);
        y = r * std::sin(t);
        z = 0.3 * i;
      } else {
        x = j + 0.3 * data.ConsumeFloatingPointInRange<double>(-1.0, 1.0);
        y = i + 0.3 * data.ConsumeFloatingPointInRange<double>(-1.0, 1.0);
        z = curl * (x * x + 0.5 * y * y) / 4.0 + data.ConsumeFloatingPointInRange<double>(-0.5, 0.5);
      }
      m.positions.insert(m.positions.end(), {scale * x, scale * y, scale * z});
    }
  }
  const int span = band ? cols : cols - 1;
  for (int i = 0; i + 1 < rows; ++i) {
    for (int j = 0; j < span; ++j) {
      const int a = i * cols + j, b = i * cols + (j + 1) % cols;
      const int c = (i + 1) * cols + j, d = (i + 1) * cols + (j + 1) % cols;
      if (data.ConsumeBool())
        m.triangles.insert(m.triangles.end(), {a, b, d, a, d, c});
      else
        m.triangles.insert(m.triangles.end(), {a, b, c, b, d, c});
    }
  }
  // A few edits: move a vertex anywhere (incl. NaN), rewrite an index,
  // flip a triangle, duplicate a triangle, drop the last triangle, add a
  // loose vertex.
  const int edits = data.ConsumeIntegralInRange<int>(0, 3);
  for (int e = 0; e < edits && !m.triangles.empty(); ++e) {
    const size_t t = data.ConsumeIntegralInRange<size_t>(0, m.triangles.size() / 3 - 1);
    switch (data.ConsumeIntegralInRange<int>(0, 5)) {
      case 0:
        m.positions[data.ConsumeIntegralInRange<size_t>(0, m.positions.size() - 1)] = fuzzed_coordinate(data);
        break;
      case 1:
        m.triangles[3 * t + data.ConsumeIntegralInRange<size_t>(0, 2)] =
            data.ConsumeIntegralInRange<int32_t>(-2, static_cast<int32_t>(m.vertex_count()) + 1);
        break;
      case 2:
        std::swap(m.triangles[3 * t + 1], m.triangles[3 * t + 2]);
        break;
      case 3:
        m.triangles.insert(m.triangles.end(), m.triangles.begin() + 3 * t, m.triangles.begin() + 3 * t + 3);
        break;
      case 4:
        m.triangles.resize(m.triangles.size() - 3);
        break;
      default:
        m.positions.insert(m.positions.end(), {0.5 * scale, 0.5 * scale, 9.0 * scale});
        break;
    }
  }
  return m;
}

struct Cancel {
  int limit;  // reports answered "go on" before the callback says stop; < 0 never
  int calls = 0;
  bool asked = false;
};

int progress(double fraction, const char* stage, void* user) {
  auto* c = static_cast<Cancel*>(user);
  require(stage != nullptr && std::strlen(stage) < 200, "progress stage is not a short string");
  require(fraction >= 0.0 && fraction <= 1.0, "progress fraction outside [0, 1]");
  require(!c->asked, "progress reported again after the callback said stop");
  if (c->limit >= 0 && c->calls >= c->limit) {
    c->asked = true;
    return 0;
  }
  ++c->calls;
  return 1;
}

// The engine's own score of a result (native/pipeline.cpp, IterateScore): the
// mean |defect| over the interior vertices; on a segmented mesh in the refit
// mode (`piecewise`) the median over the interior vertices that are not on a
// seam (all interior vertices when every one is on a seam).
double score(const std::vector<double>& defects, const std::vector<uint8_t>& interior,
             const std::vector<int32_t>& patch_ids, const Mesh& m, bool piecewise) {
  std::vector<uint8_t> scored = interior;
  if (piecewise) {
    std::vector<int32_t> first(defects.size(), -1);
    std::vector<uint8_t> seam(defects.size(), 0);
    for (size_t f = 0; f < patch_ids.size(); ++f) {
      for (int c = 0; c < 3; ++c) {
        const auto v = static_cast<size_t>(m.triangles[3 * f + static_cast<size_t>(c)]);
        if (first[v] < 0)
          first[v] = patch_ids[f];
        else if (first[v] != patch_ids[f])
          seam[v] = 1;
      }
    }
    std::vector<uint8_t> inside(scored.size());
    bool any = false;
    for (size_t v = 0; v < scored.size(); ++v) any |= (inside[v] = scored[v] && !seam[v]) != 0;
    if (any) scored = inside;
  }
  std::vector<double> values;
  for (size_t v = 0; v < defects.size(); ++v)
    if (scored[v]) values.push_back(std::abs(defects[v]));
  if (values.empty()) return 0.0;
  if (!piecewise) {
    double sum = 0.0;
    for (double x : values) sum += x;
    return sum / static_cast<double>(values.size());
  }
  auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

bool known_status(int32_t s) { return s >= DEV_STATUS_OK && s <= DEV_STATUS_NO_INTERIOR_VERTEX; }

void check_message(const char* message, size_t capacity) {
  require(std::memchr(message, '\0', capacity) != nullptr, "message is not NUL-terminated");
}

void check_result(const dev_result* result, const Mesh& m, const std::vector<uint8_t>& pins, bool paper_mode) {
  dev_stats s;
  require(dev_result_stats(result, &s) == DEV_STATUS_OK, "dev_result_stats failed");
  require(s.vertices == m.vertex_count() && s.faces == m.triangle_count(), "stats counts differ");
  for (double v : {s.average_edge_length, s.mean_defect_before, s.mean_defect_after, s.max_defect_before,
                   s.max_defect_after, s.change_percent, s.max_vertex_move})
    require(std::isfinite(v), "a figure in dev_stats is not finite");
  std::vector<double> positions(m.positions.size());
  require(dev_result_positions(result, positions.data(), static_cast<int64_t>(positions.size())) == DEV_STATUS_OK,
          "dev_result_positions failed");
  for (double v : positions) require(std::isfinite(v), "a result position is not finite");
  for (size_t v = 0; v < pins.size(); ++v) {
    if (pins[v])
      require(std::memcmp(&positions[3 * v], &m.positions[3 * v], 3 * sizeof(double)) == 0, "a pinned vertex moved");
  }
  std::vector<double> defect_before(static_cast<size_t>(m.vertex_count()));
  std::vector<double> defect_after(static_cast<size_t>(m.vertex_count()));
  require(dev_result_defect_before(result, defect_before.data(), m.vertex_count()) == DEV_STATUS_OK,
          "dev_result_defect_before failed");
  require(dev_result_defect_after(result, defect_after.data(), m.vertex_count()) == DEV_STATUS_OK,
          "dev_result_defect_after failed");
  for (double v : defect_before) require(std::isfinite(v), "a defect is not finite");
  for (double v : defect_after) require(std::isfinite(v), "a defect is not finite");
  std::vector<uint8_t> interior(static_cast<size_t>(m.vertex_count()));
  require(dev_result_interior(result, interior.data(), m.vertex_count()) == DEV_STATUS_OK,
          "dev_result_interior failed");
  std::vector<double> normals(static_cast<size_t>(3 * m.triangle_count()));
  require(dev_result_target_normals(result, normals.data(), 3 * m.triangle_count()) == DEV_STATUS_OK,
          "dev_result_target_normals failed");
  std::vector<int32_t> patches(static_cast<size_t>(m.triangle_count()));
  require(dev_result_patch_ids(result, patches.data(), m.triangle_count()) == DEV_STATUS_OK,
          "dev_result_patch_ids failed");
  for (int32_t p : patches) require(p >= 0 && p < s.patches, "patch id out of range");
  // Never worse than the input, by the engine's score.
  const bool piecewise = s.patches > 1 && !paper_mode;
  require(score(defect_after, interior, patches, m, piecewise) <= score(defect_before, interior, patches, m, piecewise),
          "the result is worse than the input");
  // Too small a buffer is refused, not overrun.
  if (!positions.empty())
    require(dev_result_positions(result, positions.data(), static_cast<int64_t>(positions.size()) - 1) ==
                DEV_STATUS_INVALID_ARGUMENT,
            "a short buffer was accepted");
  const int64_t curves = dev_result_curve_count(result);
  require(curves == s.curves, "curve count differs from the stats");
  for (int64_t c = 0; c < curves; ++c) {
    int64_t count = -1;
    int32_t patch = -1, closed = -1;
    require(dev_result_curve_info(result, c, &count, &patch, &closed) == DEV_STATUS_OK, "dev_result_curve_info failed");
    require(count >= 0 && patch >= 0 && patch < s.patches, "bad curve info");
    std::vector<double> points(static_cast<size_t>(3 * count) + 1);
    require(dev_result_curve_points(result, c, points.data(), 3 * count) == DEV_STATUS_OK,
            "dev_result_curve_points failed");
    for (int64_t i = 0; i < 3 * count; ++i) require(std::isfinite(points[i]), "curve point not finite");
  }
  require(dev_result_curve_info(result, curves, nullptr, nullptr, nullptr) == DEV_STATUS_INVALID_ARGUMENT,
          "curve index past the end accepted");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* bytes, size_t size) {
  FuzzedDataProvider data(bytes, size);
  const int shape = data.ConsumeIntegralInRange<int>(0, 3);
  Mesh m = shape == 0 ? raw_mesh(data) : grid_mesh(data);

  std::vector<uint8_t> pins;
  if (data.ConsumeBool()) {
    pins.resize(static_cast<size_t>(m.vertex_count()));
    const int density = data.ConsumeIntegralInRange<int>(0, 4);  // 4: every vertex
    for (auto& p : pins) p = density == 4 || data.ConsumeIntegralInRange<int>(0, 7) < density;
  }
  dev_params params;
  fuzz_params(data, params);
  const bool default_params = data.ConsumeIntegralInRange<int>(0, 7) == 0;
  Cancel cancel{data.ConsumeBool() ? data.ConsumeIntegralInRange<int>(0, 12) : -1};
  const bool with_progress = data.ConsumeIntegralInRange<int>(0, 3) != 0;
  const size_t capacity = data.ConsumeIntegralInRange<size_t>(1, 300);

  // Counts as given, except that a caller may lie downward (never upward:
  // that would be the caller reading past its own buffer).
  int64_t n_vertices = m.vertex_count();
  int64_t n_triangles = m.triangle_count();
  if (data.ConsumeIntegralInRange<int>(0, 15) == 0) n_vertices = data.ConsumeIntegralInRange<int64_t>(-2, n_vertices);
  if (data.ConsumeIntegralInRange<int>(0, 15) == 0) n_triangles = data.ConsumeIntegralInRange<int64_t>(-2, n_triangles);
  const double* positions = m.positions.empty() ? nullptr : m.positions.data();
  const int32_t* triangles = m.triangles.empty() ? nullptr : m.triangles.data();

  std::vector<char> message(capacity + 1, 'x');
  message[capacity] = '#';  // canary just past the buffer the engine gets
  const int32_t checked = dev_validate(positions, n_vertices, triangles, n_triangles, message.data(), capacity);
  require(known_status(checked), "dev_validate returned an unknown status");
  check_message(message.data(), capacity);
  require(message[capacity] == '#', "dev_validate wrote past the message buffer");
  const std::string checked_message(message.data());

  dev_result* result = reinterpret_cast<dev_result*>(&cancel);  // must be overwritten
  std::fill(message.begin(), message.end() - 1, 'x');
  const int32_t status = dev_run(positions, n_vertices, triangles, n_triangles, pins.empty() ? nullptr : pins.data(),
                                 default_params ? nullptr : &params, with_progress ? progress : nullptr, &cancel,
                                 &result, message.data(), capacity);
  require(known_status(status), "dev_run returned an unknown status");
  check_message(message.data(), capacity);
  require(message[capacity] == '#', "dev_run wrote past the message buffer");
  if (std::getenv("FUZZ_VERBOSE") != nullptr)
    std::fprintf(stderr,
                 "v=%lld t=%lld validate=%d run=%d: %s\n  params%s: omega %g tolerance %g iterations %d "
                 "mode %d solver %d pin_boundary %d mls %d stop %g threshold %g segmentation %d "
                 "patches %d segment_error %g seams %d grid %d smoothing %d\n",
                 static_cast<long long>(n_vertices), static_cast<long long>(n_triangles), checked, status,
                 message.data(), default_params ? " (unused: defaults)" : "", params.omega, params.tolerance,
                 params.max_iterations, params.mode, params.solver, params.pin_boundary, params.use_mls_weights,
                 params.stop_relative_change, params.developable_threshold, params.segmentation, params.target_patches,
                 params.segment_max_error, params.seams, params.grid_resolution, params.target_smoothing);
  require(status != DEV_STATUS_INTERNAL_ERROR, "dev_run reported an internal error");
  // A mesh the input check refuses is refused by dev_run with the same code
  // (unless a parameter or the pin mask was refused first).
  if (checked != DEV_STATUS_OK && status != DEV_STATUS_INVALID_ARGUMENT && status != DEV_STATUS_CANCELLED)
    require(status == checked, "dev_run and dev_validate disagree");
  if (status == DEV_STATUS_OK) {
    require(result != nullptr, "OK without a result");
    require(!cancel.asked, "the run ignored a cancel");
    require(checked == DEV_STATUS_OK, "dev_run accepted a mesh dev_validate refused");
    std::vector<uint8_t> used_pins = pins;
    used_pins.resize(static_cast<size_t>(std::max<int64_t>(n_vertices, 0)));
    Mesh used = m;
    used.positions.resize(static_cast<size_t>(3 * n_vertices));
    used.triangles.resize(static_cast<size_t>(3 * n_triangles));
    check_result(result, used, pins.empty() ? std::vector<uint8_t>() : used_pins,
                 !default_params && params.mode == DEV_MODE_PAPER);
    // The run's note on what it turned: the input check's words, as far as its message buffer held them.
    dev_stats s;
    require(dev_result_stats(result, &s) == DEV_STATUS_OK, "dev_result_stats failed");
    require(std::memchr(s.orientation_note, '\0', sizeof s.orientation_note) != nullptr,
            "orientation_note is not NUL-terminated");
    const std::string note(s.orientation_note);
    require((note.empty() ? std::string("ok") : "ok: " + note).substr(0, capacity - 1) == checked_message,
            "dev_run's orientation_note and dev_validate's message differ");
    dev_result_free(result);
  } else {
    require(result == nullptr, "a failed run returned a result");
    if (status == DEV_STATUS_CANCELLED) require(with_progress && cancel.asked, "cancelled without asking");
  }
  return 0;
}
