// synthesize node: the analogy A* = M A M^-1 applied to the exemplar, per sample (paper section 5.3, DESIGN section 4).
//
// All positions are in the working frame: the source's and target's (the exemplar enters after its rigid
// registration). The label node gives each target sample t a transform Q_l with Q_l p_t ~ p_s (target -> source).
// An exemplar sample e whose source sample s = M^-1(e) maps back into the region labelled l (the target sample
// nearest Q_l^-1 p_s lies within `reach` alpha and is labelled l) is carried into the output as Q_l^-1 p_e: the
// exemplar's own geometry, style included, moved where the structure needs it. Each region is extended by its
// boundary ring (the target samples next to it on the kNN graph), so neighbouring patches overlap and the align node
// can close the seams. Target regions labelled self-reference are copied as they are. A target sample whose own
// region's image left a hole (no carried source sample lands within `reach`: the exemplar has nothing where its
// transform maps it) is first filled by another used transform's image that does reach it (fill_holes in
// synthesize.cpp). A target sample is copied from the target, with a count in the result, where no carried source
// sample lands within `gap_distance` of it or no output point lies over it (within `overlay_distance` across its
// normal and `gap_distance` along it), but not where the output points near its plane stand off it in relief (a
// gear's teeth stand 4 alpha off its plain disk) or a relief facing its way lies sunk under it (up to three times
// `gap_distance`: a real pillar's panels behind its bounding box), nor where a round template stands outside the
// scan's own radii about its axis (`off_profile`). Reaching is judged where the carried samples' source samples land,
// on the template, not where their relief does.
//
// The template alone cannot fix every transform: on a body of revolution any rotation about its axis explains it,
// but the exemplar's detail (flutes, beads) repeats only at some angles. So, before carrying the exemplar, each
// transform is refined against the images already placed, where they overlap (the scan itself first in completion
// mode, else the largest region's image), the transform whose image overlaps the placed ones most going next: a phase
// search along the region's slippable motions, then ICP along those motions only, or free rigid ICP, whichever of the
// three fits the placed images best. A transform whose image overlaps nothing placed is kept as labelled. A region
// that turns on itself about an axis may then take a second phase for the part of it on one side of a cut across the
// axis, where detail of another period lies (a vase's ring of 16 beads below its 12 flutes): that part becomes a patch
// of its own (phase_split in synthesize.cpp).
//
// In completion mode the exemplar is the scan: its samples are part of the output as they are (origin 0), and target
// samples it covers (`covered`) get nothing synthesised.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"
#include "nodes/synthesize/repeats.h"

