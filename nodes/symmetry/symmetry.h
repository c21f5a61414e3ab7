// symmetry node: the global rotational symmetries of a shape, and the candidates they imply (DESIGN section 9).
//
// Templates are simple on purpose, and simple shapes are symmetric. Pair voting sees a symmetry in two ways, both bad:
// - a continuous symmetry of the source S (a body of revolution, a disk) spreads one correct motion into a ring of
//   equivalent modes, which fills the mode budget before the motion to another part of T is found;
// - a discrete symmetry of the target T (the quarter turns of a box, the half turn between two equal bodies) is a
//   candidate the labelling needs (the paper's eq. 9 prefers kappa pi / 2 rotations), but voting finds it only when
//   the unseen part has curvature of its own to vote with.
// So the symmetries are found directly. A rotation by angle theta about an axis through the shape's centroid holds when
// at least `min_overlap` of the shape's samples (an even subsample of `test_samples`), rotated, land within
// `distance` alpha of a sample whose normal agrees within `normal_angle_deg`. The axes tried are x, y, z and the
// shape's principal axes (templates are drawn axis-aligned, and the paper assumes aligned inputs). An axis that holds
// at the `continuous` test angles, which no small order explains, is continuous (a body of revolution); otherwise the
// largest order n <= `max_order` whose 2 pi / n rotation holds is its discrete order. A continuous axis then passes
// through the point the shape's normals meet it at, where its half turn fits better there: the box's centre and the
// centroid are the axis' only to a tenth of an alpha, and every turn about it carries that error twice over. The
// discrete symmetries are closed under composition (the group of a box is 8 rotations, not 4 + 2) up to `max_group`
// elements.
//
// Deviations and choices: only proper rotations (voting has no reflections either); translational symmetry (a row of
// legs) is not searched globally: its repeats are partial symmetries that voting finds. A continuous axis is sampled
// every 360 / `continuous_steps` degrees: the phase between those steps is fixed later against the exemplar
// (synthesize's slippage search), as DESIGN section 9 says.
#pragma once

#include <optional>
#include <vector>

#include "nodes/core/analogy.h"
#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"

