// The engine's side of each node (DESIGN section 2): the message it sends and the body its tbb::flow node runs.
//
// Messages are immutable and shared (std::shared_ptr<const T>); each points back at the messages it was made from,
// so the last one of a run reaches every result the output writer needs. A body calls the node function of nodes/
// with its options, logs one line, records warnings and the node's timing; run_node adds the node's name to any error.
// No geometry here: every decision about points is a node function's.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "engine/background.h"
#include "engine/config.h"
#include "engine/pipeline.h"
#include "nodes/curves/curves.h"
#include "nodes/curves/sample_curves.h"
#include "nodes/exchange/exchange.h"
#include "nodes/sample/sample.h"
#include "nodes/surface/surface.h"
#include "nodes/synthesize/synthesize.h"
#include "nodes/transfer/transfer.h"

namespace scanfill {

// A scan read in chunks (load.stream_above): its file, read again by the sample and transfer nodes, and what the load's
// pass over it found (load.points then holds only the summary's every-k-th points).
struct Streamed {
  std::filesystem::path path;
  ChunksSummary summary;
};
struct Loaded {
  Input input;
  LoadResult load;
  BoundingBox box;                           // of load.points (of every point when streamed), for the report
  std::shared_ptr<const Curves> curves;      // mode curves: the drawing (load.points are its samples once sampled)
  std::shared_ptr<const Streamed> streamed;  // set when the input is read in chunks, never whole
  Index points() const { return streamed ? streamed->summary.points : load.points.size(); }
};
struct Sampled {
  std::shared_ptr<const Loaded> loaded;
  SampleResult sample;
  std::shared_ptr<const CurveSamples> curves;  // mode curves: each sample's curve and arc parameter
};
struct Featured {
  std::shared_ptr<const Sampled> sampled;
  FeaturesResult features;
};
using LoadedPtr = std::shared_ptr<const Loaded>;
using SampledPtr = std::shared_ptr<const Sampled>;
using FeaturedPtr = std::shared_ptr<const Featured>;

// M: the exemplar (scan) <-> source (template) map.
struct Correspondence {
  FeaturedPtr exemplar, source;
  CorrespondResult map;
};
using CorrespondencePtr = std::shared_ptr<const Correspondence>;

// Completion: the template samples the registered scan covers; their subset is the analogy's source S.
struct Coverage {
  CorrespondencePtr correspondence;
  CoverResult cover;
};
using CoveragePtr = std::shared_ptr<const Coverage>;

// A: S -> T, one message per stage.
struct Symmetries {
  PointSet source;  // S
  FeaturedPtr target;
  CorrespondencePtr correspondence;  // completion: the scan on the template (support's face shifts read it); else null
  double spacing = 0;
  SymmetryResult source_symmetry, target_symmetry;
  std::optional<Eigen::Matrix3d> target_axes;  // T's own axes (object_axes): unset where the world's
};
using SymmetriesPtr = std::shared_ptr<const Symmetries>;
struct Votes {
  SymmetriesPtr symmetries;  // S, T and alpha, with their symmetries
  VoteResult votes;
  const PointSet& source() const { return symmetries->source; }
  const FeaturedPtr& target() const { return symmetries->target; }
  double spacing() const { return symmetries->spacing; }
};
using VotesPtr = std::shared_ptr<const Votes>;
struct FoundModes {
  std::shared_ptr<const Votes> votes;
  ModesResult modes;
};
using FoundModesPtr = std::shared_ptr<const FoundModes>;
struct Supports {
  FoundModesPtr modes;
  SupportResult support;
  Index voted = 0;                                // transforms grown from the modes
  Index composed = 0;                             // candidates composed with the target's symmetries
  Index refuted = 0;                              // completion: candidates the scan's radii about T's axis refute
  bool scan_repeats = false;                      // completion: the scan repeats about the target's axis
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // label.up, else the target's own axis, else the axis of the faces
                                                  // the scan shows plainest, else the axis of the faces it does not
                                                  // show, else the axis it stands on the ground along, else +z (label
                                                  // and synthesize use it)
  const char* up_from = "default";  // where it came from: label.up, symmetry, plainest_faces, unseen_faces, ground or
                                    // default (the report's)
};
using SupportsPtr = std::shared_ptr<const Supports>;
struct Labelled {
  SupportsPtr supports;
  LabelResult labels;
  const Votes& votes() const { return *supports->modes->votes; }
};
using LabelledPtr = std::shared_ptr<const Labelled>;

// M, A -> synthesize -> align -> transfer.
struct Synthesized {
  CorrespondencePtr correspondence;
  LabelledPtr analogy;
  CoveragePtr coverage;  // completion only
  Synthesis synthesis;
};
using SynthesizedPtr = std::shared_ptr<const Synthesized>;
struct Aligned {
  SynthesizedPtr synthesized;
  AlignResult alignment;
};
using AlignedPtr = std::shared_ptr<const Aligned>;
// The transfer's plan (DESIGN section 10): what `scanfill plan` writes and the transfer node carries the points by.
struct Planned {
  AlignedPtr aligned;
  TransferPlan plan;
};
using PlannedPtr = std::shared_ptr<const Planned>;
// The transfer streams output.ply into the staging folder as it carries the points (DESIGN section 10: memory bounded
// by the samples plus one chunk); what the message keeps of the output is its counts and every `stride`-th point.
struct Transferred {
  AlignedPtr aligned;
  TransferCounts counts;
  ColourChoice colour = ColourChoice::kOrigin;  // output.ply's RGB (output.colour resolved)
  bool intensity = false;                       // output.ply has the scan's intensity
  Index stride = 1;                             // kept: every stride-th output point
  TransferResult kept;  // all the points when there are few (and in mode curves), else a bounded even subsample:
                        // the preview's input
  std::filesystem::path written;  // output.ply, in the staging folder
  // output.ply's last runs and its commit may still be in progress when the node returns: wait() before using it.
  std::shared_ptr<SerialBackground> writing;
};
using TransferredPtr = std::shared_ptr<const Transferred>;

// Mode curves: the output points as polylines along the target's curves (output.svg, output.txt).
struct Drawn {
  TransferredPtr transferred;
  Curves curves;
};
using DrawnPtr = std::shared_ptr<const Drawn>;

// output.surface: the completed shape meshed (output_mesh.ply), from the synthesis' samples.
struct Surfaced {
  SynthesizedPtr synthesized;
  SurfaceResult surface;
};
using SurfacedPtr = std::shared_ptr<const Surfaced>;

// Mode exchange: an input's part boxes (from the config, a castle's layout or a PLY's part property), and one
// exemplar/target pair's exchange.
struct Parts {
  Input input;
  PartBoxes boxes;
  std::string from;              // where the boxes came from, for the report
  std::vector<int> part_labels;  // per box, the PLY's label (empty otherwise)
};
using PartsPtr = std::shared_ptr<const Parts>;
struct Exchanged {
  LoadedPtr exemplar;  // carried at full resolution: a mesh's triangles, a cloud's points
  PartsPtr exemplar_parts, target_parts;
  size_t pair = 0;  // exemplar index x targets + target index: the report's order
  Exchange exchange;
};
using ExchangedPtr = std::shared_ptr<const Exchanged>;

// What a run's nodes share with the engine: the config, timings, warnings and, for the writer, every input's features
// and the last message of the graph.
class RunState {
 public:
  explicit RunState(const RunConfig& config) : config(config), inputs_(config.inputs.size()) {}
  const RunConfig& config;
  std::filesystem::path write_dir;  // the staging folder the writer writes into (engine/staging.h)
  bool plan_only = false;           // `scanfill plan`: the graph stops at the plan node

