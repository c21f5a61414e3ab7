#include "nodes/symmetry/symmetry.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>

#include "nodes/core/disjoint_sets.h"
#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/core/surface_elements.h"
#include "nodes/procedural/normal_axis.h"
#include "nodes/symmetry/face_repeat.h"
#include "nodes/symmetry/symmetry_options.h"

namespace scanfill {
namespace {

Similarity rotation_about(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double angle) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  return Similarity{R, centre - R * centre, 1.0};
}

// The shape's samples and tree, with an even subsample to score rotations on.
struct Scorer {
  const PointSet& shape;
  KdTree tree;
  std::vector<Index> tests;
  double limit2 = 0, cos_limit = 0;

  Scorer(const PointSet& s, double spacing, const SymmetryOptions& o) : shape(s) {
    tree.build(shape.positions());
    const Index n = shape.size(), m = std::min(n, o.test_samples);
    for (Index i = 0; i < m; ++i) tests.push_back(i * n / m);
    limit2 = std::pow(o.distance * spacing, 2);
    cos_limit = std::cos(o.normal_angle_deg * M_PI / 180);
  }

  double overlap(const Similarity& q) const {
    std::vector<std::uint8_t> hit(tests.size(), 0);
    tbb::parallel_for(size_t(0), tests.size(), [&](size_t i) {
      const Index t = tests[i];
      std::int32_t j;
      double d2;
      tree.knn(q.apply(shape.positions().col(t)), 1, &j, &d2);
      hit[i] = d2 <= limit2 && q.apply_normal(shape.normals().col(t)).dot(shape.normals().col(j)) >= cos_limit;
    });
    return tests.empty() ? 0.0 : double(std::count(hit.begin(), hit.end(), 1)) / double(tests.size());
  }

  // The median distance of the test samples under q from the plane of the sample nearest each.
  double misfit(const Similarity& q) const {
    std::vector<double> d(tests.size());
    tbb::parallel_for(size_t(0), tests.size(), [&](size_t i) {
      const Eigen::Vector3d p = q.apply(shape.positions().col(tests[i]));
      std::int32_t j;
      double d2;
      tree.knn(p, 1, &j, &d2);
      d[i] = std::abs(shape.normals().col(j).dot(p - shape.positions().col(j)));
    });
    if (d.empty()) return 0.0;
    std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(d.size() / 2), d.end());
    return d[d.size() / 2];
  }
};

// The centre of a continuous axis along `axis`: the point the shape's normals meet it at (axis_along), where the
// shape's half turn about it fits the shape better than about `centre`, and it lies within two alpha of `centre`. The
// bounding box's centre or the centroid is the axis' only to a tenth of an alpha or so (uneven sampling, a model not
// closed), and a turn carries that error twice over: on the text2mesh vase's `revolution:` template, turns by 30, 90
// and 180 degrees about the box's centre fitted the template to 0.04, 0.11 and 0.15 alpha, which the labelling's
// unary (sigma_p 0.1 alpha) read as a preference for small turns; about the centre the normals meet, 0.02 alpha.
// Normals along the axis (a flat cap, a table leg's end) meet no point of it, and a point-to-plane misfit cannot see
// a flat part slide in its plane: such a part, with fewer than 16 elements facing over 30 degrees off the axis, keeps
// `centre`.
Eigen::Vector3d centre_of_turns(const Scorer& scorer, const Eigen::Vector3d& axis, const Eigen::Vector3d& centre,
                                double spacing) {
  const SurfaceElements elements = surface_elements(scorer.shape);
  Index facing_off_axis = 0;
  for (Index i = 0; i < elements.size(); ++i) facing_off_axis += elements.normals.col(i).cross(axis).norm() > 0.5;
  if (facing_off_axis < 16) return centre;
  const Eigen::Vector3d met = axis_along(elements, axis).centre;
  const Eigen::Vector3d off = met - centre;
  if ((off - off.dot(axis) * axis).norm() > 2 * spacing) return centre;
  return scorer.misfit(rotation_about(met, axis, M_PI)) < scorer.misfit(rotation_about(centre, axis, M_PI)) ? met
                                                                                                            : centre;
}

