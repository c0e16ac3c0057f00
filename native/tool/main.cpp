// developable: the command-line tool. Reads a mesh, runs the engine through
// its C ABI (the same path the Blender add-on takes), writes the result.
#include "api/developable.h"
#include "mesh_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

const char* const usage_text =
    "usage: developable INPUT OUTPUT [options]\n"
    "\n"
    "Makes a triangle mesh nearly developable (Gaussian curvature close to zero) by\n"
    "normal-guided deformation. INPUT and OUTPUT are .obj, .off, .ply or .stl files.\n"
    "\n"
    "options:\n"
    "  --omega X            weight of the normal rows (default 5)\n"
    "  --tolerance X        E_allow: largest vertex move in multiples of the average\n"
    "                       edge length AE; 0 for no limit (default 10)\n"
    "  --max-move X         largest vertex move as a fraction of the bounding box's\n"
    "                       diagonal; the smaller limit applies; 0 for no limit\n"
    "                       (default 0.01)\n"
    "  --max-iterations N   iteration limit (default 400)\n"
    "  --mode refit|paper   refit the ideal curve every iteration (default), or the\n"
    "                       paper's one set of targets\n"
    "  --solver decoupled|coupled\n"
    "                       linear system of the refit mode (default decoupled)\n"
    "  --pin-boundary       pin every boundary vertex\n"
    "  --pin FILE           pin the vertices listed in FILE (zero-based, one per line)\n"
    "  --no-mls             no moving-least-squares row weights around the pins\n"
    "  --segmentation auto|on|off\n"
    "                       split into quasi-developable patches (default auto:\n"
    "                       when the mesh is closed or one ideal curve does not\n"
    "                       fit; an open mesh split so is also run as one patch,\n"
    "                       kept if more developable)\n"
    "  --patches N          wanted number of patches (default: automatic)\n"
    "  --segment-error X    largest cone-fitting error of a patch, rad\n"
    "  --seams free|pinned  seams move freely (default) or are pinned (the paper)\n"
    "  --target-smoothing N rounds of averaging the target normals inside each patch\n"
    "                       (default: 1 on a segmented mesh, 0 on one patch)\n"
    "  --polish auto|on|off drive the angle defects to zero after the deformation\n"
    "                       (default auto: on in refit mode, off in paper mode)\n"
    "  --no-smoothed-input  do not let the polish of the input with its noise\n"
    "                       smoothed (nor its projection from the smoothed\n"
    "                       input) compete with the deformation's result\n"
    "  --report FILE.json   write the run's figures, patch ids and curves as JSON\n"
    "                       (with --pattern also the pattern's pieces and seams)\n"
    "\n"
    "flat pattern of the result (each patch unfolded, laid out on sheets):\n"
    "  --pattern OUT.svg    write the pattern: OUT.svg for one sheet, OUT-1.svg,\n"
    "                       OUT-2.svg, ... for more\n"
    "  --sheet WxH|a4|a3|letter\n"
    "                       sheet size in mm, portrait (default a4 = 210x297)\n"
    "  --margin MM          free margin on every side of a sheet (default 10)\n"
    "  --scale X|auto       paper length per model length: 1 = 1:1 (default),\n"
    "                       0.1 = 1:10; auto = the largest of 1, 1/2, 1/5, ... that fits\n"
    "  --unit m|cm|mm|in    the model's unit (default m)\n"
    "  --seam-tolerance X   largest relative length change of a piece's outline\n"
    "                       edge before the piece is split (default 0.0025; 0 = none)\n"
    "  --seam-allowance MM  cut every piece this far outside its outline, on paper,\n"
    "                       for sewing or gluing; the outline is drawn dashed as the\n"
    "                       seam line (default 0: the outline is the cut line)\n"
    "  --glue-tabs MM       a glue tab this high on one side of every seam, folded\n"
    "                       along it (papercraft; default 0: none; not with\n"
    "                       --seam-allowance)\n"
    "  --quiet              no progress on stderr\n"
    "  --help               this text\n"
    "\n"
    "The output is never folded or worse than the input (mean |defect|, flat share):\n"
    "when no such result exists the input is written unchanged and a line\n"
    "'WARNING: ...' on stderr says why (also with --quiet); an input that is\n"
    "developable already, or has no interior vertex (a band one face high: it\n"
    "unfolds as it stands), is written unchanged with a line 'note: ...'.\n"
    "\n"
    "Exit status: 0 done, 1 bad usage or file error, 2 the engine refused the mesh.\n";

