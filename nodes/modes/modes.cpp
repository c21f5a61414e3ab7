#include "nodes/modes/modes.h"
#include "nodes/modes/modes_options.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <flann/flann.hpp>
#include <map>

namespace scanfill {

double mode_accuracy(const VoteResult& votes, const ModesOptions& o) {
  return o.bandwidth * votes.diagonal / votes.weights.translation;
}

ModesResult find_modes(const VoteResult& votes, const ModesOptions& o) {
  check_options(o);  // the config checks these too; a direct caller gets the same checks
  ModesResult result;
  const Index n = votes.embedding.cols();
  if (n == 0) return result;
  using Vec = Eigen::Matrix<double, 13, 1>;
  // FLANN reads the 13 by V column-major matrix as V rows of 13.
  flann::Matrix<double> data(const_cast<double*>(votes.embedding.data()), size_t(n), 13);
  flann::Index<flann::L2<double>> index(data, flann::KDTreeSingleIndexParams(16));
  index.buildIndex();
  const float radius2 = float(o.bandwidth * o.bandwidth);

  // Seeds: centroids of the most populated bins.
  std::map<std::array<std::int64_t, 13>, std::pair<Index, Vec>> bins;
  for (Index i = 0; i < n; ++i) {
    std::array<std::int64_t, 13> key;
    for (int d = 0; d < 13; ++d) key[size_t(d)] = std::int64_t(std::floor(votes.embedding(d, i) / o.bandwidth));
    auto& bin = bins[key];
    if (bin.first == 0) bin.second.setZero();
    ++bin.first;
    bin.second += votes.embedding.col(i);
  }
  std::vector<std::pair<Index, Vec>> seeds;
  for (const auto& [key, bin] : bins) seeds.push_back({bin.first, bin.second / double(bin.first)});
  std::stable_sort(seeds.begin(), seeds.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  if (Index(seeds.size()) > o.max_seeds) seeds.resize(size_t(o.max_seeds));
  result.seeds = Index(seeds.size());

  // Mean shift from each seed, in parallel.
  std::vector<std::pair<Index, Vec>> converged(seeds.size());
  tbb::parallel_for(size_t(0), seeds.size(), [&](size_t k) {
    Vec x = seeds[k].second;
    std::vector<std::vector<size_t>> idx;
    std::vector<std::vector<double>> dist;
    Index support = 0;
    for (int it = 0; it < o.max_iterations; ++it) {
      flann::Matrix<double> q(x.data(), 1, 13);
      index.radiusSearch(q, idx, dist, radius2, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED, 0, false));
      support = Index(idx[0].size());
      if (support == 0) break;
      Vec mean = Vec::Zero();
      for (const size_t j : idx[0]) mean += votes.embedding.col(Index(j));
      mean /= double(support);
      const double shift = (mean - x).norm();
      x = mean;
      if (shift < 1e-3 * o.bandwidth) break;
    }
    converged[k] = {support, x};
  });

  // Merge modes closer than the bandwidth, strongest first.
  std::stable_sort(converged.begin(), converged.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Vec> kept;
  for (const auto& [support, x] : converged) {
    if (support < o.min_votes || Index(kept.size()) >= o.max_modes) continue;
    bool near = false;
    for (const Vec& y : kept) near = near || (x - y).norm() < o.bandwidth;
    if (near) continue;
    kept.push_back(x);
    Mode mode;
    mode.transform = unembed(x, votes);
    std::vector<std::vector<size_t>> idx;
    std::vector<std::vector<double>> dist;
    Vec xq = x;
    flann::Matrix<double> q(xq.data(), 1, 13);
    index.radiusSearch(q, idx, dist, radius2, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED, 0, false));
    mode.votes = Index(idx[0].size());
    for (const size_t j : idx[0]) mode.voters.push_back(votes.voter[j]);
    std::sort(mode.voters.begin(), mode.voters.end());
    mode.voters.erase(std::unique(mode.voters.begin(), mode.voters.end()), mode.voters.end());
    result.modes.push_back(std::move(mode));
  }
  std::stable_sort(result.modes.begin(), result.modes.end(),
                   [](const Mode& a, const Mode& b) { return a.votes > b.votes; });
  return result;
}

}  // namespace scanfill