// x, y, z and the principal axes of the samples, without near-duplicates.
std::vector<Eigen::Vector3d> candidate_axes(const Eigen::Matrix3Xd& p, const Eigen::Vector3d& centre) {
  std::vector<Eigen::Vector3d> axes{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (Index i = 0; i < p.cols(); ++i) C += (p.col(i) - centre) * (p.col(i) - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C);
  for (int k = 2; k >= 0; --k) {
    Eigen::Vector3d a = eig.eigenvectors().col(k);
    Index largest = 0;
    a.cwiseAbs().maxCoeff(&largest);
    if (a(largest) < 0) a = -a;
    const bool known = std::any_of(axes.begin(), axes.end(), [&](const Eigen::Vector3d& b) {
      return std::abs(a.dot(b)) > std::cos(2 * M_PI / 180);
    });
    if (!known) axes.push_back(a);
  }
  return axes;
}

bool same_rotation(const Similarity& a, const Similarity& b, double tolerance) {
  return (a.rotation - b.rotation).norm() < 1e-3 && (a.translation - b.translation).norm() < tolerance;
}

// The group generated by `generators` (closed under composition), identity excluded, at most `max_size` elements.
std::vector<Similarity> close_group(const std::vector<Similarity>& generators, double tolerance, int max_size) {
  std::vector<Similarity> group{Similarity{}};
  for (size_t i = 0; i < group.size() && int(group.size()) <= max_size; ++i)
    for (const auto& g : generators) {
      Similarity h = g.compose(group[i]);
      h.rotation = nearest_rotation(h.rotation);
      const bool known =
          std::any_of(group.begin(), group.end(), [&](const Similarity& k) { return same_rotation(k, h, tolerance); });
      if (!known && int(group.size()) <= max_size) group.push_back(h);
    }
  group.erase(group.begin());
  return group;
}

// A fixed direction square to the unit axis a: the world's x made square to it, or its y where x lies within 30
// degrees of a.
Eigen::Vector3d square_reference(const Eigen::Vector3d& a) {
  Eigen::Vector3d e = Eigen::Vector3d::UnitX() - a.x() * a;
  if (e.norm() < 0.5) e = Eigen::Vector3d::UnitY() - a.y() * a;
  return e.normalized();
}

// The angle theta of the rotation G_theta about the unit axis a that picks one member of the family G_theta R: the one
// nearest the identity; when the whole family is about as far from it (R turns a over, as a flip does: every member
// has the same trace), the one that keeps a fixed reference direction e, perpendicular to a, best (e G_theta R e
// largest), so that a ring of flips is one mode as well.
double twist_to_identity(const Eigen::Matrix3d& R, const Eigen::Vector3d& a) {
  Eigen::Matrix3d across;  // [a]_x
  across << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  // trace(G_theta R) = a'Ra + cos(theta) (tr R - a'Ra) + sin(theta) tr([a]_x R): largest at theta = atan2(B, A).
  const double A = R.trace() - a.dot(R * a), B = (across * R).trace();
  if (std::hypot(A, B) > 0.25) return std::atan2(B, A);
  const Eigen::Vector3d e = square_reference(a);
  const Eigen::Vector3d r = R * e, r_perp = r - a.dot(r) * a;
  return std::atan2(e.dot(a.cross(r_perp)), e.dot(r_perp));
}

// Connected components of the kNN graph (8 neighbours within 3 alpha) over edges whose normals agree within
// `normal_angle_deg`, each ascending, ordered by their smallest sample. With `interior`, a sample whose normal
// disagrees with a neighbour's joins nothing (it stays a component of its own): the normals blended across a sharp
// edge then cannot chain two faces together.
std::vector<std::vector<std::int32_t>> smooth_components(const PointSet& shape, double spacing, double normal_angle_deg,
                                                         bool interior = false) {
  const Index n = shape.size();
  constexpr int k = 8;
  KdTree tree;
  tree.build(shape.positions());
  std::vector<double> d2;
  const std::vector<std::int32_t> graph = knn_graph(tree, shape.positions(), k, &d2);
  const double cos_limit = std::cos(normal_angle_deg * M_PI / 180), limit2 = std::pow(3 * spacing, 2);
  const auto edge = [&](Index i, int e) {  // a neighbour within reach
    return graph[size_t(i * k + e)] >= 0 && d2[size_t(i * k + e)] <= limit2;
  };
  const auto agree = [&](Index i, int e) {
    return shape.normals().col(i).dot(shape.normals().col(graph[size_t(i * k + e)])) >= cos_limit;
  };
  std::vector<std::uint8_t> joins(size_t(n), 1);
  if (interior)
    for (Index i = 0; i < n; ++i)
      for (int e = 0; e < k; ++e) joins[size_t(i)] = joins[size_t(i)] && (!edge(i, e) || agree(i, e));
  DisjointSets sets(n);
  for (Index i = 0; i < n; ++i)
    for (int e = 0; e < k; ++e) {
      if (!edge(i, e) || !agree(i, e)) continue;
      const std::int32_t j = graph[size_t(i * k + e)];
      if (joins[size_t(i)] && joins[size_t(j)]) sets.join(std::int32_t(i), j);
    }
  std::vector<std::vector<std::int32_t>> components;
  std::vector<std::int32_t> slot(static_cast<size_t>(n), -1);
  for (Index i = 0; i < n; ++i) {
    const std::int32_t r = sets.find(std::int32_t(i));
    if (slot[size_t(r)] < 0) {
      slot[size_t(r)] = std::int32_t(components.size());
      components.emplace_back();
    }
    components[size_t(slot[size_t(r)])].push_back(std::int32_t(i));
  }
  return components;
}

// Q o R as a mode: it explains t when R t lies on Q's `support`, so its voters are the samples nearest R^-1 u for u in
// the support (within `reach` of it, when R carries only part of T onto T).
Mode composed_mode(const Similarity& q, const Similarity& r, const std::vector<std::int32_t>& support,
                   const PointSet& target, const KdTree& tree, double reach = std::numeric_limits<double>::infinity()) {
  const Similarity r_inv = r.inverse();
  Mode m;
  m.transform = q.compose(r);
  m.voters.resize(support.size());
  tbb::parallel_for(size_t(0), support.size(), [&](size_t i) {
    double d2;
    tree.knn(r_inv.apply(target.positions().col(support[i])), 1, &m.voters[i], &d2);
    if (d2 > reach * reach) m.voters[i] = -1;
  });
  std::sort(m.voters.begin(), m.voters.end());
  m.voters.erase(std::unique(m.voters.begin(), m.voters.end()), m.voters.end());
  if (!m.voters.empty() && m.voters.front() < 0) m.voters.erase(m.voters.begin());
  m.votes = Index(m.voters.size());
  return m;
}

// Q composed with the turns of each part that Q's support reaches, about the part's own axis (every 360 / `turns`
// degrees); only the support on the part votes, since a part's turn moves the rest of T off itself.
void append_part_turns(const Similarity& q, const std::vector<std::int32_t>& support,
                       const std::vector<PartSymmetry>& parts, int turns, const PointSet& target, const KdTree& tree,
                       std::vector<Mode>& out) {
  for (const PartSymmetry& part : parts) {
    std::vector<std::int32_t> on_part;
    std::set_intersection(support.begin(), support.end(), part.samples.begin(), part.samples.end(),
                          std::back_inserter(on_part));
    if (on_part.empty()) continue;
    for (int k = 1; k < turns; ++k)
      out.push_back(composed_mode(q, rotation_about(part.axis.centre, part.axis.direction, 2 * M_PI * k / turns),
                                  on_part, target, tree));
  }
}

// The turn about `up` by a multiple of 90 degrees that carries face `a` onto face `b`, centre onto centre; none when
// either face is not upright or their normals are not a quarter or half turn apart (within 3 degrees).
std::optional<Similarity> face_turn(const PlanarFace& a, const PlanarFace& b, const Eigen::Vector3d& up) {
  const double upright = std::sin(5 * M_PI / 180);
  if (std::abs(a.normal.dot(up)) > upright || std::abs(b.normal.dot(up)) > upright) return std::nullopt;
  const double angle = std::atan2(up.dot(a.normal.cross(b.normal)), a.normal.dot(b.normal));
  const double quarters = std::round(angle / (M_PI / 2));
  if (quarters == 0 || std::abs(angle - quarters * M_PI / 2) > 3 * M_PI / 180) return std::nullopt;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(quarters * M_PI / 2, up).toRotationMatrix();
  return Similarity{R, b.centre - R * a.centre, 1.0};
}

// The exemplar (in the source's frame, with normals) and a tree over its positions.
struct FaceExemplar {
  const PointSet& points;
  const KdTree& tree;
};

// The exemplar's samples on face A as Q sees it: those whose image under Q^-1 lies within 4 alpha of Q's support on A
// (`on_a`, ascending), nearest to it; relief stands off the plain template by up to that.
std::vector<std::int32_t> exemplar_on_face(const FaceExemplar& exemplar, const Similarity& q,
                                           const std::vector<std::int32_t>& on_a, const KdTree& tree, double spacing) {
  const Similarity q_inv = q.inverse();
  std::vector<std::int32_t> near;
  for (Index e = 0; e < exemplar.points.size(); ++e) {
    std::int32_t t;
    double d2;
    if (tree.knn(q_inv.apply(exemplar.points.positions().col(e)), 1, &t, &d2) == 1 && d2 <= std::pow(4 * spacing, 2) &&
        std::binary_search(on_a.begin(), on_a.end(), t))
      near.push_back(std::int32_t(e));
  }
  return near;
}

// The samples' extent along `direction`, each mapped by `map` first.
std::pair<double, double> extent_along(const Eigen::Matrix3Xd& positions, const std::vector<std::int32_t>& samples,
                                       const Similarity& map, const Eigen::Vector3d& direction) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const std::int32_t i : samples) {
    const double u = direction.dot(map.apply(positions.col(i)));
    lo = std::min(lo, u);
    hi = std::max(hi, u);
  }
  return {lo, hi};
}