[[noreturn]] void die(int code, const std::string& message) {
  std::cerr << "developable: error: " << message << "\n";
  std::exit(code);
}

double parse_number(const std::string& option, const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(value)) die(1, option + " needs a number, got '" + text + "'");
  return value;
}

int parse_integer(const std::string& option, const char* text) {
  const double value = parse_number(option, text);
  if (value != std::floor(value) || std::abs(value) > 1e9) die(1, option + " needs a whole number, got '" + text + "'");
  return static_cast<int>(value);
}

std::vector<uint8_t> read_pins(const std::string& path, int64_t vertex_count) {
  std::ifstream in(path);
  if (!in) die(1, "cannot open pin file " + path);
  std::vector<uint8_t> pinned(static_cast<size_t>(vertex_count), 0);
  std::string line;
  for (int line_number = 1; std::getline(in, line); ++line_number) {
    std::istringstream words(line);
    long long index = 0;
    if (!(words >> index)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      die(1, path + ":" + std::to_string(line_number) + ": not a vertex index: '" + line + "'");
    }
    if (index < 0 || index >= vertex_count)
      die(1, path + ":" + std::to_string(line_number) + ": vertex " + std::to_string(index) +
                 " does not exist (the mesh has " + std::to_string(vertex_count) + ")");
    pinned[static_cast<size_t>(index)] = 1;
  }
  return pinned;
}

int print_progress(double fraction, const char* stage, void*) {
  std::fprintf(stderr, "\r[%3d%%] %-24s", static_cast<int>(std::lround(100.0 * fraction)), stage);
  std::fflush(stderr);
  return 1;
}

const char* stop_reason_name(int32_t reason) {
  switch (reason) {
    case DEV_STOP_ALREADY_DEVELOPABLE:
      return "already_developable";
    case DEV_STOP_CONVERGED:
      return "converged";
    case DEV_STOP_STALLED:
      return "stalled";
    default:
      return "iteration_limit";
  }
}

const char* origin_name(int32_t origin) {
  switch (origin) {
    case DEV_ORIGIN_DEFORMATION:
      return "deformation";
    case DEV_ORIGIN_DEFORMATION_POLISH:
      return "deformation_polish";
    case DEV_ORIGIN_NEAR_FLAT_POLISH:
      return "near_flat_polish";
    case DEV_ORIGIN_INPUT_POLISH:
      return "input_polish";
    case DEV_ORIGIN_SMOOTHED_INPUT_POLISH:
      return "smoothed_input_polish";
    case DEV_ORIGIN_SMOOTHED_STEP_POLISH:
      return "smoothed_step_polish";
    case DEV_ORIGIN_PROJECTED_INPUT:
      return "projected_input";
    case DEV_ORIGIN_THINNED_PIECES:
      return "thinned_pieces";
    case DEV_ORIGIN_RULED_FINISH:
      return "ruled_finish";
    default:
      return "input";
  }
}

const char* unchanged_reason_name(int32_t reason) {
  switch (reason) {
    case DEV_UNCHANGED_ALREADY_DEVELOPABLE:
      return "already_developable";
    case DEV_UNCHANGED_DEVELOPABLE_PIECEWISE:
      return "developable_piecewise";
    case DEV_UNCHANGED_ALREADY_FLAT:
      return "already_flat";
    case DEV_UNCHANGED_NO_VISIBLE_GAIN:
      return "no_visible_gain";
    case DEV_UNCHANGED_NO_BETTER_ITERATE:
      return "no_better_iterate";
    case DEV_UNCHANGED_REJECTED:
      return "rejected";
    default:
      return "none";
  }
}

std::string json_number(double value) {
  if (!std::isfinite(value)) return "null";
  std::ostringstream s;
  s << std::setprecision(17) << value;
  return s.str();
}

// The characters of `text` escaped for a JSON string.
std::string json_string(const char* text) {
  std::ostringstream s;
  for (const char* c = text; *c != '\0'; ++c) {
    const auto u = static_cast<unsigned char>(*c);
    if (*c == '"' || *c == '\\')
      s << '\\' << *c;
    else if (u < 0x20)
      s << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int(u) << std::dec;
    else
      s << *c;
  }
  return s.str();
}

