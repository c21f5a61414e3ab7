#include "nodes/render/render.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

// The camera's frame: right, up and forward unit vectors, and the focal length in pixels.
struct View {
  Eigen::Vector3d right, up, forward, eye;
  double focal = 1;
};

View view_of(const Camera& c, int height) {
  View v;
  v.eye = c.eye;
  v.forward = (c.target - c.eye).normalized();
  Eigen::Vector3d up = c.up;
  if (std::abs(up.normalized().dot(v.forward)) > 0.99) up = Eigen::Vector3d::UnitY();  // looking along the up axis
  v.right = v.forward.cross(up).normalized();
  v.up = v.right.cross(v.forward);
  v.focal = 0.5 * height / std::tan(0.5 * c.fov_deg * M_PI / 180);
  return v;
}

void splat(Image& image, std::vector<float>& depth, double x, double y, float z, double radius, const Rgb& colour) {
  const int x0 = std::max(0, int(std::floor(x - radius))), x1 = std::min(image.width - 1, int(std::ceil(x + radius)));
  const int y0 = std::max(0, int(std::floor(y - radius))), y1 = std::min(image.height - 1, int(std::ceil(y + radius)));
  for (int py = y0; py <= y1; ++py)
    for (int px = x0; px <= x1; ++px) {
      if ((px - x) * (px - x) + (py - y) * (py - y) > radius * radius) continue;
      const size_t i = size_t(py) * size_t(image.width) + size_t(px);
      if (z >= depth[i]) continue;
      depth[i] = z;
      std::copy(colour.begin(), colour.end(), image.rgb.begin() + std::ptrdiff_t(3 * i));
    }
}

// Where a one-sided scan was seen from: its normals face the scanner, so their mean points there (none when they do
// not agree: a closed model, or unoriented normals).
std::optional<Eigen::Vector3d> facing_eye(const PointSet& scan, const BoundingBox& box) {
  if (!scan.has_normals() || scan.size() == 0) return std::nullopt;
  const Eigen::Vector3d mean = scan.normals().rowwise().sum() / double(scan.size());
  if (mean.norm() < 0.3) return std::nullopt;
  return Eigen::Vector3d(0.5 * (box.min + box.max) + box.diagonal() * mean.normalized());
}

}  // namespace

Image blank_image(int width, int height) {
  if (width < 1 || height < 1) throw InvariantError("blank_image: the image needs at least one pixel");
  return Image{width, height, std::vector<std::uint8_t>(size_t(width) * size_t(height) * 3, 255)};
}

void render_points(const PointSet& points, const std::vector<Rgb>& colours, const Camera& camera, double radius_px,
                   Image& image) {
  if (colours.size() != 1 && Index(colours.size()) != points.size())
    throw InvariantError("render_points: one colour, or one per point");
  const View v = view_of(camera, image.height);
  std::vector<float> depth(size_t(image.width) * size_t(image.height), std::numeric_limits<float>::infinity());
  const bool shaded = points.has_normals();
  for (Index i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d d = points.positions().col(i) - v.eye;
    const double z = d.dot(v.forward);
    if (z <= 1e-9) continue;  // behind the camera
    const double x = 0.5 * image.width + v.focal * d.dot(v.right) / z;
    const double y = 0.5 * image.height - v.focal * d.dot(v.up) / z;
    Rgb c = colours.size() == 1 ? colours[0] : colours[size_t(i)];
    if (shaded) {  // two-sided Lambert with a headlight: scans' normals may face either way
      const double facing = std::abs(points.normals().col(i).dot(d.normalized()));
      for (auto& channel : c) channel = std::uint8_t(std::lround(channel * (0.35 + 0.65 * facing)));
    }
    splat(image, depth, x, y, float(z), radius_px, c);
  }
}

std::array<Camera, 2> preview_cameras(const BoundingBox& box, const std::optional<Eigen::Vector3d>& eye) {
  const Eigen::Vector3d centre = 0.5 * (box.min + box.max);
  Eigen::Vector3d direction = eye ? Eigen::Vector3d(*eye - centre) : Eigen::Vector3d(0, -1, 0.3);
  if (direction.norm() < 1e-12) direction = Eigen::Vector3d(0, -1, 0.3);
  direction.normalize();
  Camera front;
  front.fov_deg = 30;
  const double distance = 0.55 * std::max(box.diagonal(), 1e-9) / std::tan(0.5 * front.fov_deg * M_PI / 180);
  front.target = centre;
  front.eye = centre + distance * direction;
  Camera back = front;
  back.eye = centre + distance * Eigen::Vector3d(-direction.x(), -direction.y(), direction.z());
  if (std::hypot(direction.x(), direction.y()) < 1e-6) back.eye = centre - distance * direction;  // from above: below
  return {front, back};
}

