// Consistent winding for a triangle mesh as a file gives it (DESIGN section 2: loaders take files as they are).
//
// A template drawn by hand or by a script often joins parts wound opposite ways: a box whose bottom and back faces
// were drawn with the same corner order as its top and front has them facing in. Every sampled normal then points
// into the part, and the analogy reads a thin plate's two faces as one facing one way (a chair's seat: its unseen
// underside was left bare). So the faces are wound consistently where the mesh says how:
// - vertices are welded where their positions are exactly equal (parts written face by face repeat their corners);
// - across every edge that exactly two faces share (after welding), the second face is wound against the first, as
//   an orientable surface's are, by breadth-first propagation from each part's first face (faces joined by such
//   edges); edges of one face or of three and more propagate nothing;
// - a part that is closed (no such edge) and encloses a negative signed volume is turned whole, so that its normals
//   face out.
// An open part keeps its first face's winding (a range scan's, its sensor's). Deterministic: the order of the faces
// decides, never hashing or threads.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "nodes/core/point_set.h"

namespace scanfill {

// Rewinds triangles (3 vertex indices each into `positions`' columns) in place as above; returns how many it turned.
Index orient_faces(const Eigen::Matrix3Xd& positions, std::vector<std::int32_t>& triangles);

}  // namespace scanfill