// The "pattern" member of the report: figures, pieces, seams, files.
std::string pattern_json(const dev_pattern* pattern, const dev_pattern_params& params) {
  dev_pattern_stats st;
  dev_pattern_stats_get(pattern, &st);
  std::ostringstream json;
  json << "{\"parameters\": {\"sheet_width_mm\": " << json_number(params.sheet_width_mm)
       << ", \"sheet_height_mm\": " << json_number(params.sheet_height_mm)
       << ", \"margin_mm\": " << json_number(params.margin_mm) << ", \"unit\": \"" << params.unit_name
       << "\", \"unit_mm\": " << json_number(params.unit_mm)
       << ", \"seam_tolerance\": " << json_number(params.seam_tolerance)
       << ", \"seam_allowance_mm\": " << json_number(params.seam_allowance_mm)
       << ", \"glue_tabs_mm\": " << json_number(params.glue_tabs_mm) << "},\n";
  json << "    \"stats\": {\"pieces\": " << st.pieces << ", \"sheets\": " << st.sheets << ", \"seams\": " << st.seams
       << ", \"cut_edges\": " << st.cut_edges << ", \"splits\": " << st.splits
       << ", \"max_strain\": " << json_number(st.max_strain) << ", \"mean_strain\": " << json_number(st.mean_strain)
       << ", \"max_area_change\": " << json_number(st.max_area_change) << ", \"scale\": " << json_number(st.scale)
       << ", \"time_unfold_ms\": " << json_number(st.time_unfold_ms)
       << ", \"time_layout_ms\": " << json_number(st.time_layout_ms)
       << ", \"time_total_ms\": " << json_number(st.time_total_ms)
       << ", \"cut_lines_from_hull\": " << st.cut_lines_from_hull << ", \"glue_tabs\": " << st.glue_tabs
       << ", \"glue_tabs_dropped\": " << st.glue_tabs_dropped << "},\n    \"files\": [";
  char path[4096];
  for (int64_t i = 0; i < st.svg_files; ++i) {
    dev_pattern_svg_file(pattern, i, path, sizeof path);
    json << (i ? ", " : "") << "\"" << json_string(path) << "\"";
  }
  json << "],\n    \"pieces\": [";
  for (int64_t i = 0; i < st.pieces; ++i) {
    dev_pattern_piece p;
    dev_pattern_piece_get(pattern, i, &p);
    json << (i ? "," : "") << "\n      {\"label\": \"" << p.label << "\", \"patch\": " << p.patch
         << ", \"sheet\": " << p.sheet << ", \"faces\": " << p.faces << ", \"cut_edges\": " << p.cut_edges
         << ", \"max_strain\": " << json_number(p.max_strain) << ", \"mean_strain\": " << json_number(p.mean_strain)
         << ", \"area_3d\": " << json_number(p.area_3d) << ", \"area_flat\": " << json_number(p.area_flat)
         << ", \"area_change\": " << json_number(p.area_change)
         << ", \"outline_length\": " << json_number(p.outline_length) << ", \"width_mm\": " << json_number(p.width_mm)
         << ", \"height_mm\": " << json_number(p.height_mm) << "}";
  }
  json << "],\n    \"seams\": [";
  for (int64_t i = 0; i < st.seams; ++i) {
    dev_pattern_seam m;
    dev_pattern_seam_get(pattern, i, &m);
    json << (i ? "," : "") << "\n      {\"label\": \"" << m.label << "\", \"piece_a\": " << m.piece_a
         << ", \"piece_b\": " << m.piece_b << ", \"cut\": " << (m.cut ? "true" : "false") << ", \"edges\": " << m.edges
         << ", \"length_3d\": " << json_number(m.length_3d) << ", \"length_a\": " << json_number(m.length_a)
         << ", \"length_b\": " << json_number(m.length_b) << "}";
  }
  json << "]}";
  return json.str();
}

// Writes `text` to `path` whole or not at all (through a temporary file); dies on an error.
void write_whole(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".partial";
  {
    std::ofstream out(temporary);
    out << text;
    if (!out) die(1, "cannot write report " + path);
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) die(1, "cannot write report " + path);
}

