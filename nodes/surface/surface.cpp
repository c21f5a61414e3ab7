#include "nodes/surface/surface.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/poisson.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string_view>
#include <tuple>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/surface/surface_options.h"

namespace scanfill {
namespace {

// Voxel coordinates packed 21 bits a axis, on a grid of `size` from `origin`.
std::vector<std::uint64_t> voxel_keys(const Eigen::Matrix3Xd& p, const Eigen::Vector3d& origin, double size) {
  std::vector<std::uint64_t> keys(size_t(p.cols()));
  for (Index i = 0; i < p.cols(); ++i) {
    std::uint64_t key = 0;
    for (int k = 0; k < 3; ++k) {
      const auto c = std::uint64_t(std::clamp((p(k, i) - origin(k)) / size, 0.0, double((1 << 21) - 1)));
      key = (key << 21) | c;
    }
    keys[size_t(i)] = key;
  }
  return keys;
}

Index occupied_cells(std::vector<std::uint64_t> keys) {
  std::sort(keys.begin(), keys.end());
  return Index(std::unique(keys.begin(), keys.end()) - keys.begin());
}

// The cell size that leaves about `budget` occupied cells. Points on a surface fill cells in proportion to 1 / size^2:
// a first guess from the bounding box, then two corrections by that law.
double cell_size_for(const Eigen::Matrix3Xd& p, const BoundingBox& box, Index budget) {
  const double extent = (box.max - box.min).maxCoeff();
  const double finest = extent / double((1 << 21) - 2);
  double size = std::max(box.diagonal() / std::sqrt(double(budget)), finest);
  for (int round = 0; round < 2; ++round) {
    const Index cells = occupied_cells(voxel_keys(p, box.min, size));
    size = std::max(size * std::sqrt(double(cells) / double(budget)), finest);
  }
  return size;
}

struct Mesh {
  Eigen::Matrix3Xd vertices;
  Matrix3Xi faces;
  Index diagnostics = 0;  // PoissonRecon's stdout lines about unpaired edges
};

// Captures what is written to file descriptor 1 (stdout) while it lives: PoissonRecon prints its diagnostics there
// with printf and no switch turns them off (see surface.h). fd 1 is pointed at an anonymous temporary file and put back
// in the destructor, whatever happens in between (an exception included). Whatever else a thread of the process wrote
// to stdout in that window is not lost: take() hands back the text, and the caller passes on the lines that are not
// PoissonRecon's. If stdout is closed or no temporary file can be made, nothing is captured and the diagnostics go
// where they always went.
class StdoutCapture {
 public:
  StdoutCapture() {
    std::fflush(stdout);
    file_ = std::tmpfile();
    if (!file_) return;
    saved_ = ::dup(STDOUT_FILENO);
    if (saved_ >= 0 && ::dup2(::fileno(file_), STDOUT_FILENO) < 0) {
      ::close(saved_);
      saved_ = -1;
    }
  }
  ~StdoutCapture() {
    restore();
    if (file_) std::fclose(file_);
  }
  StdoutCapture(const StdoutCapture&) = delete;
  StdoutCapture& operator=(const StdoutCapture&) = delete;

  // Puts stdout back and returns what was written to it meanwhile (nothing when it could not be captured).
  std::string take() {
    if (saved_ < 0) return {};
    restore();
    std::string text;
    std::rewind(file_);
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, file_)) > 0;) text.append(buf, n);
    return text;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stdout);  // PoissonRecon's printf output still in stdio's buffer goes to the file first
    ::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
    saved_ = -1;
  }
  std::FILE* file_ = nullptr;
  int saved_ = -1;  // the real stdout while captured
};

// PoissonRecon's lines in `text` counted; the other lines written to the real stdout, as they would have been.
Index poisson_diagnostics(const std::string& text) {
  static const char* const kPrefixes[] = {"Vertex pair not in list", "Could not find vertex", "Bad Edge"};
  Index count = 0;
  std::string others;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    end = end == std::string::npos ? text.size() : end + 1;
    const std::string_view line(text.data() + start, end - start);
    bool poisson = false;
    for (const char* prefix : kPrefixes) poisson = poisson || line.starts_with(prefix);
    if (poisson)
      ++count;
    else
      others.append(line);
    start = end;
  }
  if (!others.empty()) {
    std::fwrite(others.data(), 1, others.size(), stdout);
    std::fflush(stdout);
  }
  return count;
}

