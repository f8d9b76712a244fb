// convexHull (convex_hull.h) with Qhull's reentrant C library.
#include "cga_rigid_sim/scene/convex_hull.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <map>

namespace cga_rigid_sim {
namespace scene {
namespace {

// The distinct points, in lexicographic order.
std::vector<Eigen::Vector3d> distinct(std::vector<Eigen::Vector3d> v) {
  const auto less = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

}  // namespace

ConvexHull convexHull(const std::vector<Eigen::Vector3d>& points) {
  ConvexHull out;
  const std::vector<Eigen::Vector3d> p = distinct(points);
  if (p.size() < 4) {
    out.vertices = p;
    return out;
  }
  std::vector<coordT> coords(3 * p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < 3; ++k) coords[3 * i + k] = p[i][k];
  qhT qh_storage;
  qhT* qh = &qh_storage;
  // Qhull reports to a FILE*; /dev/null keeps its messages out of the simulator's log (a flat
  // point set is a normal input here, answered below).
  FILE* sink = std::fopen("/dev/null", "w");
  QHULL_LIB_CHECK
  qh_zero(qh, sink);
  // Qt: triangulated facets; Qx would merge coplanar ones (exact enough for contacts either way).
  char options[] = "qhull Qt";
  const int failed = qh_new_qhull(qh, 3, static_cast<int>(p.size()), coords.data(), False,
                                  options, nullptr, sink);
  if (!failed) {
    std::map<int, int> index;  // point id → hull vertex
    const auto vertexOf = [&](vertexT* v) {
      const int id = qh_pointid(qh, v->point);
      const auto it = index.find(id);
      if (it != index.end()) return it->second;
      const int k = static_cast<int>(out.vertices.size());
      index.emplace(id, k);
      out.vertices.push_back(p[static_cast<std::size_t>(id)]);
      return k;
    };
    facetT* facet;
    FORALLfacets {
      if (facet->upperdelaunay) continue;
      std::array<int, 3> t{};
      int c = 0;
      vertexT *vertex, **vertexp;
      FOREACHvertex_(facet->vertices) {
        if (c < 3) t[c] = vertexOf(vertex);
        ++c;
      }
      if (c != 3) continue;
      // Outward: the facet's normal points out of the hull.
      const Eigen::Vector3d n(facet->normal[0], facet->normal[1], facet->normal[2]);
      const Eigen::Vector3d& a = out.vertices[t[0]];
      if ((out.vertices[t[1]] - a).cross(out.vertices[t[2]] - a).dot(n) < 0) std::swap(t[1], t[2]);
      out.triangles.push_back(t);
    }
  }
  int curlong = 0, totlong = 0;
  qh_freeqhull(qh, !qh_ALL);
  qh_memfreeshort(qh, &curlong, &totlong);
  if (sink) std::fclose(sink);
  if (failed || out.triangles.empty()) {  // flat or degenerate: no volume
    out.vertices = p;
    out.triangles.clear();
  }
  return out;
}

}  // namespace scene
}  // namespace cga_rigid_sim
