#include "nodes/graphcut/binary_energy.h"

#include "nodes/core/errors.h"

namespace scanfill {
void BinaryEnergy::reset() {
  constant_ = 0;
  unary_.clear();
  edges_.clear();
  value_.clear();
  truncated_ = 0;
}

Index BinaryEnergy::add_variable() {
  unary_.push_back(0.0);
  return Index(unary_.size()) - 1;
}

void BinaryEnergy::add_unary(Index v, double e0, double e1) {
  constant_ += e0;
  unary_[size_t(v)] += e1 - e0;
}

bool BinaryEnergy::add_pairwise(Index u, Index v, double e00, double e01, double e10, double e11) {
  if (u == v) throw InvariantError("binary energy: pairwise term of a variable with itself");
  bool truncated = false;
  const double excess = (e00 + e11) - (e01 + e10);
  if (excess > 0) {  // not submodular: raise the mixed terms by half the excess each
    e01 += 0.5 * excess;
    e10 += 0.5 * excess;
    ++truncated_;
    truncated = true;
  }
  // E = e00 + (e10 - e00) x_u + (e11 - e10) x_v + (e01 + e10 - e00 - e11) (1 - x_u) x_v
  constant_ += e00;
  unary_[size_t(u)] += e10 - e00;
  unary_[size_t(v)] += e11 - e10;
  if (e01 + e10 - e00 - e11 > 0) edges_.push_back({std::int32_t(u), std::int32_t(v), e01 + e10 - e00 - e11, 0.0});
  return truncated;
}

double BinaryEnergy::minimize() {
  const Index n = variables();
  value_.assign(size_t(n), 0);
  if (n == 0) return constant_;
  // Source side = 0, sink side = 1. A positive U(1) - U(0) is paid when v ends on the sink side: arc s -> v; a
  // negative one is -d paid when v stays on the source side (arc v -> t), with d added to the constant.
  double constant = constant_;
  source_.assign(size_t(n), 0.0);
  sink_.assign(size_t(n), 0.0);
  for (Index v = 0; v < n; ++v) {
    const double d = unary_[size_t(v)];
    if (d > 0) {
      source_[size_t(v)] = d;
    } else if (d < 0) {
      sink_[size_t(v)] = -d;
      constant += d;
    }
  }
  flow_.build(std::int32_t(n), source_, sink_, edges_);
  const double flow = flow_.solve();
  for (Index v = 0; v < n; ++v) value_[size_t(v)] = flow_.sink_side(std::int32_t(v));
  return constant + flow;
}

}  // namespace scanfill
