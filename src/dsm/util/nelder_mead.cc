// SPDX-License-Identifier: MIT
#include "dsm/util/nelder_mead.h"

#include <algorithm>
#include <numeric>
#include <vector>

namespace dsm {

NelderMeadResult NelderMead(const std::function<double(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x0,
                            const NelderMeadOptions& options) {
  const int n = static_cast<int>(x0.size());
  std::vector<Eigen::VectorXd> x(n + 1, x0);
  std::vector<double> fx(n + 1);
  for (int i = 0; i < n; ++i) x[i + 1](i) += options.initial_step;
  for (int i = 0; i <= n; ++i) fx[i] = f(x[i]);
  std::vector<int> order(n + 1);
  int it = 0;
  for (; it < options.max_iterations; ++it) {
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return fx[a] < fx[b]; });
    const int best = order.front(), worst = order.back(), second = order[n - 1];
    if (fx[worst] - fx[best] < options.tolerance) break;
    Eigen::VectorXd centroid = Eigen::VectorXd::Zero(n);
    for (int i = 0; i <= n; ++i)
      if (i != worst) centroid += x[i];
    centroid /= n;
    // Reflection, expansion, contraction, shrink (coefficients 1, 2, 0.5, 0.5).
    const Eigen::VectorXd xr = centroid + (centroid - x[worst]);
    const double fr = f(xr);
    if (fr < fx[best]) {
      const Eigen::VectorXd xe = centroid + 2.0 * (centroid - x[worst]);
      const double fe = f(xe);
      if (fe < fr) {
        x[worst] = xe, fx[worst] = fe;
      } else {
        x[worst] = xr, fx[worst] = fr;
      }
    } else if (fr < fx[second]) {
      x[worst] = xr, fx[worst] = fr;
    } else {
      const bool outside = fr < fx[worst];
      const Eigen::VectorXd xc = outside ? Eigen::VectorXd(centroid + 0.5 * (xr - centroid))
                                         : Eigen::VectorXd(centroid + 0.5 * (x[worst] - centroid));
      const double fc = f(xc);
      if (fc < (outside ? fr : fx[worst])) {
        x[worst] = xc, fx[worst] = fc;
      } else {
        for (int i = 0; i <= n; ++i) {
          if (i == best) continue;
          x[i] = x[best] + 0.5 * (x[i] - x[best]);
          fx[i] = f(x[i]);
        }
      }
    }
  }
  const int best = static_cast<int>(std::min_element(fx.begin(), fx.end()) - fx.begin());
  return {x[best], fx[best], it};
}

}  // namespace dsm