  void record(const std::string& name, double seconds);
  void warn(const std::string& node, const std::string& what);
  void keep(FeaturedPtr f);
  void keep(LabelledPtr a);
  void keep(PlannedPtr p);
  void keep(TransferredPtr t);
  void keep(SurfacedPtr s);
  void keep(DrawnPtr d);
  void keep(ExchangedPtr e);

  // After the graph has run.
  const std::vector<NodeTiming>& timings() const { return timings_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::vector<FeaturedPtr>& inputs() const { return inputs_; }  // in config.inputs' order
  const LabelledPtr& analogy() const { return analogy_; }
  const PlannedPtr& plan() const { return plan_; }
  const TransferredPtr& output() const { return output_; }
  const SurfacedPtr& surface() const { return surface_; }  // null unless output.surface made one
  const DrawnPtr& drawing() const { return drawing_; }     // mode curves only
  std::vector<ExchangedPtr> exchanges() const;             // mode exchange: every pair, in pair order

 private:
  std::mutex mutex_;
  std::vector<NodeTiming> timings_;
  std::vector<std::string> warnings_;
  std::vector<FeaturedPtr> inputs_;
  LabelledPtr analogy_;
  PlannedPtr plan_;
  TransferredPtr output_;
  SurfacedPtr surface_;
  DrawnPtr drawing_;
  std::vector<ExchangedPtr> exchanges_;
};

// An input as the run loads it: its fragments merged; completion's scan through the virtual scanner when configured.
LoadResult load_as_run(const RunConfig& config, const Input& input);
// The input's name for messages: its spec, and how many fragments come with it.
std::string input_subject(const Input& input);

// The node bodies. `reference`: the input whose spacing alpha this one is sampled at (nullptr: as configured).
LoadedPtr load_stage(RunState& state, const Input& input);
SampledPtr sample_stage(RunState& state, const LoadedPtr& in, const SampledPtr& reference);
FeaturedPtr features_stage(RunState& state, const SampledPtr& in);
// Mode curves: a drawing read, then sampled with its frames (the plane's sample and features in one node, since the
// frames come from the curve itself); every drawing at the spacing of `reference` (the target's) when given.
LoadedPtr load_curves_stage(RunState& state, const Input& input);
FeaturedPtr sample_curves_stage(RunState& state, const LoadedPtr& in, const FeaturedPtr& reference);
CorrespondencePtr correspond_stage(RunState& state, const FeaturedPtr& exemplar, const FeaturedPtr& source);
CoveragePtr cover_stage(RunState& state, const CorrespondencePtr& correspondence);
SymmetriesPtr symmetry_stage(RunState& state, const PointSet& source, const FeaturedPtr& target,
                             const CorrespondencePtr& correspondence = nullptr);
VotesPtr vote_stage(RunState& state, const SymmetriesPtr& in);
FoundModesPtr modes_stage(RunState& state, const VotesPtr& in);
SupportsPtr support_stage(RunState& state, const FoundModesPtr& in);
LabelledPtr label_stage(RunState& state, const SupportsPtr& in);
SynthesizedPtr synthesize_stage(RunState& state, const CorrespondencePtr& correspondence, const LabelledPtr& analogy,
                                const CoveragePtr& coverage);
AlignedPtr align_stage(RunState& state, const SynthesizedPtr& in);
// `to_scan_frame`: completion writes the output in the scan's frame (the inverse of the rigid registration).
PlannedPtr plan_stage(RunState& state, const AlignedPtr& in, bool to_scan_frame);
TransferredPtr transfer_stage(RunState& state, const PlannedPtr& in);
// The surface is made from the synthesis' samples as the output will have them (kept_points), so it runs beside
// align, plan and the transfer. `to_scan_frame` as plan_stage's.
SurfacedPtr surface_stage(RunState& state, const SynthesizedPtr& in, bool to_scan_frame);
// Mode curves: the output points ordered into polylines along the target's curves.
DrawnPtr draw_curves_stage(RunState& state, const TransferredPtr& in);

// Mode exchange: an input's part boxes; one pair's box-wise analogy and synthesis.
PartsPtr parts_stage(RunState& state, const Input& input);
ExchangedPtr exchange_stage(RunState& state, const LoadedPtr& exemplar, const PartsPtr& exemplar_parts,
                            const PartsPtr& target_parts, size_t pair);

// Builds and runs the graph of state.config.mode (pipeline.cpp); with state.plan_only it ends at the plan node.
void run_graph(RunState& state);

}  // namespace scanfill
