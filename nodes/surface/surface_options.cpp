#include "nodes/surface/surface_options.h"

namespace scanfill {

OptionTable option_table(SurfaceOptions& s) {
  using namespace checks;
  return {"surface",
          "output_mesh.ply (output.surface): a Poisson surface of the completed samples (pcl::Poisson)",
          {{"depth", &s.depth, "Poisson octree depth, at most 2^depth cells a side; [4, 12]",
            range(&s.depth, 4, 12, false, "an integer in [4, 12]")},
           {"samples_per_node", &s.samples_per_node, "least points per octree leaf (more smooths noise); [1, 20]",
            range(&s.samples_per_node, 1.0, 20.0, false, "a number in [1, 20]")},
           {"max_points", &s.max_points, "points are voxel-thinned to about this many before meshing; >= 100",
            range<Index>(&s.max_points, 100, Index(1) << 40, false, "an integer >= 100")},
           {"trim_distance", &s.trim_distance,
            "triangles with a corner farther than this (spacings) from the points are dropped; > 0",
            positive(&s.trim_distance)}}};
}

}  // namespace scanfill
