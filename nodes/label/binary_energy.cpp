#include "nodes/label/binary_energy.h"

// GCC 12 reports -Wmaybe-uninitialized inside Boost.Graph's edge iterators once they are inlined here (a known false
// positive of boost::optional); it is silenced for this file's use of Boost only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
using Graph = boost::adjacency_list<
    boost::vecS, boost::vecS, boost::directedS, boost::no_property,
    boost::property<boost::edge_capacity_t, double,
                    boost::property<boost::edge_residual_capacity_t, double,
                                    boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;

}  // namespace

BinaryEnergy::BinaryEnergy() = default;
BinaryEnergy::~BinaryEnergy() = default;

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
  edges_.push_back({std::int32_t(u), std::int32_t(v), e01 + e10 - e00 - e11, 0.0});
  return truncated;
}

double BinaryEnergy::minimize() {
  const Index n = variables();
  value_.assign(size_t(n), 0);
  if (n == 0) return constant_;
  Graph g(size_t(n) + 2);
  const auto s = Traits::vertex_descriptor(n), t = Traits::vertex_descriptor(n + 1);
  auto capacity = boost::get(boost::edge_capacity, g);
  auto reverse = boost::get(boost::edge_reverse, g);
  auto add = [&](Traits::vertex_descriptor a, Traits::vertex_descriptor b, double ab, double ba) {
    const auto e1 = boost::add_edge(a, b, g).first;
    const auto e2 = boost::add_edge(b, a, g).first;
    capacity[e1] = ab;
    capacity[e2] = ba;
    reverse[e1] = e2;
    reverse[e2] = e1;
  };
  // Source side = 0, sink side = 1. A positive U(1) - U(0) is paid when v ends on the sink side: edge s -> v.
  double constant = constant_;
  for (Index v = 0; v < n; ++v) {
    const double d = unary_[size_t(v)];
    if (d > 0)
      add(s, Traits::vertex_descriptor(v), d, 0.0);
    else if (d < 0) {
      constant += d;  // U(1) - U(0) = d < 0: pay -d when v stays on the source side (x = 0)
      add(Traits::vertex_descriptor(v), t, -d, 0.0);
    }
  }
  for (const Edge& e : edges_)
    if (e.uv > 0 || e.vu > 0) add(Traits::vertex_descriptor(e.u), Traits::vertex_descriptor(e.v), e.uv, e.vu);
  std::vector<boost::default_color_type> color(size_t(n) + 2);
  std::vector<Traits::edge_descriptor> predecessor(size_t(n) + 2);
  std::vector<long> distance(size_t(n) + 2);
  const auto index = boost::get(boost::vertex_index, g);
  const double flow =
      boost::boykov_kolmogorov_max_flow(g, capacity, boost::get(boost::edge_residual_capacity, g), reverse,
                                        boost::make_iterator_property_map(predecessor.begin(), index),
                                        boost::make_iterator_property_map(color.begin(), index),
                                        boost::make_iterator_property_map(distance.begin(), index), index, s, t);
  // Vertices of the sink tree are white; source tree black; free (gray) ones may go either way: keep them at 0.
  for (Index v = 0; v < n; ++v) value_[size_t(v)] = color[size_t(v)] == boost::white_color;
  return constant + flow;
}

}  // namespace scanfill

#pragma GCC diagnostic pop
