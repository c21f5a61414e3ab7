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
// weight at twice the sines' robust spread), so that relief weighs little. Many models are drawn along a coordinate
// axis: each within 25 degrees of the free axis, its centre fitted the same way, is tried too, and the one the
// normals meet best is taken where they meet it nearly as well as the free axis (a misfit within 10% and 0.005): half
// a noisy vase fixes its direction only loosely (the free axis is 17 degrees off the text2mesh vase's). Relief can
// pull the free axis across: a teapot's spout and handle to x (misfit 0.19 against y's 0.04), the Vase-Lion's face
// seen from its side to x (0.30 against z's 0.34). The direction points to the positive side; the centre is the axis's
// point nearest the elements' mean. Needs at least 16 elements (else throws InputError). Normals all parallel (a plane)
// meet every axis along them: the result is one such axis, with misfit 0.
RevolutionAxis axis_from_normals(const SurfaceElements& surface);

// The axis along `direction` (non-zero) that the surface's normals meet best: axis_from_normals' centre for a fixed
// direction. Needs at least 16 elements (else throws InputError).
RevolutionAxis axis_along(const SurfaceElements& surface, const Eigen::Vector3d& direction);

}  // namespace scanfill
