#include "csgfit/features/mesh_features.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "model/linalg.h"
#include "model/random.h"

namespace csgfit {

namespace {

using linalg::cross;
using linalg::dot;

bool normalized(Vec3& v) {
  const double n = std::sqrt(dot(v, v));
  if (!(n > 1e-300)) return false;
  for (double& c : v) c /= n;
  return true;
}

struct Facet {
  Vec3 n;      // unit normal
  double area;
};

// Triangle t's unit normal and area; false for a degenerate or non-finite triangle.
bool facet_of(const TriangleMesh& mesh, std::size_t t, Facet& f) {
  const auto& tri = mesh.triangles[t];
  const auto& p0 = mesh.vertices[static_cast<std::size_t>(tri[0])];
  const auto& p1 = mesh.vertices[static_cast<std::size_t>(tri[1])];
  const auto& p2 = mesh.vertices[static_cast<std::size_t>(tri[2])];
  f.n = cross(Vec3{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]},
              Vec3{p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]});
  f.area = 0.5 * std::sqrt(dot(f.n, f.n));
  return f.area > 0 && std::isfinite(f.area) && normalized(f.n);
}

// Face area whose normal lies within the cone around +-d.
double aligned_area(const std::vector<Facet>& facets, const Vec3& d, double cos_tol) {
  double a = 0;
  for (const Facet& f : facets)
    if (std::fabs(dot(f.n, d)) >= cos_tol) a += f.area;
  return a;
}

// The area-weighted mean (signs made to agree with d) of the normals in d's cone.
Vec3 refine(const std::vector<Facet>& facets, const Vec3& d, double cos_tol) {
  Vec3 s{0, 0, 0};
  for (const Facet& f : facets) {
    const double c = dot(f.n, d);
    if (std::fabs(c) < cos_tol) continue;
    const double w = c > 0 ? f.area : -f.area;
    for (int a = 0; a < 3; ++a) s[a] += w * f.n[a];
  }
  return normalized(s) ? s : d;
}

}  // namespace

std::vector<AxisPlane> axis_planes(const TriangleMesh& mesh, double merge, double min_area) {
  const double cos_tol = std::cos(0.5 * 3.14159265358979323846 / 180);
  std::vector<AxisPlane> faces;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Facet f;
    if (!facet_of(mesh, t, f)) continue;
    const auto& tri = mesh.triangles[t];
    for (int a = 0; a < 3; ++a)
      if (std::fabs(f.n[a]) >= cos_tol) {
        double offset = 0;
        for (int v : tri) offset += mesh.vertices[static_cast<std::size_t>(v)][a];
        faces.push_back({a, offset / 3, f.area});
      }
  }
  std::sort(faces.begin(), faces.end(), [](const AxisPlane& x, const AxisPlane& y) {
    return x.axis != y.axis ? x.axis < y.axis : x.offset < y.offset;
  });
  std::vector<AxisPlane> planes;
  double weighted = 0;
  auto close = [&] {
    if (!planes.empty()) {
      planes.back().offset = weighted / planes.back().area;
      if (planes.back().area < min_area) planes.pop_back();
    }
  };
  double last = 0;
  for (const AxisPlane& f : faces) {
    if (planes.empty() || f.axis != planes.back().axis || f.offset - last > merge) {
      close();
      planes.push_back({f.axis, f.offset, 0});
      weighted = 0;
    }
    planes.back().area += f.area;
    weighted += f.area * f.offset;
    last = f.offset;
  }
  close();
  return planes;
}

std::vector<Vec3> surface_samples(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed,
                                  std::vector<Vec3>* normals) {
  std::vector<double> cumulative;
  cumulative.reserve(mesh.triangles.size());
  double total = 0;
  for (const auto& t : mesh.triangles) {
    const auto& p0 = mesh.vertices[static_cast<std::size_t>(t[0])];
    const auto& p1 = mesh.vertices[static_cast<std::size_t>(t[1])];
    const auto& p2 = mesh.vertices[static_cast<std::size_t>(t[2])];
    const Vec3 n = cross(Vec3{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]},
                         Vec3{p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]});
    const double a = 0.5 * std::sqrt(dot(n, n));
    total += std::isfinite(a) ? a : 0.0;
    cumulative.push_back(total);
  }
  std::vector<Vec3> out;
  if (!(total > 0)) return out;
  rnd::Rng rng(rnd::splitmix(seed ^ 0x5eed5a3b1e5ULL));
  out.reserve(count);
  if (normals) normals->clear(), normals->reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double x = rnd::uniform(rng, 0, total);
    const std::size_t t = static_cast<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin());
    const auto& tri = mesh.triangles[std::min(t, mesh.triangles.size() - 1)];
    double u = rnd::uniform(rng, 0, 1), v = rnd::uniform(rng, 0, 1);
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    const auto& p0 = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const auto& p1 = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const auto& p2 = mesh.vertices[static_cast<std::size_t>(tri[2])];
    out.push_back({p0[0] + u * (p1[0] - p0[0]) + v * (p2[0] - p0[0]),
                   p0[1] + u * (p1[1] - p0[1]) + v * (p2[1] - p0[1]),
                   p0[2] + u * (p1[2] - p0[2]) + v * (p2[2] - p0[2])});
    if (!normals) continue;
    const Vec3 n = cross(Vec3{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]},
                         Vec3{p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]});
    const double len = std::sqrt(dot(n, n));
    normals->push_back(len > 0 ? Vec3{n[0] / len, n[1] / len, n[2] / len} : Vec3{0, 0, 1});
  }
  return out;
}

