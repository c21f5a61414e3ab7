// correspond node: the dense source <-> exemplar map M of the paper's section 4 (DESIGN section 4).
//
// The exemplar samples are registered to the source samples, rigidly first (trimmed point-to-plane ICP from the
// given, roughly aligned pose; the given pose itself where ICP only slides the scan between its relief and the
// ground, or cuts a template that bounds the scan as given through it: kept_input_pose; ICP's turn about the
// template's centroid where only the relief pulled its move, a template drawn a little turned: turned_in_place; where
// both are bodies of revolution that ICP lays askew, a vase in a plain cylinder, the scan's own axis laid on the
// template's: laid_on_axis; where the template is a low-poly polygon about an axis, a hexagon drawn for a column, and
// the scan is round or lies better on the body of revolution through its corners, that body in its place from here
// on: polygon), then non-rigidly by embedded deformation (Sumner, Schmid, Pauly 2007): a graph of
// deformation nodes, each with an affine map and a translation, solved by Levenberg-Marquardt on normal equations
// assembled in parallel and factorised block by block (deformation_solve.h; Huber loss on the data terms). Registration
// alternates with an assignment: eq. 1's cost (squared distance in the common frame, in alpha units, plus normal_weight
// (1 - n_e . n_s)) on a sparse graph of each exemplar sample's `candidates` nearest source samples, plus an escape arc
// (left unmatched at the cost of escape_distance alpha), solved exactly as a min-cost flow (LEMON NetworkSimplex,
// integer costs). A source sample may take up to `many_to_one` exemplar samples, so partial and many-to-one matching
// are allowed. The deformation's stiffness starts at `stiffness` and halves every outer iteration. User landmarks
// (exemplar point -> source point) enter as heavily weighted data terms.
//
// Every source sample ends up matched: one with no exemplar sample of its own takes that of its nearest matched
// neighbour. Throws InputError when the inputs cannot be registered: too few samples, or no
// overlap before or after rigid registration (inputs far apart, or at very different scales: check_shared_scale
// below is the pipeline's scale check, made once before sampling).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/progress.h"
#include "nodes/core/similarity.h"
#include "nodes/core/solver_summary.h"
#include "nodes/correspond/template_size.h"