// pcl::Poisson on one thread. PoissonRecon's octree allocator and node data are static: one reconstruction at a time.
Mesh run_poisson(const PointSet& points, const SurfaceOptions& options) {
  static std::mutex not_reentrant;
  const std::lock_guard<std::mutex> lock(not_reentrant);
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud(new pcl::PointCloud<pcl::PointNormal>);
  cloud->resize(size_t(points.size()));
  for (Index i = 0; i < points.size(); ++i) {
    pcl::PointNormal& q = (*cloud)[size_t(i)];
    q.getVector3fMap() = points.positions().col(i).cast<float>();
    q.getNormalVector3fMap() = points.normals().col(i).cast<float>();
  }
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setDepth(options.depth);
  poisson.setSamplesPerNode(float(options.samples_per_node));
  poisson.setThreads(1);
  poisson.setInputCloud(cloud);
  pcl::PointCloud<pcl::PointNormal> vertices;
  std::vector<pcl::Vertices> polygons;
  StdoutCapture capture;
  poisson.reconstruct(vertices, polygons);
  const Index diagnostics = poisson_diagnostics(capture.take());
  Mesh mesh{Eigen::Matrix3Xd(3, Index(vertices.size())), Matrix3Xi(3, Index(polygons.size())), diagnostics};
  for (size_t i = 0; i < vertices.size(); ++i)
    mesh.vertices.col(Index(i)) = vertices[i].getVector3fMap().cast<double>();
  Index f = 0;
  for (const pcl::Vertices& polygon : polygons) {
    if (polygon.vertices.size() != 3) continue;  // output_polygons is off: triangles only
    for (int k = 0; k < 3; ++k) mesh.faces(k, f) = std::int32_t(polygon.vertices[size_t(k)]);
    ++f;
  }
  mesh.faces.conservativeResize(3, f);
  return mesh;
}

// Each point's spacing: the side of the patch of surface it stands for, sqrt(pi r^2 / k) with r the distance to its
// k-th nearest neighbour. Robust where points cluster (merged patches, random clouds), which the mean nearest-neighbour
// distance is not.
std::vector<double> local_spacing(const KdTree& tree, const Eigen::Matrix3Xd& p) {
  const int k = int(std::min<Index>(8, p.cols() - 1));
  std::vector<double> d2;
  const std::vector<std::int32_t> knn = knn_graph(tree, p, k, &d2);
  std::vector<double> s(size_t(p.cols()));
  for (size_t i = 0; i < s.size(); ++i) {
    int found = k;
    while (found > 1 && knn[i * size_t(k) + size_t(found) - 1] < 0) --found;
    s[i] = std::sqrt(M_PI * std::max(d2[i * size_t(k) + size_t(found) - 1], 0.0) / found);
  }
  return s;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Per vertex, whether it lies within `trim` spacings of its nearest point: that point's spacing or `least`, whichever
// is larger (a dense cluster of points does not trim the surface around it).
std::vector<char> near_vertices(const Eigen::Matrix3Xd& vertices, const KdTree& tree,
                                const std::vector<double>& spacing, double least, double trim) {
  std::vector<std::int32_t> nearest;
  std::vector<double> distance2;
  nearest_each(tree, vertices, nearest, distance2);
  std::vector<char> near(distance2.size());
  for (size_t v = 0; v < near.size(); ++v) {
    const double reach = trim * std::max(spacing[size_t(nearest[v])], least);
    near[v] = distance2[v] <= reach * reach;
  }
  return near;
}

// The triangles whose three corners are near the points; the vertices they use, renumbered in order.
Mesh trimmed(const Mesh& mesh, const std::vector<char>& near_vertex) {
  std::vector<std::int32_t> renumber(size_t(mesh.vertices.cols()), -1);
  std::vector<Index> kept_faces;
  for (Index f = 0; f < mesh.faces.cols(); ++f) {
    const auto near = [&](int k) { return near_vertex[size_t(mesh.faces(k, f))] != 0; };
    if (near(0) && near(1) && near(2)) kept_faces.push_back(f);
  }
  for (const Index f : kept_faces)
    for (int k = 0; k < 3; ++k) renumber[size_t(mesh.faces(k, f))] = 0;
  std::int32_t used = 0;
  for (auto& r : renumber)
    if (r == 0) r = used++;
  Mesh out{Eigen::Matrix3Xd(3, used), Matrix3Xi(3, Index(kept_faces.size()))};
  for (size_t v = 0; v < renumber.size(); ++v)
    if (renumber[v] >= 0) out.vertices.col(renumber[v]) = mesh.vertices.col(Index(v));
  for (size_t i = 0; i < kept_faces.size(); ++i)
    for (int k = 0; k < 3; ++k) out.faces(k, Index(i)) = renumber[size_t(mesh.faces(k, kept_faces[i]))];
  return out;
}

// Area-weighted face normals summed at the vertices (a face's cross product is twice its area along its normal).
Eigen::Matrix3Xd vertex_normals(const Mesh& mesh) {
  Eigen::Matrix3Xd n = Eigen::Matrix3Xd::Zero(3, mesh.vertices.cols());
  for (Index f = 0; f < mesh.faces.cols(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.col(mesh.faces(0, f)), b = mesh.vertices.col(mesh.faces(1, f)),
                          c = mesh.vertices.col(mesh.faces(2, f));
    const Eigen::Vector3d area_normal = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) n.col(mesh.faces(k, f)) += area_normal;
  }
  for (Index v = 0; v < n.cols(); ++v) {
    const double len = n.col(v).norm();
    n.col(v) = len > 0 ? Eigen::Vector3d(n.col(v) / len) : Eigen::Vector3d::UnitZ();
  }
  return n;
}

// Whether the mesh's winding faces away from the points' normals (then every triangle is flipped).
bool winding_disagrees(const Eigen::Matrix3Xd& mesh_vertices, const Eigen::Matrix3Xd& mesh_normals,
                       const PointSet& points, const KdTree& tree) {
  std::vector<std::int32_t> nearest;
  std::vector<double> distance2;
  nearest_each(tree, mesh_vertices, nearest, distance2);
  double agreement = 0;
  for (Index v = 0; v < mesh_vertices.cols(); ++v)
    agreement += mesh_normals.col(v).dot(points.normals().col(nearest[size_t(v)]));
  return agreement < 0;
}

}  // namespace