namespace scanfill {

struct SymmetryOptions {
  bool enabled = true;                // find symmetries and compose candidates; false = plain voting only
  double distance = 1.5;              // a rotated sample must land this close (alpha) to a sample; > 0
  double normal_angle_deg = 30;       // with normals within this angle; (0, 180]
  double min_overlap = 0.9;           // share of samples that must land on the shape; (0, 1]
  int max_order = 8;                  // largest discrete order n tried per axis; [2, 64]
  int continuous_steps = 12;          // a continuous axis offers rotations every 360 / this degrees; [2, 360]
  int max_group = 48;                 // most discrete symmetries kept; [1, 1000]
  Index test_samples = 3000;          // samples each rotation is scored on (an even subsample); >= 10
  int max_base_transforms = 6;        // found transforms composed with the symmetries, strongest first; >= 0
  bool parts = true;                  // also the turns of each part of T about its own continuous axis (a table's legs)
  double part_normal_angle_deg = 45;  // neighbouring samples are in one part when their normals agree this well
  Index part_min_samples = 100;       // smaller parts are not searched; >= 10
  int part_turns = 4;                 // a part's axis offers the turns by multiples of 360 / this degrees; [2, 360]
  bool face_turns = true;  // also the quarter turns about the up axis between flat faces of T that its symmetries do
                           // not relate (the long and the short sides of a box that is not square)
  bool planar = false;     // only the z axis (mode curves; set by the engine, no key): a half turn about an axis of the
                           // plane maps a drawing to its mirror image, which is no motion of the plane
};

struct SymmetryAxis {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit
  int order = 0;                                         // 0 = continuous, else n-fold
};

// A part of the shape (a leg of a table) that is a body of revolution about an axis of its own, not the shape's.
struct PartSymmetry {
  SymmetryAxis axis;                  // continuous (order 0)
  std::vector<std::int32_t> samples;  // the part's samples, ascending
};

// A flat face of the shape (a side of a box): its samples, their mean normal and their centroid.
struct PlanarFace {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::vector<std::int32_t> samples;  // ascending
};

struct SymmetryResult {
  std::vector<SymmetryAxis> axes;          // axes with a symmetry, continuous ones first
  std::vector<Similarity> rotations;       // the symmetry group (identity excluded): shape -> shape
  std::optional<SymmetryAxis> continuous;  // the first continuous axis, if any
  std::vector<PartSymmetry> parts;         // parts symmetric about their own axis (find_part_symmetries)
  std::vector<PlanarFace> faces;           // flat faces (find_planar_faces)
};

// `shape` needs normals; `spacing` is alpha. Deterministic.
SymmetryResult find_symmetries(const PointSet& shape, double spacing, const SymmetryOptions& options);

// The parts of `shape` that are bodies of revolution about their own axis, which is none of `global`'s continuous
// axes: a table's turned legs, each a symmetry of a part, not of the whole (DESIGN section 9). Parts are the connected
// components of `mesh`'s faces when `shape` was sampled from a mesh (`mesh`, in the same frame), else of the kNN
// graph (8 neighbours within 3 alpha) whose edges join samples with normals within `part_normal_angle_deg` (a sharp
// edge splits parts; the blended normals where a leg meets a top may not). Each part of at least `part_min_samples`
// samples and at most 90% of the shape is tested as a shape of its own by find_symmetries; parts about one axis (a
// cylinder's side and caps) are one. Deterministic.
std::vector<PartSymmetry> find_part_symmetries(const PointSet& shape, double spacing, const SymmetryResult& global,
                                               const SymmetryOptions& options, const PointSet* mesh = nullptr);

// The flat faces of `shape`: the connected components of the kNN graph (8 neighbours within 3 alpha) over samples
// whose normals agree within 5 degrees with every neighbour's (a box's edges, where sampled normals blend, split them)
// that hold at least `part_min_samples` samples, every normal within 5 degrees of their mean. Empty unless
// `face_turns`. Deterministic.
std::vector<PlanarFace> find_planar_faces(const PointSet& shape, double spacing, const SymmetryOptions& options);

// The direction a symmetric object stands along: its continuous axis, else its discrete axis of highest order when
// no other axis has that order, else nothing (the symmetry does not tell). A vase or a cylinder drawn y-up gives y; a
// box with a square footprint gives the axis of its quarter turns; a cube or a shape without symmetry gives nothing.
std::optional<Eigen::Vector3d> upright_axis(const SymmetryResult& symmetry);
// That axis itself (its centre, direction and order).
std::optional<SymmetryAxis> principal_axis(const SymmetryResult& symmetry);

// The shape's own axes, the columns of a rotation: its principal symmetry axis (else its first), the symmetry axis
// most nearly square to that (within 10 degrees; else the world's x, or y where x is within 30 degrees of it, made
// square to it), and their cross product; nullopt without a symmetry axis, or where the frame lies within a degree of
// the world's axes (a model drawn square to them keeps them). A box standing turned in the scan's frame has its own
// box's axes: the vote space is sized by the bounding box in them (vote), and eq. 9's axis rotations are theirs
// (label).
std::optional<Eigen::Matrix3d> object_axes(const SymmetryResult& symmetry);

// Votes modulo the source's continuous symmetry about `axis`: every vote Q (target -> source) is replaced by the
// member of its family G_theta o Q (G_theta the rotation about the axis, which leaves S unchanged) whose rotation is
// nearest the identity, so that a ring of equivalent motions becomes one mode. Its phase is fixed later.
void quotient_votes(VoteResult& votes, const SymmetryAxis& axis);

// G_theta o Q, the member of Q's family about the source's continuous `axis` whose rotation is nearest the identity.
Similarity nearest_identity_member(const Similarity& q, const SymmetryAxis& axis);

// After support's ICP, which slides a transform freely along the source's continuous symmetry (a disk turns on
// itself), each found transform is put back on its family's representative, as its votes were: the phase ICP drifted
// to says nothing (the source has no detail to fix it), while the representative is the turn eq. 9 prefers. Only
// the found transforms: compositions with the target's symmetries are deliberately other members.
void snap_to_family_representatives(std::vector<SupportedTransform>& transforms, const SymmetryAxis& axis);

// Candidates the paper expects: each of the `max_base_transforms` strongest found transforms Q (target -> source)
// composed with each symmetry R of the target (target -> target): Q o R explains the target samples that R carries
// onto Q's support. Where T has a continuous axis, Q is first replaced by the member of its family Q o G_theta whose
// rotation is nearest the identity (ICP slides it freely along the axis), which is a candidate too: its compositions
// with the axis steps then include the axis rotations. Returned as modes whose voters are those samples, for
// grow_supports. With `parts`, Q is also composed with each part's turns about the part's own axis (by multiples of
// 360 / part_turns degrees), where Q's support reaches the part: the voters are then the part's samples that the turn
// carries onto that support, so that the part's unseen side can take its seen side's detail. With `face_turns`, Q is
// also composed with the turn about `up` by a multiple of 90 degrees that carries a flat face B of T onto a face A that
// Q's support reaches, centre onto centre, where no symmetry of T does so (a box that is not square has no quarter
// turn, yet its short side takes its long side's relief, centred): the voters are B's samples that the turn carries
// within `distance` alpha of the support on A. Given the exemplar (completion: the scan's samples, with normals, and
// `exemplar_to_source`, their registration onto the template), where B is wider than A the turn is also shifted along A
// onto B's ends, by multiples of the exemplar's own repeat along A (face_repeat.h), so that the ends take A's relief in
// phase with B's middle.
std::vector<Mode> composed_candidates(const std::vector<SupportedTransform>& found,
                                      const SymmetryResult& target_symmetry, const PointSet& target, double spacing,
                                      const Eigen::Vector3d& up, const SymmetryOptions& options,
                                      const PointSet* exemplar = nullptr,
                                      const Similarity& exemplar_to_source = Similarity{});

// On a template with a discrete symmetry group (a box, a prism; none for a body of revolution, whose turns are
// many), each found transform Q composed with each of T's own rotations R that keeps the object's `up` direction
// within 3 degrees. Where a half turn end over end and a half turn about the vertical carry the seen side onto the
// same face of a box, the two explain the same samples, and the coverage rule and the duplicate rule keep the one
// with the larger support by a few samples; the label node prefers the upright turn per sample
// (label.upright_unary) only if it is a candidate. These are kept as preferred (the ribbed box seen square on its
// short side: its far short side took the near one upside down, the plinth band at its top).
std::vector<Mode> upright_turns(const std::vector<SupportedTransform>& found, const SymmetryResult& target_symmetry,
                                const PointSet& target, const Eigen::Vector3d& up);

// The turns eq. 9 prefers about T's continuous axis, for a scan that T's turns all explain alike: the family member
// nearest the identity of the strongest found transform whose family holds it (not a flip end over end), composed with
// the turns by 0, 90, 180 and 270 degrees about the axis. Voting finds some turn of the family at random angles, and
// the coverage rule (extend_supports) keeps no composition where those already explain T; these are kept as preferred.
// Empty without a continuous axis.
std::vector<Mode> axis_quarter_turns(const std::vector<SupportedTransform>& found,
                                     const SymmetryResult& target_symmetry, const PointSet& target);

}  // namespace scanfill
