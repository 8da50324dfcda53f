#pragma once
// The mean of a Monte Carlo estimator's samples and its standard error, accumulated in double.
#include <cmath>

struct RunningEstimate {
  double sum = 0, sumSquares = 0;
  long count = 0;

  void add(double x) { sum += x, sumSquares += x * x, ++count; }
  double mean() const { return sum / count; }
  double standardError() const { return std::sqrt((sumSquares / count - mean() * mean()) / (count - 1)); }
};