// The shifts along A that bring B's turned end, `gap` past A's edge, onto A in phase with the exemplar's relief, A
// being `width` wide: each the smallest multiple of the period that reaches the end within an alpha, or else the
// largest whose image still joins the images before it (at most 8); for a plain face, any shift is in phase.
std::vector<double> phase_shifts(const FaceRepeat& repeat, double gap, double width, double spacing) {
  std::vector<double> shifts;
  double reached = 0;  // how far past A's edge the images so far reach
  while (reached < gap - spacing && shifts.size() < 8) {
    double shift = std::min(gap, reached + width);
    if (repeat.period > 0) {
      const double p = repeat.period;
      shift = std::min(std::ceil((gap - spacing) / p) * p, std::floor((reached + width) / p) * p);
    }
    if (shift <= reached) break;  // a period longer than A: no image joins
    shifts.push_back(shift);
    reached = shift;
  }
  return shifts;
}

// The exemplar's repeat along face A as Q sees it (repeat_along, in T's units), where Q's support holds most of A (the
// exemplar shows it); none elsewhere.
std::optional<FaceRepeat> repeat_on_face(const Similarity& q, const std::vector<std::int32_t>& on_a,
                                         const PlanarFace& a, const Eigen::Vector3d& along,
                                         std::pair<double, double> a_extent, const FaceExemplar& exemplar,
                                         double spacing, const KdTree& tree) {
  if (2 * on_a.size() < a.samples.size()) return std::nullopt;
  const auto [lo, hi] = a_extent;
  const auto repeat = repeat_along(exemplar.points, exemplar.tree, exemplar_on_face(exemplar, q, on_a, tree, spacing),
                                   (q.rotation * along).normalized(), spacing * q.scale, 0.5 * (hi - lo) * q.scale);
  if (!repeat) return std::nullopt;
  return FaceRepeat{repeat->period / q.scale};
}

