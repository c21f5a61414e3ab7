// render: a small z-buffered point renderer for the run's preview.png (issue 14): each point a shaded disc, nearest
// wins, no external renderer. Pure and deterministic (one pass in point order).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "nodes/core/image.h"
#include "nodes/core/point_set.h"

namespace scanfill {

struct Camera {
  Eigen::Vector3d eye = Eigen::Vector3d(0, -3, 0);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fov_deg = 30.0;
};

// A white image.
Image blank_image(int width, int height);

// Draws `points` into `image` seen by `camera`: discs of `radius_px` pixels, coloured by `colours` (one per point, or
// one for all), shaded by the normal's facing when there are normals. The z-buffer is the image's own: call once per
// image (later calls draw over earlier ones).
void render_points(const PointSet& points, const std::vector<Rgb>& colours, const Camera& camera, double radius_px,
                   Image& image);

// Two cameras framing `box`: from the direction of `eye` (default: the front, -y, slightly above) and from the
// opposite side (turned half about the vertical through the box centre).
std::array<Camera, 2> preview_cameras(const BoundingBox& box, const std::optional<Eigen::Vector3d>& eye);

// Panels side by side, `columns` a row, with a 4-pixel grey gutter. Panels must share one size.
Image tile_images(const std::vector<Image>& panels, int columns);

// One panel of a preview: points with their colours (one, or one per point) and their spacing (disc size).
struct PreviewPanel {
  const PointSet* points = nullptr;
  std::vector<Rgb> colours;
  double spacing = 0;  // mean distance between neighbouring points, model units (> 0)
};

// The panels in a row seen from `eye` (preview_cameras), and below them the same seen from the opposite side, all
// framed on the bounding box of panel `frame`; each panel panel_size pixels square. Without an eye, the first panel
// (the scan) decides: its mean normal points to where a one-sided scan was seen from; else the front.
Image preview_image(const std::vector<PreviewPanel>& panels, size_t frame, const std::optional<Eigen::Vector3d>& eye,
                    int panel_size = 360);

// Drawings of the plane z = 0 (mode curves), one panel each in a row, all on one scale framed on the panels' common
// bounding box, as an SVG viewer shows them (x to the right, y down); points as flat discs, unshaded.
Image plane_image(const std::vector<PreviewPanel>& panels, int panel_size = 360);

}  // namespace scanfill