namespace scanfill {

struct Landmark {
  Eigen::Vector3d exemplar;  // a point on the exemplar (scan), in its input frame
  Eigen::Vector3d source;    // where it belongs on the source (template)
};

// Landmarks given as two MeshLab picked-points files, paired by point name (correspond.landmarks_file).
struct LandmarkFiles {
  std::filesystem::path exemplar;  // picked on the scan or exemplar
  std::filesystem::path source;    // picked on the template or source
};

// A template that is a regular polygon about an axis (a low-poly cylinder, its vertices on the circle, as Blender,
// OpenSCAD and trimesh draw one), read as the body of revolution through its corners.
struct PolygonBody {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();      // a point on the axis
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // the axis' unit direction
  int sides = 0;                                         // 5 to 32; 0: none
  double phase = 0;  // the angle across the axis of one facet's outward normal, from direction.unitOrthogonal()
};

// `points` on the body of revolution a polygon draws: each moved away from the axis at its height and angle, so that
// the polygon's rim lands on the circle through its corners (a facet's centre by 1 / cos(pi / sides), a corner not at
// all), which lays walls on the body's wall and caps on its disks; a wall's normal turned across the axis to face
// along its radius. Triangles, colours and indices are kept; curvatures, directions and face provenance describe the
// polygon still. Throws InvariantError for other than 5 to 32 sides or an axis direction that is not a unit vector.
PointSet on_polygon_body(const PointSet& points, const PolygonBody& body);

// The surface the body's copies are made of: a template mesh split until its edges are at most `spacing` long (so
// that its triangles bend round the body), into at most `most_faces` triangles, then moved onto the body; a cloud only
// moved. With as many triangles at most as the template has samples, the split mesh has fewer vertices than samples,
// so the transfer draws copies from it at random, evenly over its area (copy_surface), not at its vertices, which
// crowd along a long thin triangle's short sides.
PointSet polygon_body_surface(const PointSet& surface, const PolygonBody& body, double spacing, Index most_faces);

struct CorrespondOptions {
  bool rigid = true;                  // rigid pre-alignment by ICP (roughly aligned inputs); false: the given pose
  int rigid_iterations = 40;          // ICP steps; [1, 500]
  double rigid_trim = 3.0;            // ICP ignores pairs farther than this times the median pair distance; >= 1
  double rigid_fine_trim = 3.0;       // the same in the point-to-plane steps (1: only the closer half); > 0
  int outer_iterations = 4;           // assignment / deformation alternations (0 = rigid only); [0, 20]
  int deformation_nodes = 150;        // embedded-deformation graph nodes; [4, 5000]
  int node_neighbors = 6;             // graph edges per node; [2, 16]
  Index deformation_samples = 20000;  // data terms of the deformation solve (every k-th matched sample); >= 100
  double stiffness = 10.0;            // initial weight of the rotation and smoothness terms; > 0
  double robust_scale = 2.0;          // Huber scale of the data terms, in alpha; > 0
  int candidates = 8;                 // nearest source samples each exemplar sample may match; [1, 64]
  double normal_weight = 1.0;         // eq. 1 weight of (1 - n_e . n_s) against the squared distance in alpha; >= 0
  double escape_distance = 3.0;    // an exemplar sample is left unmatched at the cost of this distance, in alpha; > 0
  int many_to_one = 3;             // exemplar samples a source sample may take; [1, 64]
  double landmark_weight = 100.0;  // weight of a landmark against a data term; > 0
  double min_overlap = 0.2;        // share of exemplar samples that must lie within escape_distance after ICP; [0, 1]
  double max_scale_ratio = 10.0;   // bounding-box diagonals may differ by at most this factor; > 1
  Index min_samples = 50;          // fewer exemplar or source samples are refused; >= 4
  std::vector<Landmark> landmarks;
  LandmarkFiles landmarks_file;  // more landmarks, by name from two .pp files (empty paths: none)
  bool polygon_body = true;  // a polygon template may stand for the body through its corners (PolygonBody): completion
                             // only, where every later node takes the body (set by the engine, no key)
  bool scaled_template = true;  // a template drawn at another size may stand scaled for itself (template_scaled):
                                // completion only, as polygon_body (set by the engine, no key)
};

struct CorrespondResult {
  Similarity rigid;                           // exemplar input frame -> source frame (a rigid motion)
  Eigen::Matrix3Xd registered;                // exemplar samples after the rigid motion
  Eigen::Matrix3Xd deformed;                  // exemplar samples after the rigid motion and the deformation
  std::vector<std::int32_t> exemplar_match;   // per exemplar sample: its source sample, or -1 (escaped)
  std::vector<std::int32_t> source_match;     // per source sample: an exemplar sample (nearest matched rule)
  std::vector<std::int32_t> exemplar_source;  // per exemplar sample: its match, else the source sample nearest its
                                              // deformed position within 2 escape_distance (-1 beyond: an outlier)
  Index matched = 0;                          // exemplar samples with a source sample
  double rigid_rms = 0;                       // RMS distance of ICP's trimmed pairs (even where its pose is not kept)
  bool kept_input_pose = false;               // rigid is the identity: ICP's pose was the relief's pull
  bool turned_in_place = false;               // rigid is ICP's turn about the source's centroid: the relief pulled
                                              // ICP's move
  bool laid_on_axis = false;                  // rigid lays the scan's own axis of revolution on the source's
  // The template looks drawn at another size than the scan (template_size.h): scaled by template_scaling along its
  // principal axes (spread ascending) about its centroid and shifted, it lays as much of the scan in its own pose on
  // itself as ICP's move does, so the scan keeps its own pose (kept_input_pose too). In completion
  // (CorrespondOptions::scaled_template), the template so scaled stands in for it (template_scaled): the scan is
  // deformed onto it, and every later node takes it (scaled_source).
  bool another_size = false;
  TemplateScaling template_scaling;
  bool template_scaled = false;
  PolygonBody polygon;      // sides > 0: the source is a regular polygon, and the scan is registered
                            // and deformed onto on_polygon_body(source), which stands in for it
  double deformed_rms = 0;  // RMS distance of the matched pairs after deformation
  // Ceres' summary of each outer iteration's deformation solve, in order (empty when only the rigid registration ran).
  std::vector<SolverSummary> deformation_solves;
  std::vector<std::string> warnings;
};

// Throws InputError unless two inputs' bounding-box diagonals lie within max_ratio of each other (paper section 3:
// inputs share a scale). name_a and name_b say which inputs they are ("the exemplar (scan)"). The one scale check:
// the pipeline calls it on every input before sampling them at a shared alpha; correspond() does not repeat it.
void check_shared_scale(const std::string& name_a, const PointSet& a, const std::string& name_b, const PointSet& b,
                        double max_ratio);

// Landmarks from two MeshLab picked-points files: each exemplar point paired with the source point of the same name.
// Names found in only one file are listed in `unpaired`. Throws IoError naming a file that cannot be read, and
// InputError when no name is in both.
std::vector<Landmark> landmarks_by_name(const LandmarkFiles& files, std::vector<std::string>& unpaired);

// The template's points (samples or surface) where something stands in for the template from the correspondence on:
// on the polygon's body (CorrespondResult::polygon), then scaled (template_scaled); as they are otherwise.
PointSet template_in_place(const PointSet& points, const CorrespondResult& r);

// exemplar and source: samples with normals, at the same spacing alpha.
CorrespondResult correspond(const PointSet& exemplar, const PointSet& source, double spacing,
                            const CorrespondOptions& options, const ProgressFn& progress = {});

// One assignment step (exposed for tests): exemplar samples at `positions` with `normals` to source samples, eq. 1's
// integer cost on each sample's `candidates` nearest, escape arcs, at most `many_to_one` per source sample, solved
// exactly by min-cost flow. Writes per exemplar sample its source sample or -1; returns the number matched and sets
// `cost` to the flow's total cost (in units of 1/1000 alpha^2).
Index assign_samples(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals, const PointSet& source,
                     double spacing, const CorrespondOptions& options, std::vector<std::int32_t>& match,
                     std::int64_t* cost = nullptr);

// The source samples within `distance` of any of `points` (ascending): in completion mode, the template samples the
// registered scan covers, which form the source S.
std::vector<std::int32_t> covered_samples(const PointSet& source, const Eigen::Matrix3Xd& points, double distance);

// Completion's source S (DESIGN section 2): the template samples the registered, deformed scan covers.
struct CoverOptions {
  double distance = 2.0;   // a template sample within this many alpha of a deformed scan sample is covered; > 0
  double relief = 6.0;     // a template sample with a scan sample this far (alpha) along its normal, within `distance`
                           // of the normal's line and facing the same way, is seen in relief; >= 0 (0: none)
  Index min_samples = 30;  // fewer covered samples are too little of the template to learn from; >= 1
};

// Two notions of "the scan has this part". S, what the analogy learns from, is the template within `distance` of the
// deformed scan. What synthesis leaves to the scan is wider: also the template the scan stands over in relief, further
// than the deformation pulled it (a gear's tooth gaps, 3 cm = 4 alpha inside its plain disk): synthesised there, the
// exemplar's images or template copies would lie over detail the scan already has. Relief is kept out of S: measured
// on the robustness sweep, adding it to S changed the votes and cost the vase from below and the gear's back-oblique
// view most of their unseen detail.
struct CoverResult {
  std::vector<std::int32_t> samples;  // S's template samples (within `distance`), ascending
  std::vector<std::uint8_t> covered;  // per template sample: 1 when in S or seen in relief (nothing is synthesised)
  PointSet source;                    // the samples with their features: the analogy's source S
};

// The scan samples after registration and deformation (map.deformed) cover the template; `spacing`: alpha.
// Throws InputError when fewer than min_samples are covered, ConfigError naming the key for options out of range.
// `exemplar`: the scan samples `map` registered (their normals, turned by map.rigid, serve the relief test).
CoverResult cover_template(const PointSet& templ, const CorrespondResult& map, const PointSet& exemplar, double spacing,
                           const CoverOptions& options);

}  // namespace scanfill