PointSet thin_to_budget(const PointSet& points, Index max_points) {
  if (points.size() <= max_points) return points;
  const Eigen::Matrix3Xd& p = points.positions();
  const BoundingBox box = bounding_box(p);
  const double size = cell_size_for(p, box, max_points);
  const std::vector<std::uint64_t> keys = voxel_keys(p, box.min, size);
  // Per cell, the point nearest its centre (ties to the lower index): sorted by (cell, distance, index).
  std::vector<std::tuple<std::uint64_t, double, std::int32_t>> order(keys.size());
  for (Index i = 0; i < p.cols(); ++i) {
    const Eigen::Vector3d cell = ((p.col(i) - box.min) / size).array().floor();
    const Eigen::Vector3d centre = box.min + (cell.array() + 0.5).matrix() * size;
    order[size_t(i)] = {keys[size_t(i)], (p.col(i) - centre).squaredNorm(), std::int32_t(i)};
  }
  std::sort(order.begin(), order.end());
  std::vector<std::int32_t> kept;
  for (size_t i = 0; i < order.size(); ++i)
    if (i == 0 || std::get<0>(order[i]) != std::get<0>(order[i - 1])) kept.push_back(std::get<2>(order[i]));
  std::sort(kept.begin(), kept.end());
  return subset(points, kept);
}

SurfaceResult poisson_surface(const PointSet& points, const SurfaceOptions& options) {
  check_options(options);
  if (!points.has_normals()) throw InvariantError("the surface needs the points' normals");
  if (points.size() < 3)
    throw InvariantError("the surface needs at least 3 points, got " + std::to_string(points.size()));
  SurfaceResult result;
  const PointSet thinned = thin_to_budget(points, options.max_points);
  result.points_meshed = thinned.size();
  KdTree tree;
  tree.build(thinned.positions());
  const Mesh poisson = run_poisson(thinned, options);
  result.poisson_vertices = poisson.vertices.cols();
  result.poisson_faces = poisson.faces.cols();
  result.diagnostics = poisson.diagnostics;
  if (poisson.diagnostics > 0)
    result.warnings.push_back("PoissonRecon could not pair " + std::to_string(poisson.diagnostics) +
                              " iso-surface edges (its 'Vertex pair not in list' reports); the mesh may have small "
                              "holes there");
  const std::vector<double> spacing = local_spacing(tree, thinned.positions());
  result.spacing = median(spacing);
  Mesh mesh = trimmed(poisson, near_vertices(poisson.vertices, tree, spacing, result.spacing, options.trim_distance));
  result.trimmed_faces = result.poisson_faces - mesh.faces.cols();
  Eigen::Matrix3Xd normals = vertex_normals(mesh);
  if (winding_disagrees(mesh.vertices, normals, thinned, tree)) {
    mesh.faces.row(1).swap(mesh.faces.row(2));
    normals = -normals;
  }
  result.mesh = PointSet(std::move(mesh.vertices));
  result.mesh.set_normals(std::move(normals));
  result.mesh.set_faces(std::move(mesh.faces));
  result.mesh.check();
  return result;
}

}  // namespace scanfill
