#include "nodes/vote/vote.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <random>

#include "nodes/core/errors.h"
#include "nodes/vote/vote_options.h"

namespace scanfill {
namespace {

constexpr double kFlatSignature = 10.0;  // k2/k1 lies in [-1, 1]; flat points get a class of their own

// k2/k1 on a surface; on a curve of the plane (k2 = 0) the dimensionless k1 alpha, clamped into [-1, 1] (a curve has
// no scale-free signature of one sample: a scaled partner lies further off in signature, hence curve_matches).
double signature(const PointSet& p, Index i, double spacing, double flat, bool planar) {
  const double k1 = p.curvatures()(0, i), k2 = p.curvatures()(1, i);
  if (std::abs(k1) * spacing < flat) return kFlatSignature;
  return planar ? std::clamp(k1 * spacing, -1.0, 1.0) : k2 / k1;
}

Eigen::Matrix3d frame(const PointSet& p, Index i, int variant) {
  const Eigen::Vector3d n = p.normals().col(i);
  Eigen::Vector3d d1 = p.directions().col(i);
  // variants 0-3: d1 turned by 0, 180, 90, 270 degrees about n (the 4-fold ambiguity of a cross field)
  if (variant == 1) d1 = -d1;
  if (variant == 2) d1 = n.cross(d1);
  if (variant == 3) d1 = -n.cross(d1);
  Eigen::Matrix3d F;
  F.col(0) = d1;
  F.col(1) = n.cross(d1);
  F.col(2) = n;
  return F;
}

}  // namespace

VoteResult vote(const PointSet& source, const PointSet& target, double spacing, const VoteOptions& o) {
  check_options(o);  // the config checks these too; a direct caller gets the same checks
  for (const PointSet* p : {&source, &target})
    if (!p->has_normals() || !p->has_curvatures() || !p->has_directions())
      throw InputError("voting needs normals, curvatures and directions on both shapes (run features first)");
  if (source.size() == 0 || target.size() == 0) throw InputError("voting needs non-empty source and target");
  VoteResult result;
  Eigen::Matrix3Xd both(3, source.size() + target.size());
  both << source.positions(), target.positions();
  const BoundingBox box = bounding_box(o.axes ? Eigen::Matrix3Xd(o.axes->transpose() * both) : both);
  result.center = 0.5 * (box.min + box.max);
  if (o.axes) result.center = *o.axes * result.center;
  result.diagonal = std::max(box.diagonal(), 1e-12);
  result.weights = {o.rotation_weight, o.translation_weight, o.scale_weight};

  // Source points sorted by signature.
  std::vector<std::pair<double, std::int32_t>> by_sig(static_cast<size_t>(source.size()));
  for (Index i = 0; i < source.size(); ++i)
    by_sig[size_t(i)] = {signature(source, i, spacing, o.flat_curvature, o.planar), std::int32_t(i)};
  std::sort(by_sig.begin(), by_sig.end());

  // Voting target points: a seeded sample without replacement, of the curved points when there are enough.
  std::vector<std::int32_t> voters;
  for (Index t = 0; t < target.size(); ++t)
    if (signature(target, t, spacing, o.flat_curvature, o.planar) != kFlatSignature) voters.push_back(std::int32_t(t));
  if (double(voters.size()) < o.min_curved_fraction * double(target.size())) {
    voters.resize(static_cast<size_t>(target.size()));
    std::iota(voters.begin(), voters.end(), 0);
  }
  std::mt19937_64 rng(o.seed);
  const Index pool = Index(voters.size());
  const Index n_voters = std::min<Index>(o.target_samples, pool);
  for (Index k = 0; k < n_voters; ++k)
    std::swap(voters[size_t(k)], voters[size_t(k + Index(rng() % std::uint64_t(pool - k)))]);
  voters.resize(size_t(n_voters));
  std::sort(voters.begin(), voters.end());

  // Each voter's votes in its own slot range: deterministic order on any thread count.
  const int per_pair_max = 4;
  const int matches = o.planar ? o.curve_matches : o.matches_per_point;
  const size_t slot = size_t(matches) * per_pair_max;
  VoteMatrix all(13, Index(voters.size() * slot));
  std::vector<std::int32_t> owner(voters.size() * slot, -1);
  const double log_min = std::log(o.min_scale), log_max = std::log(o.max_scale);
  tbb::parallel_for(size_t(0), voters.size(), [&](size_t v) {
    const Index t = voters[v];
    const double sig = signature(target, t, spacing, o.flat_curvature, o.planar);
    const bool t_flat = sig == kFlatSignature;
    // The `matches` nearest signatures: expand a window around the insertion point.
    auto hi = std::lower_bound(by_sig.begin(), by_sig.end(), std::make_pair(sig, std::int32_t(-1)));
    auto lo = hi;
    size_t out = v * slot;
    for (int m = 0; m < matches && (lo != by_sig.begin() || hi != by_sig.end()); ++m) {
      const bool take_lo = hi == by_sig.end() || (lo != by_sig.begin() && sig - (lo - 1)->first <= hi->first - sig);
      const auto it = take_lo ? --lo : hi++;
      const Index s = it->second;
      if ((it->first == kFlatSignature) != t_flat) continue;
      double scale = 1.0;
      if (!t_flat) {
        const double ratio = target.curvatures()(0, t) / source.curvatures()(0, s);
        if (!(ratio > 0)) continue;  // opposite bending: no similarity maps one to the other
        if (o.allow_scale) {
          scale = ratio;
          if (std::log(scale) < log_min || std::log(scale) > log_max) continue;
        } else if (std::abs(std::log(ratio)) > std::log(1.5)) {
          continue;  // rigid: the curvatures must agree
        }
      }
      const bool umbilic =
          t_flat || std::abs(target.curvatures()(1, t)) > o.umbilic_ratio * std::abs(target.curvatures()(0, t));
      // In the plane, d1 = z x n fixes the frame: the other variants turn z over (a mirror image) or out of the plane.
      const int variants = o.planar ? 1 : umbilic ? 4 : 2;
      const Eigen::Matrix3d Fs = frame(source, s, 0);
      for (int var = 0; var < variants; ++var) {
        Similarity q;
        q.rotation = Fs * frame(target, t, var).transpose();
        q.scale = scale;
        q.translation = source.positions().col(s) - scale * q.rotation * target.positions().col(t);
        all.col(Index(out)) = embed(q, result);
        owner[out++] = std::int32_t(t);
      }
    }
  });
  Index count = 0;
  for (const auto w : owner) count += w >= 0;
  result.embedding.resize(13, count);
  result.voter.reserve(size_t(count));
  for (size_t k = 0; k < owner.size(); ++k)
    if (owner[k] >= 0) {
      result.embedding.col(Index(result.voter.size())) = all.col(Index(k));
      result.voter.push_back(owner[k]);
    }
  result.pairs = count;
  return result;
}

}  // namespace scanfill