namespace scanfill {

enum class Origin : std::uint8_t { kExemplar = 0, kSynthesized = 1, kTarget = 2 };

// A patch: one transform applied to one input (the exemplar, or the target for copies).
struct Patch {
  int label = -1;                     // transform label; -1 for the exemplar itself; the self label for copies
  Origin origin = Origin::kExemplar;  // what its points are
  bool from_target = false;           // base input: the target (copies) or the exemplar
  Similarity transform;               // base input's working frame -> working frame
};

struct SynthesisOptions {
  double reach = 2.0;             // a mapped source sample belongs to a region within this many alpha; > 0
  int ring_k = 8;                 // kNN graph that defines a region's boundary ring; [0, 32] (0 = no overlap)
  double gap_distance = 4.0;      // copied with no landed source sample or output point this close (alpha); > 0
  double overlay_distance = 2.0;  // ... and this close across its normal (alpha); > 0
  int refine_iterations = 10;     // ICP steps refining each transform against the exemplar's overlapping images; >= 0
  double refine_distance = 3.0;   // ICP pairs closer than this, in alpha; > 0
  double search_distance = 15.0;  // slippable motions are searched this far (alpha) before ICP; >= 0
  bool repeats = true;            // completion: turn images to the exemplar's own repeats, and fill with its turns
  bool mirror = true;             // completion: the exemplar's mirror image about a plane through the template's axis
  bool seen_through = true;       // completion: no copies where the scanner saw through the template (the engine
                                  // judges it: SynthesisInputs::seen_through)
};

struct Synthesis {
  PointSet points;                  // working frame: positions and normals
  std::vector<Origin> origin;       // per point
  std::vector<std::int32_t> label;  // per point: the transform label, -1 for exemplar points, self label for copies
  std::vector<std::int32_t> patch;  // per point: index into patches
  std::vector<std::int32_t> base;   // per point: the exemplar sample or target sample it came from
  std::vector<std::uint8_t> ring;   // per point: 1 when it lies on its region's extension ring
  std::vector<Patch> patches;
  Index gap_copies = 0;                // target samples copied because no patch reached them
  Index off_profile = 0;               // target samples not copied: outside the scan's own radii about the axis
  Index seen_through = 0;              // target samples not copied: the scanner saw the scan through them
  Index filled_patches = 0;            // patches that filled holes of other regions' images (fill_holes)
  std::vector<double> refinement_deg;  // per transform label: rotation of its refinement (0 if unrefined/unused)
  // Per transform label: 1 where the template pins its refinement (one of the template's own symmetries, on a scan the
  // registration barely moved; see synthesize.cpp's pinned_symmetries).
  std::vector<std::uint8_t> pinned_by_template;
  std::vector<double> refinement_shift;  // per transform label: translation of its refinement, model units
  // The exemplar's registration offset from the template, shared by every label's image (completion only; else 0).
  Eigen::Vector3d registration_offset = Eigen::Vector3d::Zero();
  std::vector<double> second_phase_deg;  // per transform label: turn of its second phase about the axis (0 if none)
  std::vector<AxialRepeats> repeats;     // completion: the exemplar's repeats about the axes regions turn about
  Index repeat_fill = 0;                 // samples added by turning the exemplar to its repeats (fill_by_repeats)
  std::optional<MirrorPlane> mirror;     // completion: the exemplar's mirror plane through the template's axis
  Index mirror_fill = 0;                 // samples added by mirroring the exemplar (replace_by_mirror)
  Index mirror_replaced = 0;             // images' points the mirrored exemplar took the place of
};

struct SynthesisInputs {
  const PointSet& exemplar;                          // exemplar samples, input frame, with normals
  const Similarity& exemplar_to_working;             // the correspondence's rigid registration
  const std::vector<std::int32_t>& exemplar_source;  // per exemplar sample: M^-1, a source sample or -1
  const PointSet& source;                            // source samples (working frame)
  const PointSet& target;                            // target samples (working frame), with normals
  const std::vector<int>& labels;                    // per target sample (label node)
  int self_label = 0;
  const std::vector<Similarity>& transforms;           // per transform label: Q_l, target -> source
  const std::vector<std::uint8_t>* covered = nullptr;  // completion: target samples the scan covers; else null
  // Completion: the template's axes of revolution (its own, its parts': a table's legs), whose turns may fill.
  const std::vector<TurningPart>* turning_parts = nullptr;
  // Completion: the template's principal axis (its continuous one, else its unique one of highest order), through
  // which a plane may mirror the exemplar onto itself; null for none.
  const TurningPart* mirror_axis = nullptr;
  // Completion: no registration moved the scan (`correspond.rigid` off, or ICP's pose not taken, or only its turn
  // taken, about the template's centroid): it stands on the template as given, so no registration offset is fitted,
  // and fits may not carry pinned regions off the template.
  bool scan_as_given = false;
  // Completion: the object's up (support's). A flip that turns it end over end on a region without slippable motion
  // (a prism's back and floor) is pinned to the template by its free fit, as a flip across the axis it turns about is.
  std::optional<Eigen::Vector3d> up = std::nullopt;
  // Completion: target samples standing outside the scan's own radii about the template's axis (outside_the_profile in
  // nodes/symmetry/profile.h): never copied, as the template is not the object there.
  const std::vector<std::uint8_t>* off_profile = nullptr;
  // Completion: target samples the scanner saw the scan through (seen_through in nodes/correspond/free_space.h): never
  // copied, as nothing stands there.
  const std::vector<std::uint8_t>* seen_through = nullptr;
};

Synthesis synthesize(const SynthesisInputs& in, double spacing, const SynthesisOptions& options);

// The synthesis' points where `keep` is 1 (one flag per point), positions and normals mapped by `to_output`. With the
// thinning of the overlaps at zero offsets (align.h's thinned_overlaps) these are the completed shape at the samples'
// resolution, as the output will have it before the seams are closed.
PointSet kept_points(const Synthesis& s, const std::vector<std::uint8_t>& keep, const Similarity& to_output);

}  // namespace scanfill