Image tile_images(const std::vector<Image>& panels, int columns) {
  if (panels.empty() || columns < 1) throw InvariantError("tile_images: no panels");
  const int w = panels[0].width, h = panels[0].height, gutter = 4;
  const int cols = std::min<int>(columns, int(panels.size()));
  const int rows = (int(panels.size()) + cols - 1) / cols;
  Image out = blank_image(cols * w + (cols - 1) * gutter, rows * h + (rows - 1) * gutter);
  std::fill(out.rgb.begin(), out.rgb.end(), std::uint8_t(200));
  for (size_t p = 0; p < panels.size(); ++p) {
    if (panels[p].width != w || panels[p].height != h) throw InvariantError("tile_images: panels of different sizes");
    const int ox = int(p) % cols * (w + gutter), oy = int(p) / cols * (h + gutter);
    for (int y = 0; y < h; ++y)
      std::copy_n(panels[p].rgb.begin() + std::ptrdiff_t(3 * size_t(y) * size_t(w)), 3 * w,
                  out.rgb.begin() + std::ptrdiff_t(3 * (size_t(oy + y) * size_t(out.width) + size_t(ox))));
  }
  return out;
}

Image preview_image(const std::vector<PreviewPanel>& panels, size_t frame, const std::optional<Eigen::Vector3d>& eye,
                    int panel_size) {
  if (frame >= panels.size()) throw InvariantError("preview_image: no panel to frame");
  const BoundingBox box = bounding_box(panels[frame].points->positions());
  const std::array<Camera, 2> cameras = preview_cameras(box, eye ? eye : facing_eye(*panels[0].points, box));
  // Each image is the whole work of one task: the same pixels on any thread count.
  std::vector<Image> images(cameras.size() * panels.size());
  tbb::parallel_for(size_t(0), images.size(), [&](size_t k) {
    const Camera& camera = cameras[k / panels.size()];
    const PreviewPanel& panel = panels[k % panels.size()];
    images[k] = blank_image(panel_size, panel_size);
    // A disc as wide as the spacing at the target's distance, so surfaces look closed: 1 to 6 pixels.
    const double focal = 0.5 * panel_size / std::tan(0.5 * camera.fov_deg * M_PI / 180);
    const double radius = std::clamp(focal * panel.spacing / (camera.eye - camera.target).norm(), 1.0, 6.0);
    render_points(*panel.points, panel.colours, camera, radius, images[k]);
  });
  return tile_images(images, int(panels.size()));
}

Image plane_image(const std::vector<PreviewPanel>& panels, int panel_size) {
  if (panels.empty()) throw InvariantError("plane_image: no panels");
  BoundingBox box = bounding_box(panels[0].points->positions());
  for (const PreviewPanel& p : panels) {
    const BoundingBox b = bounding_box(p.points->positions());
    box.min = box.min.cwiseMin(b.min);
    box.max = box.max.cwiseMax(b.max);
  }
  // Seen from below the plane with up = -y: right is +x and down is +y, as in an SVG viewer.
  Camera camera;
  camera.fov_deg = 30;
  camera.target = 0.5 * (box.min + box.max);
  camera.up = -Eigen::Vector3d::UnitY();
  const double extent = std::max((box.max - box.min).head<2>().maxCoeff(), 1e-9);
  const double distance = 0.55 * extent / std::tan(0.5 * camera.fov_deg * M_PI / 180);
  camera.eye = camera.target - distance * Eigen::Vector3d::UnitZ();
  const double focal = 0.5 * panel_size / std::tan(0.5 * camera.fov_deg * M_PI / 180);
  std::vector<Image> images;
  for (const PreviewPanel& panel : panels) {
    Image image = blank_image(panel_size, panel_size);
    const double radius = std::clamp(0.6 * focal * panel.spacing / distance, 1.0, 4.0);
    render_points(PointSet(panel.points->positions()), panel.colours, camera, radius, image);  // unshaded
    images.push_back(std::move(image));
  }
  return tile_images(images, int(panels.size()));
}

}  // namespace scanfill