void write_report(const std::string& path, const dev_result* result, const dev_stats& s, const dev_params& params,
                  const std::string& pattern) {
  std::ostringstream json;
  json << "{\n  \"engine_version\": \"" << dev_version_string() << "\",\n";
  json << "  \"parameters\": {\"omega\": " << json_number(params.omega)
       << ", \"tolerance_ae\": " << json_number(params.tolerance) << ", \"max_move\": " << json_number(params.max_move)
       << ", \"polish\": " << params.polish << ", \"polish_smoothed_input\": " << params.polish_smoothed_input
       << ", \"max_iterations\": " << params.max_iterations << ", \"mode\": \""
       << (params.mode == DEV_MODE_PAPER ? "paper" : "refit") << "\", \"solver\": \""
       << (params.solver == DEV_SOLVER_COUPLED ? "coupled" : "decoupled")
       << "\", \"pin_boundary\": " << (params.pin_boundary ? "true" : "false")
       << ", \"mls_weights\": " << (params.use_mls_weights ? "true" : "false")
       << ", \"segmentation\": " << params.segmentation << ", \"target_smoothing\": " << params.target_smoothing
       << ", \"seams\": \"" << (params.seams == DEV_SEAMS_PINNED ? "pinned" : "free") << "\"},\n";
  json << "  \"stats\": {\"vertices\": " << s.vertices << ", \"faces\": " << s.faces
       << ", \"interior_vertices\": " << s.interior_vertices << ", \"patches\": " << s.patches
       << ", \"curves\": " << s.curves << ", \"iterations\": " << s.iterations << ", \"stop_reason\": \""
       << stop_reason_name(s.stop_reason) << "\""
       << ", \"average_edge_length\": " << json_number(s.average_edge_length)
       << ", \"mean_defect_before\": " << json_number(s.mean_defect_before)
       << ", \"mean_defect_after\": " << json_number(s.mean_defect_after)
       << ", \"max_defect_before\": " << json_number(s.max_defect_before)
       << ", \"max_defect_after\": " << json_number(s.max_defect_after)
       << ", \"change_percent\": " << json_number(s.change_percent)
       << ", \"max_vertex_move\": " << json_number(s.max_vertex_move)
       << ", \"time_decompose_ms\": " << json_number(s.time_decompose_ms)
       << ", \"time_iterate_ms\": " << json_number(s.time_iterate_ms)
       << ", \"time_total_ms\": " << json_number(s.time_total_ms)
       << ", \"time_polish_ms\": " << json_number(s.time_polish_ms)
       << ", \"polish_iterations\": " << s.polish_iterations << ", \"result_origin\": \""
       << origin_name(s.result_origin) << "\""
       << ", \"worse_figures\": " << s.worse_figures << ", \"result\": \""
       << (s.result == DEV_RESULT_UNCHANGED ? "unchanged" : "improved") << "\""
       << ", \"unchanged_reason\": \"" << unchanged_reason_name(s.unchanged_reason) << "\""
       << ", \"faces_turned_over\": " << s.faces_turned_over
       << ", \"flat_share_before\": " << json_number(s.flat_share_before)
       << ", \"flat_share_after\": " << json_number(s.flat_share_after)
       << ", \"ruled_share_before\": " << json_number(s.ruled_share_before)
       << ", \"ruled_share_after\": " << json_number(s.ruled_share_after)
       << ", \"crumpled_share_before\": " << json_number(s.crumpled_share_before)
       << ", \"crumpled_share_after\": " << json_number(s.crumpled_share_after)
       << ", \"move_limit\": " << json_number(s.move_limit) << ", \"result_message\": \""
       << json_string(s.result_message) << "\"},\n";
  std::vector<int32_t> patches(static_cast<size_t>(s.faces));
  dev_result_patch_ids(result, patches.data(), s.faces);
  json << "  \"patch_ids\": [";
  for (size_t f = 0; f < patches.size(); ++f) json << (f ? "," : "") << patches[f];
  json << "],\n  \"curves\": [";
  for (int64_t c = 0; c < dev_result_curve_count(result); ++c) {
    int64_t count = 0;
    int32_t patch = 0, closed = 0;
    dev_result_curve_info(result, c, &count, &patch, &closed);
    std::vector<double> points(static_cast<size_t>(3 * count));
    dev_result_curve_points(result, c, points.data(), 3 * count);
    json << (c ? "," : "") << "\n    {\"patch\": " << patch << ", \"closed\": " << (closed ? "true" : "false")
         << ", \"points\": [";
    for (int64_t p = 0; p < count; ++p) {
      json << (p ? "," : "") << "[" << json_number(points[3 * p]) << "," << json_number(points[3 * p + 1]) << ","
           << json_number(points[3 * p + 2]) << "]";
    }
    json << "]}";
  }
  json << "\n  ]";
  if (!pattern.empty()) json << ",\n  \"pattern\": " << pattern;
  json << "\n}\n";
  write_whole(path, json.str());
}