// Where face B, turned onto face A centre onto centre, reaches past A's edges along A (B is the wider): the turn
// composed with shifts along A that carry B's ends onto A, by multiples of the exemplar's own `repeat` along A, so that
// the ends take A's relief in phase with B's middle.
void append_shifted_turns(const Similarity& q, const std::vector<std::int32_t>& on_a,
                          std::pair<double, double> a_extent, const PlanarFace& b, const Similarity& turn,
                          const Eigen::Vector3d& along, const FaceRepeat& repeat, double spacing, double reach,
                          const PointSet& target, const KdTree& tree, std::vector<Mode>& out) {
  const auto [a_lo, a_hi] = a_extent;
  const auto [b_lo, b_hi] = extent_along(target.positions(), b.samples, turn, along);
  for (const auto& [gap, sign] : {std::pair{b_hi - a_hi, -1.0}, std::pair{a_lo - b_lo, 1.0}}) {
    if (gap <= 2 * spacing) continue;
    for (const double shift : phase_shifts(repeat, gap, a_hi - a_lo, spacing)) {
      const Similarity shifted = Similarity{Eigen::Matrix3d::Identity(), sign * shift * along, 1.0}.compose(turn);
      out.push_back(composed_mode(q, shifted, on_a, target, tree, reach));
    }
  }
}

