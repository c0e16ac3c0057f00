// Flat patterns, beside pattern_layout: room for the labels on a sheet, so
// that no two labels overlap.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <unordered_map>
#include <vector>

namespace developable {

// The box a label's text takes on the sheet (mm), drawn centred on `at`,
// `size` high, turned by `angle` degrees: the axis-aligned box around the
// turned rectangle of its glyphs, each glyph counted kGlyphWidth x size wide
// (wider than any capital or digit of DejaVu Sans or Arial), 1.2 size high.
inline constexpr double kGlyphWidth = 0.8;
Eigen::AlignedBox2d label_box(const std::string& text, const Eigen::Vector2d& at, double size, double angle);

// The label boxes placed on one sheet, on a uniform grid of `cell` mm.
class LabelSpace {
 public:
  explicit LabelSpace(double cell = 10.0) : cell_(cell) {}
  // Whether `box` keeps clear of every box added (touching counts as clear).
  bool free(const Eigen::AlignedBox2d& box) const;
  void add(const Eigen::AlignedBox2d& box);

 private:
  template <typename Visit>
  void cells(const Eigen::AlignedBox2d& box, Visit visit) const;
  double cell_;
  std::vector<Eigen::AlignedBox2d> boxes_;
  std::unordered_map<long long, std::vector<int>> grid_;
};

}  // namespace developable