// The command line, parsed.
struct Arguments {
  dev_params params;
  dev_pattern_params pattern_params;
  std::vector<std::string> files;
  std::string pin_file, report_file, pattern_file;
  bool quiet = false;
};

// Reads the options with values out of argv: `value` gives the next
// argument (or dies naming the option), `choice` its index among names.
class OptionReader {
 public:
  OptionReader(int argc, char** argv) : argc_(argc), argv_(argv) {}

  bool next() { return ++i_ < argc_; }
  std::string arg() const { return argv_[i_]; }
  const char* value() {
    if (i_ + 1 >= argc_) die(1, std::string(argv_[i_]) + " needs a value (see --help)");
    return argv_[++i_];
  }
  int choice(std::initializer_list<const char*> names) {
    const std::string option = argv_[i_];
    const std::string given = value();
    int index = 0;
    for (const char* name : names) {
      if (given == name) return index;
      ++index;
    }
    die(1, option + ": unknown value '" + given + "' (see --help)");
  }

 private:
  int argc_;
  char** argv_;
  int i_ = 0;
};

// An engine option (dev_params): true when `arg` was one.
bool read_engine_option(const std::string& arg, OptionReader& in, Arguments& a) {
  dev_params& params = a.params;
  if (arg == "--omega") {
    params.omega = parse_number(arg, in.value());
  } else if (arg == "--tolerance") {
    params.tolerance = parse_number(arg, in.value());
  } else if (arg == "--max-move") {
    params.max_move = parse_number(arg, in.value());
  } else if (arg == "--polish") {
    const int index = in.choice({"auto", "on", "off"});
    params.polish = index == 0 ? -1 : (index == 1 ? 1 : 0);
  } else if (arg == "--no-smoothed-input") {
    params.polish_smoothed_input = 0;
  } else if (arg == "--max-iterations") {
    params.max_iterations = parse_integer(arg, in.value());
  } else if (arg == "--mode") {
    params.mode = in.choice({"refit", "paper"}) == 0 ? DEV_MODE_REFIT : DEV_MODE_PAPER;
  } else if (arg == "--solver") {
    params.solver = in.choice({"decoupled", "coupled"}) == 0 ? DEV_SOLVER_DECOUPLED : DEV_SOLVER_COUPLED;
  } else if (arg == "--pin-boundary") {
    params.pin_boundary = 1;
  } else if (arg == "--pin") {
    a.pin_file = in.value();
  } else if (arg == "--no-mls") {
    params.use_mls_weights = 0;
  } else if (arg == "--segmentation") {
    const int index = in.choice({"auto", "on", "off"});
    params.segmentation = index == 0 ? -1 : (index == 1 ? 1 : 0);
  } else if (arg == "--patches") {
    params.target_patches = parse_integer(arg, in.value());
  } else if (arg == "--segment-error") {
    params.segment_max_error = parse_number(arg, in.value());
  } else if (arg == "--seams") {
    params.seams = in.choice({"free", "pinned"}) == 0 ? DEV_SEAMS_FREE : DEV_SEAMS_PINNED;
  } else if (arg == "--target-smoothing") {
    params.target_smoothing = parse_integer(arg, in.value());
  } else {
    return false;
  }
  return true;
}