// Q composed with the turns about `up` that carry a face B of T onto a face A that Q's support reaches (face_turn),
// where no symmetry in `group` is that turn; only the support on A votes. With the exemplar, also the turns shifted
// along A onto B's ends where B is the wider and the exemplar repeats along A (append_shifted_turns).
void append_face_turns(const Similarity& q, const std::vector<std::int32_t>& support,
                       const std::vector<PlanarFace>& faces, const std::vector<Similarity>& group,
                       const Eigen::Vector3d& up, double spacing, double reach, const PointSet& target,
                       const KdTree& tree, const FaceExemplar* exemplar, std::vector<Mode>& out) {
  for (const PlanarFace& a : faces) {
    std::vector<std::int32_t> on_a;
    std::set_intersection(support.begin(), support.end(), a.samples.begin(), a.samples.end(), std::back_inserter(on_a));
    if (on_a.empty()) continue;
    const Eigen::Vector3d along = up.cross(a.normal).normalized();
    const auto a_extent = extent_along(target.positions(), a.samples, Similarity{}, along);
    std::optional<std::optional<FaceRepeat>> repeat;  // measured once per face, when a turn first needs it
    for (const PlanarFace& b : faces) {
      const auto turn = face_turn(b, a, up);  // T -> T: B onto A
      if (!turn) continue;
      const bool symmetry = std::any_of(group.begin(), group.end(),
                                        [&](const Similarity& g) { return same_rotation(g, *turn, 3 * spacing); });
      if (symmetry) continue;
      out.push_back(composed_mode(q, *turn, on_a, target, tree, reach));
      if (!exemplar) continue;
      if (!repeat) repeat = repeat_on_face(q, on_a, a, along, a_extent, *exemplar, spacing, tree);
      if (*repeat)
        append_shifted_turns(q, on_a, a_extent, b, *turn, along, **repeat, spacing, reach, target, tree, out);
    }
  }
}

// The samples of each connected component of `mesh`'s faces, by each sample's nearest vertex on a face: the pieces a
// template was modelled from (a table's top and legs), which a junction's blended normals cannot join. Ascending,
// ordered by their smallest sample.
std::vector<std::vector<std::int32_t>> mesh_components(const PointSet& shape, const PointSet& mesh) {
  std::vector<char> used(static_cast<size_t>(mesh.size()), 0);
  DisjointSets sets(mesh.size());
  for (Index f = 0; f < mesh.faces().cols(); ++f)
    for (int c = 0; c < 3; ++c) {
      used[size_t(mesh.faces()(c, f))] = 1;
      if (c > 0) sets.join(mesh.faces()(0, f), mesh.faces()(c, f));
    }
  std::vector<std::int32_t> on_face;
  for (Index v = 0; v < mesh.size(); ++v)
    if (used[size_t(v)]) on_face.push_back(std::int32_t(v));
  const Eigen::Matrix3Xd vertices = subset(mesh, on_face).positions();
  KdTree tree;
  tree.build(vertices);
  std::vector<std::int32_t> nearest;
  std::vector<double> d2;
  nearest_each(tree, shape.positions(), nearest, d2);
  std::vector<std::vector<std::int32_t>> components;
  std::vector<std::int32_t> slot(static_cast<size_t>(mesh.size()), -1);
  for (Index i = 0; i < shape.size(); ++i) {
    const std::int32_t r = sets.find(on_face[size_t(nearest[size_t(i)])]);
    if (slot[size_t(r)] < 0) {
      slot[size_t(r)] = std::int32_t(components.size());
      components.emplace_back();
    }
    components[size_t(slot[size_t(r)])].push_back(std::int32_t(i));
  }
  return components;
}

