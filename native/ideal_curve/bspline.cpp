#include "ideal_curve/bspline.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace developable {

int bspline_basis(int n, bool closed, double t, double b[4]) {
  if (closed) {
    double u = (t - std::floor(t)) * n;
    int seg = std::min(n - 1, std::max(0, static_cast<int>(std::floor(u))));
    const double s = u - seg, s2 = s * s, s3 = s2 * s;
    b[0] = (1.0 - s) * (1.0 - s) * (1.0 - s) / 6.0;
    b[1] = (3.0 * s3 - 6.0 * s2 + 4.0) / 6.0;
    b[2] = (-3.0 * s3 + 3.0 * s2 + 3.0 * s + 1.0) / 6.0;
    b[3] = s3 / 6.0;
    return seg;
  }
  // Clamped knots 0,0,0,0, 1/(n-3), ..., 1,1,1,1 (n + 4 of them).
  const int spans = n - 3;
  auto knot = [&](int i) { return std::min(1.0, std::max(0.0, static_cast<double>(i - 3) / spans)); };
  t = std::min(1.0, std::max(0.0, t));
  const int span = std::min(n - 1, 3 + static_cast<int>(std::floor(t * spans)));
  // Cox-de Boor (The NURBS Book, A2.2).
  double left[4], right[4];
  b[0] = 1.0;
  for (int j = 1; j <= 3; ++j) {
    left[j] = t - knot(span + 1 - j);
    right[j] = knot(span + j) - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double denom = right[r + 1] + left[j - r];
      const double temp = denom > 0.0 ? b[r] / denom : 0.0;
      b[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    b[j] = saved;
  }
  return span - 3;
}

Eigen::Vector2d evaluate(const BSpline& s, double t) {
  const int n = static_cast<int>(s.ctrl.size());
  double b[4];
  const int first = bspline_basis(n, s.closed, t, b);
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (int k = 0; k < 4; ++k) p += b[k] * s.ctrl[(first + k) % n];
  return p;
}

BSpline fit_bspline(const std::vector<Eigen::Vector2d>& data, const std::vector<double>& params,
                    const std::vector<double>& weights, int n, bool closed) {
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
  for (size_t i = 0; i < data.size(); ++i) {
    double b[4];
    const int first = bspline_basis(n, closed, params[i], b);
    for (int a = 0; a < 4; ++a) {
      const int ia = (first + a) % n;
      rhs.row(ia) += weights[i] * b[a] * data[i].transpose();
      for (int c = 0; c < 4; ++c) normal(ia, (first + c) % n) += weights[i] * b[a] * b[c];
    }
  }
  const double scale = normal.trace() > 0.0 ? normal.trace() / n : 1.0;
  const double lambda = 1e-4 * scale;
  const int rows = closed ? n : n - 2;
  for (int r = 0; r < rows; ++r) {
    const int idx[3] = {r % n, (r + 1) % n, (r + 2) % n};
    const double coef[3] = {1.0, -2.0, 1.0};
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c) normal(idx[a], idx[c]) += lambda * coef[a] * coef[c];
    }
  }
  normal.diagonal().array() += 1e-12 * scale;  // all data at one parameter
  const Eigen::MatrixXd solution = normal.ldlt().solve(rhs);
  BSpline s;
  s.closed = closed;
  s.ctrl.resize(n);
  for (int i = 0; i < n; ++i) s.ctrl[i] = solution.row(i).transpose();
  if (!solution.allFinite()) {
    throw EngineError(Status::numerical_failure, "ideal curve: B-spline fit is not finite");
  }
  return s;
}

ChartPolyline sample_bspline(const BSpline& s, int count) {
  ChartPolyline p;
  p.closed = s.closed;
  for (int i = 0; i < count; ++i) {
    const double t = s.closed ? static_cast<double>(i) / count : static_cast<double>(i) / (count - 1);
    p.points.push_back(evaluate(s, t));
    p.params.push_back(t);
  }
  return p;
}

}  // namespace developable
