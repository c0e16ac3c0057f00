#include "pattern/pattern_labels.h"

#include <cmath>

namespace developable {

Eigen::AlignedBox2d label_box(const std::string& text, const Eigen::Vector2d& at, double size, double angle) {
  const double half_w = 0.5 * kGlyphWidth * size * static_cast<double>(text.size()), half_h = 0.6 * size;
  const double a = angle * M_PI / 180.0;
  const double c = std::abs(std::cos(a)), s = std::abs(std::sin(a));
  const Eigen::Vector2d half(c * half_w + s * half_h, s * half_w + c * half_h);
  return Eigen::AlignedBox2d(at - half, at + half);
}

template <typename Visit>
void LabelSpace::cells(const Eigen::AlignedBox2d& box, Visit visit) const {
  const auto index = [&](double x) { return static_cast<long long>(std::floor(x / cell_)); };
  for (long long x = index(box.min().x()); x <= index(box.max().x()); ++x)
    for (long long y = index(box.min().y()); y <= index(box.max().y()); ++y) visit(x * 1000003LL + y);
}

bool LabelSpace::free(const Eigen::AlignedBox2d& box) const {
  bool clear = true;
  cells(box, [&](long long key) {
    const auto it = grid_.find(key);
    if (it == grid_.end()) return;
    for (int i : it->second) {
      const Eigen::AlignedBox2d& other = boxes_[i];
      if ((box.min().array() < other.max().array()).all() && (other.min().array() < box.max().array()).all())
        clear = false;
    }
  });
  return clear;
}

void LabelSpace::add(const Eigen::AlignedBox2d& box) {
  const int id = static_cast<int>(boxes_.size());
  boxes_.push_back(box);
  cells(box, [&](long long key) { grid_[key].push_back(id); });
}

}  // namespace developable