// Whether two axes are the same line (parallel, and each centre within `tolerance` of the other's line).
bool same_line(const SymmetryAxis& a, const SymmetryAxis& b, double tolerance) {
  if (std::abs(a.direction.dot(b.direction)) < std::cos(2 * M_PI / 180)) return false;
  const Eigen::Vector3d d = b.centre - a.centre;
  return (d - d.dot(a.direction) * a.direction).norm() < tolerance;
}

}  // namespace

std::vector<PartSymmetry> find_part_symmetries(const PointSet& shape, double spacing, const SymmetryResult& global,
                                               const SymmetryOptions& o, const PointSet* mesh) {
  check_options(o);
  std::vector<PartSymmetry> parts;
  if (!o.enabled || !o.parts || o.planar || shape.size() < 10) return parts;
  if (!shape.has_normals()) throw InvariantError("symmetry needs normals");
  SymmetryOptions whole = o;
  whole.parts = false;
  const bool faces = mesh && mesh->faces().cols() > 0;
  for (auto& samples :
       faces ? mesh_components(shape, *mesh) : smooth_components(shape, spacing, o.part_normal_angle_deg)) {
    if (Index(samples.size()) < o.part_min_samples || double(samples.size()) > 0.9 * double(shape.size())) continue;
    const SymmetryResult own = find_symmetries(subset(shape, samples), spacing, whole);
    if (!own.continuous) continue;
    // A part about the shape's own axis (a cylinder's cap, a vase's foot) adds nothing to the global symmetry.
    const bool global_axis = std::any_of(global.axes.begin(), global.axes.end(), [&](const SymmetryAxis& a) {
      return a.order == 0 && same_line(a, *own.continuous, 2 * spacing);
    });
    if (global_axis) continue;
    // A cylinder's side and its caps are one part: the same turns.
    const auto same = std::find_if(parts.begin(), parts.end(), [&](const PartSymmetry& p) {
      return same_line(p.axis, *own.continuous, 2 * spacing);
    });
    if (same == parts.end()) {
      parts.push_back({*own.continuous, std::move(samples)});
      continue;
    }
    std::vector<std::int32_t> both;
    std::merge(same->samples.begin(), same->samples.end(), samples.begin(), samples.end(), std::back_inserter(both));
    same->samples = std::move(both);
  }
  return parts;
}

std::vector<PlanarFace> find_planar_faces(const PointSet& shape, double spacing, const SymmetryOptions& o) {
  check_options(o);
  std::vector<PlanarFace> faces;
  if (!o.enabled || !o.face_turns || o.planar || shape.size() < 10) return faces;
  if (!shape.has_normals()) throw InvariantError("symmetry needs normals");
  const double flat = std::cos(5 * M_PI / 180);
  for (auto& samples : smooth_components(shape, spacing, 5.0, true)) {
    if (Index(samples.size()) < o.part_min_samples) continue;
    const PointSet face = subset(shape, samples);
    const Eigen::Vector3d normal = face.normals().rowwise().sum().normalized();
    if ((normal.transpose() * face.normals()).minCoeff() < flat) continue;
    faces.push_back({normal, face.positions().rowwise().mean(), std::move(samples)});
  }
  return faces;
}

