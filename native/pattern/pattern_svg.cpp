#include "pattern/pattern_svg.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace developable {
namespace {

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// Millimetres with 0.1 um resolution: plenty for a cutter, short files.
std::string mm(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4f", x);
  std::string s(buffer);
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

// The d attribute of a polyline (closed: a polygon), mm. A point that prints
// as the one before it (or, closed, as the first) is left out: a cutter has
// no use for a segment of length zero.
std::string path_data(const std::vector<Eigen::Vector2d>& points, bool closed) {
  std::vector<std::string> printed;
  for (const Eigen::Vector2d& point : points) {
    std::string xy = mm(point.x()) + " " + mm(point.y());
    if (printed.empty() || xy != printed.back()) printed.push_back(std::move(xy));
  }
  if (closed && printed.size() > 1 && printed.back() == printed.front()) printed.pop_back();
  std::string d;
  for (size_t i = 0; i < printed.size(); ++i) d += (i == 0 ? "M" : "L") + printed[i] + " ";
  if (closed) d += "Z";
  return d;
}

void text(std::ostringstream& out, const SheetLabel& label, const char* fill) {
  // Baseline a third of the height below the point: the text sits centred on it.
  out << "<text x=\"" << mm(label.at.x()) << "\" y=\"" << mm(label.at.y() + 0.35 * label.size) << "\" font-size=\""
      << mm(label.size) << "\" fill=\"" << fill << "\"";
  if (label.angle != 0.0)
    out << " transform=\"rotate(" << mm(label.angle) << " " << mm(label.at.x()) << " " << mm(label.at.y()) << ")\"";
  out << ">" << escape(label.text) << "</text>\n";
}

std::string scale_text(double scale) {
  std::ostringstream out;
  if (scale >= 1.0)
    out << scale << ":1";
  else
    out << "1:" << 1.0 / scale;
  return out.str();
}

}  // namespace

std::string pattern_svg(const Layout& layout, const UnfoldResult& unfolded, int sheet) {
  const LayoutOptions& o = layout.options;
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << mm(o.sheet_width) << "mm\" height=\""
      << mm(o.sheet_height) << "mm\" viewBox=\"0 0 " << mm(o.sheet_width) << " " << mm(o.sheet_height) << "\">\n"
      << "<title>Developable pattern, sheet " << sheet + 1 << " of " << layout.sheets << "</title>\n"
      << "<rect id=\"page\" x=\"0\" y=\"0\" width=\"" << mm(o.sheet_width) << "\" height=\"" << mm(o.sheet_height)
      << "\" fill=\"#ffffff\"/>\n";
  // The outlines: the cut lines; with a seam allowance the seam lines
  // (dashed) inside the cut lines, with glue tabs the pieces inside their
  // tabbed cut lines and the tabs' fold lines (dashed). What is cut outside
  // the outline is paler.
  // Every loop of the piece: the holes cut out (even-odd fill).
  const auto outline_path = [&](size_t p, size_t first_loop) {
    std::string d;
    for (size_t l = first_loop; l < layout.outlines[p].size(); ++l)
      d += path_data(outline_on_sheet(layout, p, l), true);
    return d;
  };
  const bool allowance = o.seam_allowance > 0.0, tabs = o.glue_tabs > 0.0;
  out << "<g id=\"cut-lines\" fill=\"" << (allowance || tabs ? "#eef4fb" : "#dbe8f6")
      << "\" stroke=\"#000000\" stroke-width=\"0.2\" stroke-linejoin=\"round\" fill-rule=\"evenodd\">\n";
  for (size_t p = 0; p < unfolded.pieces.size(); ++p) {
    if (layout.pieces[p].sheet != sheet) continue;
    out << "<path id=\"piece-" << escape(layout.pieces[p].label.text) << "\" d=\"";
    const auto& cut = layout.pieces[p].cut_line;
    out << (cut.empty() ? outline_path(p, 0) : path_data(cut, true) + outline_path(p, 1)) << "\"/>\n";
  }
  if (allowance || tabs) {
    out << "</g>\n<g id=\"" << (allowance ? "seam-lines" : "tabbed-pieces") << "\" fill=\"#dbe8f6\" "
        << (allowance ? "stroke=\"#000000\" stroke-width=\"0.2\" stroke-dasharray=\"1.5 1\" " : "stroke=\"none\" ")
        << "stroke-linejoin=\"round\" fill-rule=\"evenodd\">\n";
    for (size_t p = 0; p < unfolded.pieces.size(); ++p)
      if (layout.pieces[p].sheet == sheet)
        out << "<path id=\"seam-" << escape(layout.pieces[p].label.text) << "\" d=\"" << outline_path(p, 0) << "\"/>\n";
  }
  if (tabs) {
    out << "</g>\n<g id=\"fold-lines\" fill=\"none\" stroke=\"#000000\" stroke-width=\"0.2\" "
           "stroke-dasharray=\"1.5 1\" stroke-linejoin=\"round\">\n";
    for (const FoldLine& fold : layout.fold_lines) {
      if (fold.sheet != sheet) continue;
      out << "<path d=\"" << path_data(fold.points, false) << "\"/>\n";
    }
  }
  out << "</g>\n<g id=\"match-marks\" stroke=\"#c0392b\" stroke-width=\"0.25\">\n";
  for (const MatchMark& mark : layout.marks)
    if (mark.label.sheet == sheet)
      out << "<line x1=\"" << mm(mark.notch_from.x()) << "\" y1=\"" << mm(mark.notch_from.y()) << "\" x2=\""
          << mm(mark.notch_to.x()) << "\" y2=\"" << mm(mark.notch_to.y()) << "\"/>\n";
  out << "</g>\n<g id=\"labels\" font-family=\"DejaVu Sans, Arial, sans-serif\" text-anchor=\"middle\">\n";
  for (const PlacedPiece& piece : layout.pieces)
    if (piece.sheet == sheet) text(out, piece.label, "#1f3a5f");
  for (const MatchMark& mark : layout.marks)
    if (mark.label.sheet == sheet && !mark.label.text.empty()) text(out, mark.label, "#c0392b");
  out << "</g>\n";

  // Footer: a scale bar of a round length near 50 mm on paper.
  const double paper_per_unit = o.scale * o.unit_mm;  // mm on paper per model unit
  const bool inches = o.unit_name == "in";
  const double unit_of_bar = inches ? 25.4 : 1.0;  // the bar counts inches or millimetres of the model
  const double wanted = 50.0 / (o.scale * unit_of_bar);
  double length = std::pow(10.0, std::floor(std::log10(wanted)));
  for (double step : {5.0, 2.0})
    if (length * step <= wanted) {
      length *= step;
      break;
    }
  const double bar = length * unit_of_bar * o.scale;  // mm on paper
  std::ostringstream caption;
  if (inches)
    caption << length << " in";
  else if (length >= 1000.0)
    caption << length / 1000.0 << " m";
  else if (length >= 10.0)
    caption << length / 10.0 << " cm";
  else
    caption << length << " mm";
  const double x0 = o.margin, y0 = o.sheet_height - o.margin - 4.0;
  out << "<g id=\"scale-bar\" font-family=\"DejaVu Sans, Arial, sans-serif\" font-size=\"3\" fill=\"#000000\">\n";
  for (int i = 0; i < 5; ++i)
    out << "<rect x=\"" << mm(x0 + bar * i / 5) << "\" y=\"" << mm(y0) << "\" width=\"" << mm(bar / 5)
        << "\" height=\"2\" fill=\"" << (i % 2 == 0 ? "#000000" : "#ffffff")
        << "\" stroke=\"#000000\" stroke-width=\"0.15\"/>\n";
  out << "<text x=\"" << mm(x0) << "\" y=\"" << mm(y0 - 1.2) << "\">0</text>\n"
      << "<text x=\"" << mm(x0 + bar) << "\" y=\"" << mm(y0 - 1.2) << "\" text-anchor=\"middle\">"
      << escape(caption.str()) << "</text>\n"
      << "<text x=\"" << mm(o.sheet_width - o.margin) << "\" y=\"" << mm(y0 + 2) << "\" text-anchor=\"end\">"
      << "scale " << scale_text(o.scale) << " (print at 100 %) - " << mm(paper_per_unit) << " mm per "
      << escape(o.unit_name) << " - sheet " << sheet + 1 << " of " << layout.sheets << "</text>\n"
      << "</g>\n</svg>\n";
  return out.str();
}

std::vector<std::string> write_pattern_svg(const Layout& layout, const UnfoldResult& unfolded,
                                           const std::string& path) {
  std::vector<std::string> written;
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  const std::string stem = has_ext ? path.substr(0, dot) : path;
  const std::string ext = has_ext ? path.substr(dot) : ".svg";
  for (int s = 0; s < layout.sheets; ++s) {
    const std::string name = layout.sheets == 1 ? path : stem + "-" + std::to_string(s + 1) + ext;
    std::ofstream file(name, std::ios::binary);
    if (!file) throw EngineError(Status::invalid_argument, "cannot write the pattern file " + name);
    file << pattern_svg(layout, unfolded, s);
    file.close();
    if (!file) throw EngineError(Status::invalid_argument, "writing the pattern file " + name + " failed");
    written.push_back(name);
  }
  return written;
}

}  // namespace developable