Quaternion dominant_frame(const TriangleMesh& mesh) {
  // Faces, subsampled evenly beyond 200k: the frame is a statistic of the normals.
  const std::size_t nt = mesh.triangles.size();
  const std::size_t stride = std::max<std::size_t>(1, nt / 200000);
  std::vector<Facet> facets;
  facets.reserve(nt / stride + 1);
  double total = 0;
  for (std::size_t t = 0; t < nt; t += stride) {
    Facet f;
    if (!facet_of(mesh, t, f)) continue;
    facets.push_back(f);
    total += f.area;
  }
  if (facets.empty() || !(total > 0)) return Quaternion{};
  const double cos_tol = std::cos(2.0 * 3.14159265358979323846 / 180);
  const double sin_tol = std::sin(2.0 * 3.14159265358979323846 / 180);

  // Candidate directions: the normals of the largest faces, one per 2-degree cone.
  std::vector<std::size_t> order(facets.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return facets[a].area > facets[b].area; });
  std::vector<Vec3> candidates;
  for (std::size_t i : order) {
    if (candidates.size() >= 48) break;
    const Vec3& n = facets[i].n;
    bool known = false;
    for (const Vec3& c : candidates) known = known || std::fabs(dot(c, n)) >= cos_tol;
    if (!known) candidates.push_back(n);
  }
  std::vector<double> score(candidates.size());
  for (std::size_t c = 0; c < candidates.size(); ++c)
    score[c] = aligned_area(facets, candidates[c], cos_tol);

  std::size_t first = 0;
  for (std::size_t c = 1; c < candidates.size(); ++c)
    if (score[c] > score[first]) first = c;
  // Planar faces must carry a real share of the surface to be worth a frame.
  if (score[first] < 0.1 * total) return Quaternion{};
  const Vec3 d1 = refine(facets, candidates[first], cos_tol);
  Vec3 d2{0, 0, 0};
  double best2 = 0;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    if (std::fabs(dot(candidates[c], d1)) > sin_tol || score[c] <= best2) continue;
    best2 = score[c];
    d2 = candidates[c];
  }
  if (best2 > 0) {
    d2 = refine(facets, d2, cos_tol);
  } else {
    // Nothing planar across d1 (a turned part): the model axis most across d1.
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (std::fabs(d1[a]) < std::fabs(d1[axis])) axis = a;
    d2 = Vec3{0, 0, 0};
    d2[axis] = 1;
  }
  // Gram-Schmidt: d2 exactly across d1.
  const double c12 = dot(d2, d1);
  for (int a = 0; a < 3; ++a) d2[a] -= c12 * d1[a];
  if (!normalized(d2)) return Quaternion{};
  const Vec3 d3 = cross(d1, d2);

  // Among the 24 proper signed permutations of (d1, d2, d3), the one nearest the identity, so
  // that the frame's x is the model's x as far as the part allows.
  const Vec3 dirs[3] = {d1, d2, d3};
  Mat3 best{};
  double best_trace = -10;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : perms) {
    for (int signs = 0; signs < 8; ++signs) {
      Mat3 m{};
      for (int col = 0; col < 3; ++col) {
        const double s = (signs >> col) & 1 ? -1.0 : 1.0;
        for (int row = 0; row < 3; ++row) m[row][col] = s * dirs[p[col]][row];
      }
      if (linalg::view(m).determinant() < 0) continue;  // a reflection
      const double trace = m[0][0] + m[1][1] + m[2][2];
      if (trace > best_trace) {
        best_trace = trace;
        best = m;
      }
    }
  }
  // Keep the model's own axes when they are (nearly) as good: a part drawn axis-aligned stays
  // so, and a rotation of a fraction of a degree would only make every number ugly.
  double own = 0, framed = 0;
  for (int a = 0; a < 3; ++a) {
    Vec3 e{0, 0, 0};
    e[a] = 1;
    own += aligned_area(facets, e, cos_tol);
    framed += aligned_area(facets, linalg::column(best, a), cos_tol);
  }
  if (own >= 0.9 * framed || best_trace > 3 - 1e-6) return Quaternion{};
  Quaternion q = quaternion_from_matrix(best);
  q.normalize();
  return q;
}

}  // namespace csgfit