SymmetryResult find_symmetries(const PointSet& shape, double spacing, const SymmetryOptions& o) {
  check_options(o);
  SymmetryResult result;
  if (!o.enabled || shape.size() < 10) return result;
  if (!shape.has_normals()) throw InvariantError("symmetry needs normals");
  const Scorer scorer(shape, spacing, o);
  // The axis passes through the centre of symmetry: the bounding box's centre for an axis-aligned one, the centroid
  // for a tilted one (neither is exact for the other kind, and the centroid moves with uneven sampling).
  const Eigen::Vector3d centroid = shape.positions().rowwise().mean();
  const BoundingBox box = bounding_box(shape.positions());
  const Eigen::Vector3d box_centre = (box.min + box.max) / 2;
  // Angles no order up to 12 explains: a rotation that holds at all of them is continuous.
  const double continuous_deg[] = {7.0, 47.0, 133.0};
  std::vector<Similarity> generators;
  const std::vector<Eigen::Vector3d> axes =
      o.planar ? std::vector<Eigen::Vector3d>{Eigen::Vector3d::UnitZ()} : candidate_axes(shape.positions(), centroid);
  for (const auto& axis : axes) {
    // The centre that fits the axis better, judged on a half turn or the smallest continuous test angle.
    const auto score_at = [&](const Eigen::Vector3d& c) {
      return std::max(scorer.overlap(rotation_about(c, axis, M_PI)),
                      scorer.overlap(rotation_about(c, axis, continuous_deg[0] * M_PI / 180)));
    };
    const Eigen::Vector3d centre = score_at(box_centre) >= score_at(centroid) ? box_centre : centroid;
    const bool continuous = std::all_of(std::begin(continuous_deg), std::end(continuous_deg), [&](double deg) {
      return scorer.overlap(rotation_about(centre, axis, deg * M_PI / 180)) >= o.min_overlap;
    });
    if (continuous) {
      const SymmetryAxis a{centre_of_turns(scorer, axis, centre, spacing), axis, 0};
      result.axes.insert(result.axes.begin(), a);
      if (!result.continuous) result.continuous = a;
      generators.push_back(rotation_about(a.centre, axis, 2 * M_PI / o.continuous_steps));
      continue;
    }
    // A turn of odd order holds about neither test above: a triangular prism's box centre is off its axis, and
    // its turns by a third hold only about its centroid. Each order is tried about the other centre too.
    const Eigen::Vector3d other = centre == box_centre ? centroid : box_centre;
    for (int n = o.max_order; n >= 2; --n) {
      const auto holds_about = [&](const Eigen::Vector3d& c) {
        return scorer.overlap(rotation_about(c, axis, 2 * M_PI / n)) >= o.min_overlap;
      };
      const std::optional<Eigen::Vector3d> at = holds_about(centre)  ? std::optional(centre)
                                                : holds_about(other) ? std::optional(other)
                                                                     : std::nullopt;
      if (!at) continue;
      result.axes.push_back({*at, axis, n});
      generators.push_back(rotation_about(*at, axis, 2 * M_PI / n));
      break;
    }
  }
  result.rotations = close_group(generators, spacing, o.max_group);
  return result;
}

Similarity nearest_identity_member(const Similarity& q, const SymmetryAxis& axis) {
  return rotation_about(axis.centre, axis.direction, twist_to_identity(q.rotation, axis.direction)).compose(q);
}

std::optional<SymmetryAxis> principal_axis(const SymmetryResult& symmetry) {
  if (symmetry.continuous) return symmetry.continuous;
  const SymmetryAxis* highest = nullptr;
  bool unique = false;
  for (const auto& a : symmetry.axes) {
    if (!highest || a.order > highest->order) {
      highest = &a;
      unique = true;
    } else if (a.order == highest->order) {
      unique = false;
    }
  }
  if (highest && unique) return *highest;
  return std::nullopt;
}

std::optional<Eigen::Vector3d> upright_axis(const SymmetryResult& symmetry) {
  const auto axis = principal_axis(symmetry);
  if (axis) return axis->direction;
  return std::nullopt;
}

std::optional<Eigen::Matrix3d> object_axes(const SymmetryResult& symmetry) {
  if (symmetry.axes.empty()) return std::nullopt;
  const auto principal = principal_axis(symmetry);
  const Eigen::Vector3d z = (principal ? principal->direction : symmetry.axes.front().direction).normalized();
  const SymmetryAxis* square = nullptr;
  for (const auto& a : symmetry.axes)
    if (std::abs(a.direction.dot(z)) <= std::sin(10 * M_PI / 180) &&
        (!square || std::abs(a.direction.dot(z)) < std::abs(square->direction.dot(z))))
      square = &a;
  Eigen::Matrix3d frame;
  frame.col(0) =
      square ? Eigen::Vector3d((square->direction - square->direction.dot(z) * z).normalized()) : square_reference(z);
  frame.col(2) = z;
  frame.col(1) = z.cross(frame.col(0));
  if (is_axis_rotation(frame, M_PI / 180)) return std::nullopt;
  return frame;
}

void quotient_votes(VoteResult& votes, const SymmetryAxis& axis) {
  tbb::parallel_for(Index(0), votes.embedding.cols(), [&](Index v) {
    votes.embedding.col(v) = embed(nearest_identity_member(unembed(votes.embedding.col(v), votes), axis), votes);
  });
}

