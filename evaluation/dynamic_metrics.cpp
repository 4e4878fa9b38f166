#include "evaluation/dynamic_metrics.hpp"

#include <cmath>

namespace cleanmap {
namespace {

double ratio(std::size_t num, std::size_t den) {
  return den == 0 ? std::nan("") : static_cast<double>(num) / static_cast<double>(den);
}

}  // namespace

MovingConfusion& MovingConfusion::operator+=(const MovingConfusion& o) {
  tp += o.tp;
  fp += o.fp;
  fn += o.fn;
  tn += o.tn;
  unscored += o.unscored;
  return *this;
}

double MovingConfusion::iou() const { return ratio(tp, tp + fp + fn); }
double MovingConfusion::precision() const { return ratio(tp, tp + fp); }
double MovingConfusion::recall() const { return ratio(tp, tp + fn); }

}  // namespace cleanmap