// A flat-pattern option (dev_pattern_params): true when `arg` was one.
bool read_pattern_option(const std::string& arg, OptionReader& in, Arguments& a) {
  dev_pattern_params& pattern = a.pattern_params;
  if (arg == "--pattern") {
    a.pattern_file = in.value();
  } else if (arg == "--sheet") {
    const std::string given = in.value();
    double w = 0, h = 0;
    char extra = 0;
    if (given == "a4")
      w = 210, h = 297;
    else if (given == "a3")
      w = 297, h = 420;
    else if (given == "letter")
      w = 215.9, h = 279.4;
    else if (std::sscanf(given.c_str(), "%lfx%lf%c", &w, &h, &extra) != 2 || !(w > 0) || !(h > 0) ||
             !std::isfinite(w) || !std::isfinite(h))
      die(1, "--sheet needs WxH in mm (e.g. 210x297) or a4, a3, letter; got '" + given + "'");
    pattern.sheet_width_mm = w;
    pattern.sheet_height_mm = h;
  } else if (arg == "--margin") {
    pattern.margin_mm = parse_number(arg, in.value());
  } else if (arg == "--scale") {
    const std::string given = in.value();
    pattern.scale = given == "auto" ? 0.0 : parse_number(arg, given.c_str());
    if (given != "auto" && !(pattern.scale > 0)) die(1, "--scale needs a positive number or auto");
  } else if (arg == "--unit") {
    const int index = in.choice({"m", "cm", "mm", "in"});
    const char* names[] = {"m", "cm", "mm", "in"};
    const double mm[] = {1000.0, 10.0, 1.0, 25.4};
    std::snprintf(pattern.unit_name, sizeof pattern.unit_name, "%s", names[index]);
    pattern.unit_mm = mm[index];
  } else if (arg == "--seam-tolerance") {
    pattern.seam_tolerance = parse_number(arg, in.value());
  } else if (arg == "--seam-allowance") {
    pattern.seam_allowance_mm = parse_number(arg, in.value());
  } else if (arg == "--glue-tabs") {
    pattern.glue_tabs_mm = parse_number(arg, in.value());
  } else {
    return false;
  }
  return true;
}

// The command line; prints the usage and exits for --help, dies on a bad one.
Arguments parse_arguments(int argc, char** argv) {
  Arguments a;
  dev_default_params(&a.params);
  dev_default_pattern_params(&a.pattern_params);
  OptionReader in(argc, argv);
  while (in.next()) {
    const std::string arg = in.arg();
    if (arg == "--help" || arg == "-h") {
      std::cout << usage_text;
      std::exit(0);
    } else if (arg == "--report") {
      a.report_file = in.value();
    } else if (arg == "--quiet" || arg == "-q") {
      a.quiet = true;
    } else if (read_engine_option(arg, in, a) || read_pattern_option(arg, in, a)) {
      continue;
    } else if (!arg.empty() && arg[0] == '-') {
      die(1, "unknown option " + arg + " (see --help)");
    } else {
      a.files.push_back(arg);
    }
  }
  if (a.files.size() != 2) die(1, "need INPUT and OUTPUT files (see --help)");
  return a;
}

// The flat pattern of `positions` on the mesh's triangles (dev_unfold on
// `patches`, one per triangle, or one patch when empty), its stats and its
// report section; dies on an error.
std::string unfold(const std::vector<double>& positions, const developable_tool::RawMesh& mesh,
                   const std::vector<int32_t>& patches, Arguments& a, dev_pattern_stats& pattern_stats) {
  a.pattern_params.svg_path = a.pattern_file.c_str();
  dev_pattern* pattern = nullptr;
  char message[1024];
  const int32_t unfolded = dev_unfold(positions.data(), mesh.vertex_count(), mesh.triangles.data(),
                                      mesh.triangle_count(), patches.empty() ? nullptr : patches.data(),
                                      &a.pattern_params, nullptr, nullptr, &pattern, message, sizeof message);
  if (unfolded != DEV_STATUS_OK) die(2, "pattern: " + std::string(message));
  dev_pattern_stats_get(pattern, &pattern_stats);
  std::string report = pattern_json(pattern, a.pattern_params);
  dev_pattern_free(pattern);
  return report;
}