void snap_to_family_representatives(std::vector<SupportedTransform>& transforms, const SymmetryAxis& axis) {
  for (auto& t : transforms) t.transform = nearest_identity_member(t.transform, axis);
}

std::vector<Mode> composed_candidates(const std::vector<SupportedTransform>& found,
                                      const SymmetryResult& target_symmetry, const PointSet& target, double spacing,
                                      const Eigen::Vector3d& up, const SymmetryOptions& o, const PointSet* exemplar,
                                      const Similarity& exemplar_to_source) {
  std::vector<Mode> out;
  const bool faces = o.face_turns && target_symmetry.faces.size() > 1;
  if (!o.enabled || (target_symmetry.rotations.empty() && target_symmetry.parts.empty() && !faces) || found.empty())
    return out;
  KdTree tree, exemplar_tree;
  tree.build(target.positions());
  const PointSet registered =
      exemplar && exemplar->has_normals() && faces ? moved_by(*exemplar, exemplar_to_source) : PointSet{};
  if (!registered.empty()) exemplar_tree.build(registered.positions());
  const std::optional<FaceExemplar> face_exemplar =
      registered.empty() ? std::nullopt : std::optional<FaceExemplar>(FaceExemplar{registered, exemplar_tree});
  const size_t bases = std::min<size_t>(found.size(), size_t(std::max(0, o.max_base_transforms)));
  for (size_t b = 0; b < bases; ++b) {
    const SupportedTransform& q = found[b];
    // On a continuous axis of T, ICP lets Q slide freely: snap it first to the member of its family whose rotation
    // is nearest the identity, so that its compositions fall on the axis rotations eq. 9 prefers.
    Similarity base = q.transform;
    std::vector<Similarity> with{};
    if (const auto& axis = target_symmetry.continuous) {
      base = base.compose(
          rotation_about(axis->centre, axis->direction, twist_to_identity(base.rotation, axis->direction)));
      with.push_back(Similarity{});
    }
    with.insert(with.end(), target_symmetry.rotations.begin(), target_symmetry.rotations.end());
    for (const Similarity& r : with) out.push_back(composed_mode(base, r, q.support, target, tree));
    if (o.parts) append_part_turns(base, q.support, target_symmetry.parts, o.part_turns, target, tree, out);
    if (faces)
      append_face_turns(base, q.support, target_symmetry.faces, target_symmetry.rotations, up, spacing,
                        o.distance * spacing, target, tree, face_exemplar ? &*face_exemplar : nullptr, out);
  }
  return out;
}

std::vector<Mode> upright_turns(const std::vector<SupportedTransform>& found, const SymmetryResult& target_symmetry,
                                const PointSet& target, const Eigen::Vector3d& up) {
  const double kUpright = std::cos(3 * M_PI / 180);  // the up direction kept within 3 degrees
  std::vector<Mode> out;
  if (target_symmetry.continuous) return out;
  KdTree tree;
  for (const SupportedTransform& q : found)
    for (const Similarity& r : target_symmetry.rotations) {
      if (up.dot(q.transform.compose(r).rotation * up) < kUpright) continue;
      if (out.empty()) tree.build(target.positions());
      out.push_back(composed_mode(q.transform, r, q.support, target, tree));
    }
  return out;
}

std::vector<Mode> axis_quarter_turns(const std::vector<SupportedTransform>& found,
                                     const SymmetryResult& target_symmetry, const PointSet& target) {
  std::vector<Mode> out;
  const auto& axis = target_symmetry.continuous;
  if (!axis || found.empty()) return out;
  // The strongest transform whose family holds the identity (within 10 degrees): not a flip end over end.
  const auto q = std::find_if(found.begin(), found.end(), [&](const SupportedTransform& st) {
    return rotation_angle(nearest_identity_member(st.transform, *axis).rotation) < 10 * M_PI / 180;
  });
  if (q == found.end()) return out;
  const Similarity base = nearest_identity_member(q->transform, *axis);
  KdTree tree;
  tree.build(target.positions());
  for (int k = 0; k < 4; ++k)
    out.push_back(
        composed_mode(base, rotation_about(axis->centre, axis->direction, k * M_PI / 2), q->support, target, tree));
  return out;
}

}  // namespace scanfill
