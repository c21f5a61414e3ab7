#include "nodes/io/orient_faces.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <numeric>
#include <tuple>

namespace scanfill {
namespace {

// Per vertex: the lowest index of the vertices at exactly its position.
std::vector<std::int32_t> welded_vertices(const Eigen::Matrix3Xd& p) {
  std::vector<std::int32_t> order(size_t(p.cols()));
  std::iota(order.begin(), order.end(), 0);
  const auto less = [&](std::int32_t a, std::int32_t b) {
    for (int k = 0; k < 3; ++k)
      if (p(k, a) != p(k, b)) return p(k, a) < p(k, b);
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::int32_t> weld(order.size());
  for (size_t i = 0; i < order.size(); ++i) {
    const bool same = i > 0 && p.col(order[i]) == p.col(order[i - 1]);
    weld[size_t(order[i])] = same ? weld[size_t(order[i - 1])] : order[i];
  }
  return weld;
}

// One face's side of an undirected edge: the edge's welded ends (low, high), and whether the face runs low -> high.
struct EdgeSide {
  std::int32_t low, high, face;
  bool forward;
};

std::vector<EdgeSide> edge_sides(const std::vector<std::int32_t>& tri, const std::vector<std::int32_t>& weld) {
  std::vector<EdgeSide> sides;
  sides.reserve(tri.size());
  for (size_t f = 0; f * 3 < tri.size(); ++f)
    for (int j = 0; j < 3; ++j) {
      const std::int32_t u = weld[size_t(tri[3 * f + size_t(j)])], v = weld[size_t(tri[3 * f + size_t(j + 1) % 3])];
      if (u != v) sides.push_back({std::min(u, v), std::max(u, v), std::int32_t(f), u < v});
    }
  std::sort(sides.begin(), sides.end(), [](const EdgeSide& a, const EdgeSide& b) {
    return std::tie(a.low, a.high, a.face) < std::tie(b.low, b.high, b.face);
  });
  return sides;
}

// The faces' adjacency across manifold edges (CSR: neighbours of face f at [offset[f], offset[f + 1])), each with
// whether the two run the edge the same way (one must be turned); and per face, whether it borders an edge of one face
// or of three and more (its part is open).
struct FaceGraph {
  std::vector<std::int64_t> offset;
  std::vector<std::int32_t> neighbour;
  std::vector<std::uint8_t> same_way;
  std::vector<std::uint8_t> open;
};

FaceGraph face_graph(const std::vector<EdgeSide>& sides, size_t faces) {
  FaceGraph g{std::vector<std::int64_t>(faces + 1, 0), {}, {}, std::vector<std::uint8_t>(faces, 0)};
  std::vector<std::array<std::int32_t, 2>> pairs;
  std::vector<std::uint8_t> same;
  for (size_t i = 0; i < sides.size();) {
    size_t j = i;
    while (j < sides.size() && sides[j].low == sides[i].low && sides[j].high == sides[i].high) ++j;
    if (j - i == 2) {
      pairs.push_back({sides[i].face, sides[i + 1].face});
      same.push_back(sides[i].forward == sides[i + 1].forward);
    } else {
      for (size_t k = i; k < j; ++k) g.open[size_t(sides[k].face)] = 1;
    }
    i = j;
  }
  for (const auto& [a, b] : pairs) ++g.offset[size_t(a) + 1], ++g.offset[size_t(b) + 1];
  std::partial_sum(g.offset.begin(), g.offset.end(), g.offset.begin());
  g.neighbour.resize(size_t(g.offset.back()));
  g.same_way.resize(size_t(g.offset.back()));
  std::vector<std::int64_t> fill(g.offset.begin(), g.offset.end() - 1);
  for (size_t k = 0; k < pairs.size(); ++k)
    for (int s = 0; s < 2; ++s) {
      const std::int64_t at = fill[size_t(pairs[k][size_t(s)])]++;
      g.neighbour[size_t(at)] = pairs[k][size_t(1 - s)];
      g.same_way[size_t(at)] = same[k];
    }
  return g;
}

// Six times the signed volume a face encloses with the origin.
double signed_volume6(const Eigen::Matrix3Xd& p, const std::vector<std::int32_t>& tri, size_t f) {
  return p.col(tri[3 * f]).dot(p.col(tri[3 * f + 1]).cross(p.col(tri[3 * f + 2])));
}

}  // namespace

Index orient_faces(const Eigen::Matrix3Xd& positions, std::vector<std::int32_t>& triangles) {
  const size_t faces = triangles.size() / 3;
  if (faces == 0) return 0;
  const FaceGraph g = face_graph(edge_sides(triangles, welded_vertices(positions)), faces);
  std::vector<std::int8_t> turn(faces, -1);  // -1 unvisited
  std::vector<std::int32_t> part;
  Index turned = 0;
  for (size_t seed = 0; seed < faces; ++seed) {
    if (turn[seed] >= 0) continue;
    part.assign(1, std::int32_t(seed));
    turn[seed] = 0;
    bool open = false;
    double volume = 0;
    for (size_t head = 0; head < part.size(); ++head) {
      const auto f = size_t(part[head]);
      open = open || g.open[f];
      volume += (turn[f] ? -1.0 : 1.0) * signed_volume6(positions, triangles, f);
      for (std::int64_t e = g.offset[f]; e < g.offset[f + 1]; ++e) {
        const auto h = size_t(g.neighbour[size_t(e)]);
        if (turn[h] >= 0) continue;  // a non-orientable part keeps its first visit's winding
        turn[h] = std::int8_t(turn[f] ^ g.same_way[size_t(e)]);
        part.push_back(std::int32_t(h));
      }
    }
    const std::int8_t whole = !open && volume < 0;
    for (const std::int32_t f : part)
      if (turn[size_t(f)] ^ whole) {
        std::swap(triangles[3 * size_t(f) + 1], triangles[3 * size_t(f) + 2]);
        ++turned;
      }
  }
  return turned;
}

}  // namespace scanfill
