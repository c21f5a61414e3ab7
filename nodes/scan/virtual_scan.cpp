#include "nodes/scan/virtual_scan.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "nodes/core/errors.h"
#include "nodes/scan/virtual_scan_options.h"

namespace scanfill {

Eigen::Vector3d default_up(const Eigen::Vector3d& forward) {
  return std::abs(forward.normalized().z()) > 0.99 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
}

ScanOptions default_camera(const PointSet& mesh, const Eigen::Vector3d& eye,
                           const std::optional<Eigen::Vector3d>& target, const std::optional<Eigen::Vector3d>& up) {
  ScanOptions o;
  o.eye = eye;
  if (target) {
    o.target = *target;
  } else {
    const BoundingBox box = bounding_box(mesh.positions());
    o.target = (box.min + box.max) / 2;
  }
  o.up = up ? *up : default_up(o.target - o.eye);
  return o;
}

ScanResult virtual_scan(const PointSet& mesh, const ScanOptions& o) {
  if (!mesh.has_faces()) throw InputError("the virtual scanner needs a mesh (faces), not a point cloud");
  const Eigen::Vector3d forward = (o.target - o.eye).normalized();
  if (!forward.allFinite()) throw InputError("scanner eye and target coincide");
  const Eigen::Vector3d up = forward.cross(o.up).norm() < 1e-9 ? default_up(forward) : o.up;
  const Eigen::Vector3d right = forward.cross(up).normalized(), cam_up = right.cross(forward);
  const double tan_half = std::tan(o.fov_deg * M_PI / 360.0), aspect = double(o.width) / double(o.height);
  const double near = 1e-9;
  const int W = o.width, H = o.height;

  // Camera coordinates and pixel positions of the vertices.
  const auto& P = mesh.positions();
  const Index nv = P.cols();
  Eigen::Matrix3Xd cam(3, nv);
  Eigen::Matrix2Xd pix(2, nv);
  for (Index i = 0; i < nv; ++i) {
    const Eigen::Vector3d d = P.col(i) - o.eye;
    cam.col(i) << d.dot(right), d.dot(cam_up), d.dot(forward);
    const double z = cam(2, i);
    pix.col(i) << (cam(0, i) / (z * tan_half * aspect) + 1) * 0.5 * W, (1 - cam(1, i) / (z * tan_half)) * 0.5 * H;
  }
  // z-buffer: depth along `forward` and the face seen, per pixel.
  std::vector<double> depth(size_t(W) * size_t(H), std::numeric_limits<double>::infinity());
  std::vector<std::int32_t> face(size_t(W) * size_t(H), -1);
  const auto& F = mesh.faces();
  for (Index f = 0; f < F.cols(); ++f) {
    const int a = F(0, f), b = F(1, f), c = F(2, f);
    if (cam(2, a) <= near || cam(2, b) <= near || cam(2, c) <= near) continue;  // behind the camera: not scanned
    const Eigen::Vector3d n = (P.col(b) - P.col(a)).cross(P.col(c) - P.col(a));
    if (n.dot(o.eye - P.col(a)) <= 0) continue;  // back face
    const Eigen::Vector2d pa = pix.col(a), pb = pix.col(b), pc = pix.col(c);
    const double area = (pb - pa).x() * (pc - pa).y() - (pb - pa).y() * (pc - pa).x();
    if (std::abs(area) < 1e-18) continue;
    const int x0 = std::max(0, int(std::floor(std::min({pa.x(), pb.x(), pc.x()})))),
              x1 = std::min(W - 1, int(std::ceil(std::max({pa.x(), pb.x(), pc.x()})))),
              y0 = std::max(0, int(std::floor(std::min({pa.y(), pb.y(), pc.y()})))),
              y1 = std::min(H - 1, int(std::ceil(std::max({pa.y(), pb.y(), pc.y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d q(x + 0.5, y + 0.5);
        // Screen-space barycentrics; depth interpolated as 1/z (perspective-correct).
        const double w0 = ((pb - q).x() * (pc - q).y() - (pb - q).y() * (pc - q).x()) / area;
        const double w1 = ((pc - q).x() * (pa - q).y() - (pc - q).y() * (pa - q).x()) / area;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const double z = 1.0 / (w0 / cam(2, a) + w1 / cam(2, b) + w2 / cam(2, c));
        const size_t k = size_t(y) * size_t(W) + size_t(x);
        if (z < depth[k]) {
          depth[k] = z;
          face[k] = std::int32_t(f);
        }
      }
  }
  // One point per pixel that sees the surface, in row-major pixel order.
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  // Counted first, so that the points are made once in place (a 5800 x 5800 scan has 10^7 of them).
  const Index hits = Index(std::count_if(face.begin(), face.end(), [](std::int32_t f) { return f >= 0; }));
  if (hits == 0) throw InputError("no pixel of the virtual scanner sees the mesh (check --eye and --target)");
  ScanResult result;
  result.pixels_hit = hits;
  Eigen::Matrix3Xd Pm(3, hits), Nm(3, hits);
  Index i = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t k = size_t(y) * size_t(W) + size_t(x);
      if (face[k] < 0) continue;
      const double xn = (x + 0.5) / (0.5 * W) - 1, yn = 1 - (y + 0.5) / (0.5 * H);
      const Eigen::Vector3d ray = (forward + xn * tan_half * aspect * right + yn * tan_half * cam_up).normalized();
      double along = depth[k] / ray.dot(forward);
      if (o.noise > 0) along += o.noise * gauss(rng);
      Pm.col(i) = o.eye + along * ray;
      const auto f = face[k];
      Nm.col(i++) = (P.col(F(1, f)) - P.col(F(0, f))).cross(P.col(F(2, f)) - P.col(F(0, f))).normalized();
    }
  result.points.set_positions(std::move(Pm));
  result.points.set_normals(std::move(Nm));
  result.points.set_viewpoint(o.eye);
  return result;
}

LoadResult virtual_scan_input(LoadResult load, const VirtualScanOptions& options, const std::string& name) {
  if (!options.eye) return load;
  check_options(options);
  if (!load.points.has_faces())
    throw InputError(name + ": virtual_scan needs a mesh (triangles), got a point cloud of " +
                     std::to_string(load.points.size()) + " points");
  ScanOptions o = default_camera(load.points, *options.eye, options.target, options.up);
  o.width = options.width;
  o.height = options.height;
  o.fov_deg = options.fov_deg;
  o.noise = options.noise;
  o.seed = options.seed;
  ScanResult scan = virtual_scan(load.points, o);
  load.points = std::move(scan.points);
  load.format += " (virtual scan)";
  load.file_points = load.points.size();
  return load;
}

}  // namespace scanfill
