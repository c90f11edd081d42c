#pragma once

// Composite Simpson quadrature in double, the ground truth the media tests integrate
// densities with.

#include <functional>

namespace farm::testing {

inline double Simpson(const std::function<double(double)>& f, double a, double b, int intervals = 200000) {
  const double h = (b - a) / intervals;
  double sum = f(a) + f(b);
  for (int i = 1; i < intervals; ++i) sum += f(a + i * h) * (i % 2 ? 4 : 2);
  return sum * h / 3;
}

}  // namespace farm::testing