// Whether two vertices of the mesh lie on one point: its faces are not
// joined there (a polygon soup, an unwelded seam).
bool has_coincident_vertices(const developable_tool::RawMesh& mesh) {
  std::vector<std::array<double, 3>> points(static_cast<size_t>(mesh.vertex_count()));
  for (size_t v = 0; v < points.size(); ++v)
    points[v] = {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
  std::sort(points.begin(), points.end());
  return std::adjacent_find(points.begin(), points.end()) != points.end();
}

// The pattern's figures on stderr (not with --quiet).
void print_pattern_summary(const dev_pattern_stats& pattern_stats) {
  std::fprintf(stderr,
               "pattern: %lld pieces on %lld sheets at scale %g, %lld seams, %lld cut edges, "
               "%lld splits; strain max %.3g %% mean %.3g %%; %.1f ms\n",
               static_cast<long long>(pattern_stats.pieces), static_cast<long long>(pattern_stats.sheets),
               pattern_stats.scale, static_cast<long long>(pattern_stats.seams),
               static_cast<long long>(pattern_stats.cut_edges), static_cast<long long>(pattern_stats.splits),
               100 * pattern_stats.max_strain, 100 * pattern_stats.mean_strain, pattern_stats.time_total_ms);
}

// The run's figures on stderr (not with --quiet).
void print_summary(const dev_stats& stats, const dev_pattern_stats* pattern_stats) {
  std::fprintf(stderr,
               "#v %lld  #f %lld  AE %.4g  patches %lld\n"
               "E_before %.4e  E_after %.4e  dE %.2f %%  max |defect| %.3e -> %.3e\n"
               "iterations %d (%s), polish %d, result from %s  largest move %.4g (%.3g AE, limit %.4g)\n"
               "t_D %.2f ms  t_I %.2f ms  polish %.2f ms  t_T %.2f ms\n",
               static_cast<long long>(stats.vertices), static_cast<long long>(stats.faces), stats.average_edge_length,
               static_cast<long long>(stats.patches), stats.mean_defect_before, stats.mean_defect_after,
               stats.change_percent, stats.max_defect_before, stats.max_defect_after, stats.iterations,
               stop_reason_name(stats.stop_reason), stats.polish_iterations, origin_name(stats.result_origin),
               stats.max_vertex_move, stats.max_vertex_move / stats.average_edge_length, stats.move_limit,
               stats.time_decompose_ms, stats.time_iterate_ms, stats.time_polish_ms, stats.time_total_ms);
  const std::string result_kind = stats.result == DEV_RESULT_UNCHANGED
                                      ? std::string("unchanged (") + unchanged_reason_name(stats.unchanged_reason) + ")"
                                      : "improved";
  std::fprintf(stderr,
               "flat %.1f %% -> %.1f %%  flat and ruled %.1f %% -> %.1f %%  faces turned over %lld  result %s\n",
               100.0 * stats.flat_share_before, 100.0 * stats.flat_share_after, 100.0 * stats.ruled_share_before,
               100.0 * stats.ruled_share_after, static_cast<long long>(stats.faces_turned_over), result_kind.c_str());
  if (pattern_stats != nullptr) print_pattern_summary(*pattern_stats);
}

// The pattern's notes, also with --quiet.
void print_pattern_notes(const dev_pattern_stats& pattern_stats) {
  if (pattern_stats.glue_tabs_dropped > 0)
    std::fprintf(stderr, "note: %lld seams have no glue tab: none fitted on either side, not even at half the height\n",
                 static_cast<long long>(pattern_stats.glue_tabs_dropped));
  if (pattern_stats.cut_lines_from_hull > 0)
    std::fprintf(stderr,
                 "note: the cut lines of %lld pieces follow the offset of their convex hull (the seam "
                 "allowance is wider than asked in their hollows)\n",
                 static_cast<long long>(pattern_stats.cut_lines_from_hull));
}

// What the user must know even with --quiet: when the output is the input,
// or a figure got worse (an input developable already is no failure), and
// the pattern's notes.
void print_notes(const dev_stats& stats, const dev_pattern_stats& pattern_stats) {
  const bool nothing_to_do = stats.unchanged_reason == DEV_UNCHANGED_ALREADY_DEVELOPABLE ||
                             stats.unchanged_reason == DEV_UNCHANGED_DEVELOPABLE_PIECEWISE ||
                             stats.unchanged_reason == DEV_UNCHANGED_ALREADY_FLAT;
  if (stats.result == DEV_RESULT_UNCHANGED || stats.result_message[0] != '\0')
    std::fprintf(stderr, "%s: %s\n", nothing_to_do ? "note" : "WARNING", stats.result_message);
  print_pattern_notes(pattern_stats);
}

// A mesh without an interior vertex (a band or tube one face wide, a
// triangle fan) has no angle defect to lower, and unfolds without stretching
// as it stands: written unchanged, with its pattern when asked (one patch,
// which the unfolding opens where it must). The engine refuses it
// (DEV_STATUS_NO_INTERIOR_VERTEX); the add-on says the same.
int write_unchanged_without_interior(const developable_tool::RawMesh& mesh, Arguments& a) {
  std::string error;
  if (!developable_tool::write_mesh(a.files[1], mesh.positions, mesh.triangles, error)) die(1, error);
  dev_pattern_stats pattern_stats{};
  const std::string pattern =
      a.pattern_file.empty() ? std::string() : unfold(mesh.positions, mesh, {}, a, pattern_stats);
  if (!a.report_file.empty())
    write_whole(a.report_file, "{\n  \"engine_version\": \"" + std::string(dev_version_string()) +
                                   "\",\n  \"stats\": {\"vertices\": " + std::to_string(mesh.vertex_count()) +
                                   ", \"faces\": " + std::to_string(mesh.triangle_count()) +
                                   ", \"interior_vertices\": 0, \"result\": \"unchanged\", \"unchanged_reason\": "
                                   "\"no_interior_vertex\"}" +
                                   (pattern.empty() ? "" : ",\n  \"pattern\": " + pattern) + "\n}\n");
  std::fprintf(stderr,
               "note: Returned the input unchanged: every vertex is on the boundary, so it has no curvature to "
               "lower and unfolds without stretching as it stands.\n");
  if (!a.quiet && !a.pattern_file.empty()) print_pattern_summary(pattern_stats);
  print_pattern_notes(pattern_stats);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments a = parse_arguments(argc, argv);
  if (dev_abi_version() != DEV_ABI_VERSION) die(1, "the engine library does not match this tool");
  if (!developable_tool::can_write(a.files[1]))
    die(1, "cannot write '" + a.files[1] + "': use .obj, .off, .ply or .stl");
  developable_tool::RawMesh mesh;
  std::string error;
  if (!developable_tool::read_raw_mesh(a.files[0], mesh, error)) die(1, error);
  std::vector<uint8_t> pinned;
  if (!a.pin_file.empty()) pinned = read_pins(a.pin_file, mesh.vertex_count());

  dev_result* result = nullptr;
  char message[1024];
  const int32_t status = dev_run(mesh.positions.data(), mesh.vertex_count(), mesh.triangles.data(),
                                 mesh.triangle_count(), pinned.empty() ? nullptr : pinned.data(), &a.params,
                                 a.quiet ? nullptr : print_progress, nullptr, &result, message, sizeof message);
  if (!a.quiet) std::fprintf(stderr, "\n");
  if (status == DEV_STATUS_NO_INTERIOR_VERTEX && !has_coincident_vertices(mesh))
    return write_unchanged_without_interior(mesh, a);
  if (status != DEV_STATUS_OK) die(2, std::string(a.files[0]) + ": " + message);
  dev_stats stats;
  dev_result_stats(result, &stats);
  std::vector<double> positions(mesh.positions.size());
  dev_result_positions(result, positions.data(), static_cast<int64_t>(positions.size()));
  if (!developable_tool::write_mesh(a.files[1], positions, mesh.triangles, error)) die(1, error);
  dev_pattern_stats pattern_stats{};
  std::string pattern_report;
  if (!a.pattern_file.empty()) {
    std::vector<int32_t> patches(static_cast<size_t>(stats.faces));
    dev_result_patch_ids(result, patches.data(), stats.faces);
    pattern_report = unfold(positions, mesh, patches, a, pattern_stats);
  }
  if (!a.report_file.empty()) write_report(a.report_file, result, stats, a.params, pattern_report);
  dev_result_free(result);
  if (!a.quiet) print_summary(stats, a.pattern_file.empty() ? nullptr : &pattern_stats);
  print_notes(stats, pattern_stats);
  return 0;
}
