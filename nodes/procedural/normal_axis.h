// The axis of a body of revolution from the lines its normals lie on, which works on a partial scan (one view of a
// vase) where the axes through its bounding box's centre do not: every normal line of a surface of revolution meets
// the axis (Pottmann and Randrup, "Rotational and helical surface approximation for reverse engineering", 1998).
#pragma once

#include "nodes/core/surface_elements.h"
#include "nodes/procedural/shapes.h"

namespace scanfill {

// How far the surface's normals are from meeting `axis`: the weighted median, over the elements away from the axis,
// of the sine of the angle between an element's normal and the plane through the axis and the element. 0 on a body of
// revolution about the axis; about 0.7 (45 degrees) for normals that ignore it.
double normal_axis_misfit(const SurfaceElements& surface, const RevolutionAxis& axis);

// The axis whose Plücker coordinates (a, c x a) best satisfy a . (p x n) + (c x a) . n = 0 for every element (p, n),
// the smallest eigenvector of a 6 by 6 system reduced to 3 by 3, reweighted 10 times by each element's sine (a Cauchy
// weight at twice the sines' robust spread), so that relief and handles weigh little. The direction is snapped to a
// coordinate axis within 1 degree of it and points to its positive side; the centre is the axis's point nearest the
// elements' mean. Needs at least 16 elements not all parallel.
RevolutionAxis axis_from_normals(const SurfaceElements& surface);

}  // namespace scanfill
