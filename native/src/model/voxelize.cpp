// Robust voxelisation of triangle meshes.
//
// Every voxel centre gets six votes: the winding number along a ray to -inf and to +inf in x,
// y and z (non-zero rule). One sorted list of signed crossings per grid row answers a whole row
// at once, so the cost is O(triangle footprints + voxels) per axis. For a closed mesh all six
// agree; where a mesh is open the rays that leave through a hole disagree with the others, and
// the split votes (2 to 4 of 6) are settled by the generalised winding number (Jacobson,
// Kavan, Sorkine-Hornung 2013), evaluated exactly but only at those voxels.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/model/voxelize.h"
#include "model/triangle_geometry.h"

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct P2 {
  double u, v;
};

// Orientation of p against the line a->b, with a sign that is never 0 for a proper edge: ties
// are broken by simulation of simplicity, as if every sample point were moved by
// (e1, e2, e3), e1 >> e2 >> e3 > 0, in (x, y, z). In a ray's (u, v) plane that moves p by
// (eps, eps^2) when u is the more perturbed axis, by (eps^2, eps) otherwise (v_major). The value
// is computed from the endpoints in a canonical order, so two triangles sharing an edge get
// exactly opposite results and a ray through an edge or a vertex is counted by exactly one
// triangle of a closed fan.
int edge_sign(P2 a, P2 b, P2 p, bool v_major, double* value) {
  const bool swapped = b.u < a.u || (b.u == a.u && b.v < a.v);
  if (swapped) std::swap(a, b);
  double w = (b.u - a.u) * (p.v - a.v) - (b.v - a.v) * (p.u - a.u);
  // Moving p by (du, dv) adds (b.u - a.u) * dv - (b.v - a.v) * du.
  const int su = b.v > a.v ? -1 : (b.v < a.v ? 1 : 0);  // the du term
  const int sv = b.u > a.u ? 1 : (b.u < a.u ? -1 : 0);  // the dv term
  int s;
  if (w > 0) {
    s = 1;
  } else if (w < 0) {
    s = -1;
  } else if (!v_major) {
    s = su != 0 ? su : sv;
  } else {
    s = sv != 0 ? sv : su;
  }
  if (swapped) {
    w = -w;
    s = -s;
  }
  *value = w;
  return s;
}

struct Crossing {
  double t;           // position along the ray axis
  std::uint32_t row;  // iv * nu + iu
  std::int16_t sign;  // +1 where the ray (towards +axis) enters, -1 where it leaves
  bool tie_left;      // when t equals a sample's coordinate: is the crossing before the sample?
};

// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee 1983).
double solid_angle(const double a[3], const double b[3], const double c[3]) {
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  const double lc = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const double ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
  const double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
  const double den = la * lb * lc + ab * lc + ac * lb + bc * la;
  return 2 * std::atan2(det, den);
}

void check_mesh(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) throw InputError("cannot voxelise: the mesh has no triangles");
  const std::size_t nv = mesh.vertices.size();
  for (const auto& t : mesh.triangles) {
    for (int v : t) {
      if (v < 0 || static_cast<std::size_t>(v) >= nv) {
        throw InputError("cannot voxelise: a triangle refers to vertex " + std::to_string(v) +
                         " of " + std::to_string(nv) + " (index out of range)");
      }
      for (double c : mesh.vertices[v]) {
        if (!std::isfinite(c)) {
          throw InputError("cannot voxelise: the mesh has a non-finite coordinate (NaN or infinity)");
        }
      }
    }
  }
}

// Vertex-connected pieces of a welded mesh.
std::vector<int> piece_labels(const TriangleMesh& mesh, int* count) {
  std::vector<int> parent(mesh.vertices.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto root = [&parent](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : mesh.triangles) {
    const int a = root(t[0]);
    for (int k = 1; k < 3; ++k) {
      const int b = root(t[k]);
      if (a != b) parent[b] = a;
    }
  }
  std::vector<int> label(mesh.vertices.size(), -1);
  std::vector<int> tri_label(mesh.triangles.size());
  *count = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    int& l = label[root(mesh.triangles[t][0])];
    if (l < 0) l = (*count)++;
    tri_label[t] = l;
  }
  return tri_label;
}

// A piece whose triangles face inward (negative volume) is a cavity if it lies inside the rest
// of the mesh, and was authored inside out otherwise: those are flipped, so that a soup of
// overlapping parts gives their union under the non-zero rule whichever way each part faces.
// "Inside" is the winding number of the other pieces at a few of the piece's triangle
// centroids. Returns the number of triangles flipped.
std::size_t flip_inverted_pieces(TriangleMesh& mesh, double budget) {
  int count = 0;
  const std::vector<int> label = piece_labels(mesh, &count);
  if (count < 2) {
    // A single inverted piece needs no flip: the non-zero rule ignores the sign.
    return 0;
  }
  std::vector<double> volume(static_cast<std::size_t>(count), 0.0);
  std::vector<std::vector<int>> members(static_cast<std::size_t>(count));
  const auto& o = mesh.vertices.front();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    volume[label[t]] += geometry::six_signed_volume(o, mesh.vertices[tri[0]],
                                                    mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    members[label[t]].push_back(static_cast<int>(t));
  }
  constexpr int kSamples = 9;
  const double tris = static_cast<double>(mesh.triangles.size());
  double work = 0;
  std::size_t flipped = 0;
  for (int p = 0; p < count; ++p) {
    if (volume[p] >= 0) continue;
    work += kSamples * tris;
    if (work > budget) break;
    const std::vector<int>& mine = members[p];
    int inside = 0, samples = 0;
    for (int s = 0; s < kSamples && s < static_cast<int>(mine.size()); ++s) {
      const auto& tri = mesh.triangles[mine[mine.size() * s / kSamples]];
      std::array<double, 3> centroid{};
      for (int k = 0; k < 3; ++k) {
        for (int a = 0; a < 3; ++a) centroid[a] += mesh.vertices[tri[k]][a] / 3;
      }
      double w = 0;
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (label[t] == p) continue;
        double q[3][3];
        for (int k = 0; k < 3; ++k) {
          for (int a = 0; a < 3; ++a) q[k][a] = mesh.vertices[mesh.triangles[t][k]][a] - centroid[a];
        }
        w += solid_angle(q[0], q[1], q[2]);
      }
      inside += std::abs(w) >= 2 * kPi;  // |winding number| >= 1/2
      ++samples;
    }
    if (2 * inside < samples) {
      for (int t : mine) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
      flipped += mine.size();
    }
  }
  return flipped;
}

// The generalised winding number with far-field clustering (a one-level version of Barill et
// al. 2018, "Fast winding numbers for soups and clouds"): triangles are grouped by Morton
// order of their centroids; a group far from the query point (distance > kFar times its
// radius) contributes the solid angle of its total area vector placed at its area centroid,
// the others are summed exactly.
class FastWinding {
 public:
  static constexpr int kGroup = 32;
  static constexpr double kFar = 3.0;

  explicit FastWinding(const TriangleMesh& mesh) {
    const std::size_t nt = mesh.triangles.size();
    std::array<double, 3> lo = mesh.vertices[mesh.triangles[0][0]], hi = lo;
    std::vector<std::array<double, 3>> centroid(nt);
    for (std::size_t t = 0; t < nt; ++t) {
      for (int a = 0; a < 3; ++a) {
        centroid[t][a] = (mesh.vertices[mesh.triangles[t][0]][a] + mesh.vertices[mesh.triangles[t][1]][a] +
                          mesh.vertices[mesh.triangles[t][2]][a]) / 3;
        lo[a] = std::min(lo[a], centroid[t][a]);
        hi[a] = std::max(hi[a], centroid[t][a]);
      }
    }
    std::vector<std::pair<std::uint64_t, int>> order(nt);
    for (std::size_t t = 0; t < nt; ++t) {
      std::uint64_t code = 0;
      std::uint32_t q[3];
      for (int a = 0; a < 3; ++a) {
        const double ext = hi[a] - lo[a];
        q[a] = ext > 0 ? static_cast<std::uint32_t>((centroid[t][a] - lo[a]) / ext * 2097151.0) : 0;
      }
      for (int bit = 20; bit >= 0; --bit) {
        for (int a = 0; a < 3; ++a) code = (code << 1) | ((q[a] >> bit) & 1u);
      }
      order[t] = {code, static_cast<int>(t)};
    }
    std::sort(order.begin(), order.end());
    tri_.resize(nt * 9);
    for (std::size_t i = 0; i < nt; ++i) {
      const auto& t = mesh.triangles[order[i].second];
      for (int k = 0; k < 3; ++k) {
        for (int a = 0; a < 3; ++a) tri_[i * 9 + k * 3 + a] = mesh.vertices[t[k]][a];
      }
    }
    for (std::size_t b = 0; b < nt; b += kGroup) {
      const std::size_t e = std::min(nt, b + kGroup);
      Group g;
      g.begin = b;
      g.end = e;
      double area_sum = 0;
      std::array<double, 3> c{0, 0, 0};
      for (std::size_t i = b; i < e; ++i) {
        const double* v = &tri_[i * 9];
        const double u[3] = {v[3] - v[0], v[4] - v[1], v[5] - v[2]};
        const double w[3] = {v[6] - v[0], v[7] - v[1], v[8] - v[2]};
        const double n[3] = {0.5 * (u[1] * w[2] - u[2] * w[1]), 0.5 * (u[2] * w[0] - u[0] * w[2]),
                             0.5 * (u[0] * w[1] - u[1] * w[0])};
        const double area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int a = 0; a < 3; ++a) {
          g.normal[a] += n[a];
          c[a] += area * (v[a] + v[3 + a] + v[6 + a]) / 3;
        }
        area_sum += area;
      }
      for (int a = 0; a < 3; ++a) {
        g.centre[a] = area_sum > 0 ? c[a] / area_sum : tri_[b * 9 + a];
      }
      for (std::size_t i = b * 3; i < e * 3; ++i) {
        const double dx = tri_[i * 3] - g.centre[0], dy = tri_[i * 3 + 1] - g.centre[1],
                     dz = tri_[i * 3 + 2] - g.centre[2];
        g.radius = std::max(g.radius, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
      groups_.push_back(g);
    }
  }

  double at(const std::array<double, 3>& p) const {
    double sum = 0;
    for (const Group& g : groups_) {
      const double d[3] = {g.centre[0] - p[0], g.centre[1] - p[1], g.centre[2] - p[2]};
      const double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      if (d2 > kFar * kFar * g.radius * g.radius) {
        sum += (g.normal[0] * d[0] + g.normal[1] * d[1] + g.normal[2] * d[2]) / (d2 * std::sqrt(d2));
        continue;
      }
      for (std::size_t i = g.begin; i < g.end; ++i) {
        const double* v = &tri_[i * 9];
        const double a[3] = {v[0] - p[0], v[1] - p[1], v[2] - p[2]};
        const double b[3] = {v[3] - p[0], v[4] - p[1], v[5] - p[2]};
        const double c[3] = {v[6] - p[0], v[7] - p[1], v[8] - p[2]};
        sum += solid_angle(a, b, c);
      }
    }
    return sum / (4 * kPi);
  }

  // Solid-angle evaluations per query, roughly, for the work budget.
  double cost_per_query() const {
    return static_cast<double>(groups_.size()) + 8.0 * kGroup;
  }

 private:
  struct Group {
    std::size_t begin = 0, end = 0;
    std::array<double, 3> centre{{0, 0, 0}};
    std::array<double, 3> normal{{0, 0, 0}};  // area vector: sum of area * unit normal
    double radius = 0;
  };
  std::vector<double> tri_;  // 9 coordinates per triangle, in Morton order
  std::vector<Group> groups_;
};

}  // namespace

double winding_number(const TriangleMesh& mesh, const std::array<double, 3>& p) {
  double sum = 0;
  for (const auto& t : mesh.triangles) {
    double q[3][3];
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) q[k][a] = mesh.vertices[t[k]][a] - p[a];
    }
    sum += solid_angle(q[0], q[1], q[2]);
  }
  return sum / (4 * kPi);
}

namespace {

// Where the voxel centres are: the mesh's bounding box centred in whole voxels, plus the
// margin, moved by the lattice shift.
struct Lattice {
  int n[3];
  double origin[3];
  double h;
  std::size_t stride[3];  // of a voxel's index in the vote array, x fastest
  std::size_t voxels;
};

Lattice place_lattice(const TriangleMesh& mesh, const VoxelizeOptions& options) {
  std::array<double, 3> lo{}, hi{};
  bool first = true;
  for (const auto& t : mesh.triangles) {
    for (int v : t) {
      for (int a = 0; a < 3; ++a) {
        const double c = mesh.vertices[v][a];
        if (first || c < lo[a]) lo[a] = c;
        if (first || c > hi[a]) hi[a] = c;
      }
      first = false;
    }
  }
  if (options.cover_box)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], options.box_lo[a]);
      hi[a] = std::max(hi[a], options.box_hi[a]);
    }
  const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!(longest > 0)) throw InputError("cannot voxelise: the mesh has no extent (all vertices coincide)");
  if (options.margin < 0 || options.margin > 1000) {
    throw InputError("voxel margin " + std::to_string(options.margin) + " is outside 0..1000");
  }
  if (!(options.lattice_shift >= 0 && options.lattice_shift < 1))
    throw InputError("lattice shift " + std::to_string(options.lattice_shift) + " is outside [0, 1)");
  Lattice g;
  g.h = options.voxel_size;
  if (!(g.h > 0)) {
    if (options.resolution < 1) {
      throw InputError("voxel resolution " + std::to_string(options.resolution) + " must be at least 1");
    }
    g.h = longest / options.resolution;
  }
  const double h = g.h;
  if (!std::isfinite(h)) throw InputError("voxel size is not a finite number");
  double total = 1;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::ceil((hi[a] - lo[a]) / h - 1e-9);
    const double count = std::max(1.0, cells) + 2.0 * options.margin;
    total *= count;
    if (count > 1e9 || total > static_cast<double>(options.max_voxels)) {
      throw InputError("a voxel size of " + std::to_string(h) + " gives more than " +
                       std::to_string(options.max_voxels) + " voxels for this mesh (the limit)");
    }
    g.n[a] = static_cast<int>(count);
    g.origin[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * g.n[a] * h + options.lattice_shift * h;
  }
  g.voxels = static_cast<std::size_t>(g.n[0]) * g.n[1] * g.n[2];
  g.stride[0] = 1;
  g.stride[1] = static_cast<std::size_t>(g.n[0]);
  g.stride[2] = static_cast<std::size_t>(g.n[0]) * g.n[1];
  return g;
}

// Where the rays along axis a through the voxel centres cross the mesh's triangles, with the
// direction of each crossing (into or out of the solid).
void collect_crossings(const TriangleMesh& mesh, const Lattice& g, int a,
                       std::vector<Crossing>& crossings) {
  const double h = g.h;
  const int ua = (a + 1) % 3, va = (a + 2) % 3;  // (u, v, a) is right-handed
  const bool v_major = va < ua;                   // v is x for the y rays
  const int nu = g.n[ua], nvv = g.n[va];
  crossings.clear();
  for (const auto& t : mesh.triangles) {
    const auto& A = mesh.vertices[t[0]];
    const auto& B = mesh.vertices[t[1]];
    const auto& C = mesh.vertices[t[2]];
    const P2 p0{A[ua], A[va]}, p1{B[ua], B[va]}, p2{C[ua], C[va]};
    // Where the crossing lies exactly at a sample's coordinate, the perturbed sample is past
    // it if its own shift along the ray outweighs the shift of the crossing, which moves
    // with the sample's (u, v) shift by -(n_u du + n_v dv) / n_a along the plane.
    bool tie_left = true;
    {
      const double e1[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]};
      const double e2[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
      const double nrm[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
      // Axes in order of decreasing shift: x, y, z. Before the ray's own axis, a non-zero
      // normal component decides; the ray's own axis shift (+) means "crossing before".
      for (int axis = 0; axis < 3; ++axis) {
        if (axis == a) break;
        if (nrm[axis] != 0) {
          tie_left = (nrm[axis] / nrm[a]) > 0;  // crossing moves by -(n_axis / n_a) * shift
          break;
        }
      }
    }
    const double umin = std::min({p0.u, p1.u, p2.u}), umax = std::max({p0.u, p1.u, p2.u});
    const double vmin = std::min({p0.v, p1.v, p2.v}), vmax = std::max({p0.v, p1.v, p2.v});
    // Rows whose centre may lie in the projected bounding box, one extra on each side so
    // that rounding here can never drop a row the exact edge test would accept.
    const int iu0 = std::max(0, static_cast<int>(std::floor((umin - g.origin[ua]) / h - 0.5)));
    const int iu1 = std::min(nu - 1, static_cast<int>(std::ceil((umax - g.origin[ua]) / h - 0.5)));
    const int iv0 = std::max(0, static_cast<int>(std::floor((vmin - g.origin[va]) / h - 0.5)));
    const int iv1 = std::min(nvv - 1, static_cast<int>(std::ceil((vmax - g.origin[va]) / h - 0.5)));
    for (int iv = iv0; iv <= iv1; ++iv) {
      const double cv = g.origin[va] + (iv + 0.5) * h;
      for (int iu = iu0; iu <= iu1; ++iu) {
        const P2 c{g.origin[ua] + (iu + 0.5) * h, cv};
        double w0, w1, w2;
        const int s0 = edge_sign(p1, p2, c, v_major, &w0);
        const int s1 = edge_sign(p2, p0, c, v_major, &w1);
        const int s2 = edge_sign(p0, p1, c, v_major, &w2);
        if (s0 == 0 || s0 != s1 || s1 != s2) continue;
        const double wsum = w0 + w1 + w2;
        if (wsum == 0) continue;  // degenerate in projection
        double depth = (w0 * A[a] + w1 * B[a] + w2 * C[a]) / wsum;
        // Rounding can put the depth a hair outside the triangle's own range.
        depth = std::clamp(depth, std::min({A[a], B[a], C[a]}), std::max({A[a], B[a], C[a]}));
        // Counter-clockwise in (u, v) means the normal points along +a: the ray leaves.
        crossings.push_back({depth, static_cast<std::uint32_t>(iv * nu + iu),
                             static_cast<std::int16_t>(s0 > 0 ? -1 : 1), tie_left});
      }
    }
  }
}

// Each voxel's votes from the rays along axis a (from -inf and from +inf): a ray's winding
// number at the centre is non-zero when the centre is inside.
void count_votes(std::vector<Crossing>& crossings, const Lattice& g, int a,
                 std::vector<std::uint8_t>& votes) {
  const double h = g.h;
  const int ua = (a + 1) % 3, va = (a + 2) % 3;
  const int nu = g.n[ua];
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& x, const Crossing& y) {
    if (x.row != y.row) return x.row < y.row;
    if (x.t != y.t) return x.t < y.t;
    return x.tie_left > y.tie_left;
  });
  const int na = g.n[a];
  for (std::size_t i = 0; i < crossings.size();) {
    std::size_t j = i;
    int total_sign = 0;
    while (j < crossings.size() && crossings[j].row == crossings[i].row) {
      total_sign += crossings[j].sign;
      ++j;
    }
    const int iu = static_cast<int>(crossings[i].row % static_cast<std::uint32_t>(nu));
    const int iv = static_cast<int>(crossings[i].row / static_cast<std::uint32_t>(nu));
    std::size_t base = static_cast<std::size_t>(iu) * g.stride[ua] + static_cast<std::size_t>(iv) * g.stride[va];
    int left = 0;  // winding number from -inf up to the current centre
    std::size_t k = i;
    for (int m = 0; m < na; ++m, base += g.stride[a]) {
      const double centre = g.origin[a] + (m + 0.5) * h;
      while (k < j && (crossings[k].t < centre || (crossings[k].t == centre && crossings[k].tie_left))) {
        left += crossings[k++].sign;
      }
      const int right = left - total_sign;  // winding number from +inf
      votes[base] = static_cast<std::uint8_t>(votes[base] + (left != 0) + (right != 0));
    }
    i = j;
  }
}

// Split votes (2, 3 or 4 of 6) decided by the generalised winding number where the budget
// allows, by the vote otherwise (ties inside).
void settle_split_votes(const TriangleMesh& mesh, const Lattice& g, const VoxelizeOptions& options,
                        std::vector<std::uint8_t>& votes, VoxelizeStats& st) {
  const double h = g.h;
  const std::size_t voxels = g.voxels;
  std::vector<std::size_t> ambiguous;
  for (std::size_t i = 0; i < voxels; ++i) {
    if (votes[i] >= 2 && votes[i] <= 4) ambiguous.push_back(i);
  }
  st.ambiguous_voxels = ambiguous.size();
  std::vector<std::size_t> exact;
  if (!ambiguous.empty()) {
    const FastWinding winding(mesh);
    const double cost = winding.cost_per_query();
    if (static_cast<double>(ambiguous.size()) * cost <= options.winding_budget) {
      exact = ambiguous;
    } else {
      for (std::size_t i : ambiguous) {
        if (votes[i] == 3) exact.push_back(i);
      }
      if (static_cast<double>(exact.size()) * cost > options.winding_budget) exact.clear();
    }
    for (std::size_t i : ambiguous) votes[i] = votes[i] >= 3 ? 6 : 0;  // the vote, ties inside
    // Two threads: the machine has two cores and each query is independent.
    auto work = [&](std::size_t from, std::size_t to) {
      for (std::size_t e = from; e < to; ++e) {
        const std::size_t i = exact[e];
        const std::size_t x = i % g.stride[1], y = (i / g.stride[1]) % static_cast<std::size_t>(g.n[1]),
                          z = i / g.stride[2];
        const std::array<double, 3> p{g.origin[0] + (static_cast<double>(x) + 0.5) * h,
                                      g.origin[1] + (static_cast<double>(y) + 0.5) * h,
                                      g.origin[2] + (static_cast<double>(z) + 0.5) * h};
        votes[i] = std::abs(winding.at(p)) >= 0.5 ? 6 : 0;
      }
    };
    if (exact.size() >= 2048) {
      std::thread helper(work, exact.size() / 2, exact.size());
      work(0, exact.size() / 2);
      helper.join();
    } else {
      work(0, exact.size());
    }
  }
  st.winding_evaluations = exact.size();
}

VoxelGrid grid_from_votes(const Lattice& g, const std::vector<std::uint8_t>& votes) {
  const int* n = g.n;
  VoxelGrid grid(n[0], n[1], n[2], g.origin[0], g.origin[1], g.origin[2], g.h);
  for (int z = 0; z < n[2]; ++z) {
    for (int y = 0; y < n[1]; ++y) {
      const std::uint8_t* row = votes.data() + static_cast<std::size_t>(y) * g.stride[1] +
                                static_cast<std::size_t>(z) * g.stride[2];
      int x = 0;
      while (x < n[0]) {
        while (x < n[0] && row[x] < 4) ++x;
        const int b = x;
        while (x < n[0] && row[x] >= 4) ++x;
        if (x > b) grid.set_span(y, z, b, x);
      }
    }
  }
  return grid;
}

}  // namespace

VoxelGrid voxelize(const TriangleMesh& input, const VoxelizeOptions& options, VoxelizeStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  check_mesh(input);
  TriangleMesh mesh;
  mesh.vertices = input.vertices;
  mesh.triangles = input.triangles;
  VoxelizeStats st;
  st.orientation_flips = repair_orientation(mesh);
  weld_vertices(mesh);
  st.orientation_flips += flip_inverted_pieces(mesh, options.winding_budget);
  const Lattice g = place_lattice(mesh, options);
  std::vector<std::uint8_t> votes(g.voxels, 0);
  std::vector<Crossing> crossings;
  for (int a = 0; a < 3; ++a) {
    collect_crossings(mesh, g, a, crossings);
    count_votes(crossings, g, a, votes);
  }
  settle_split_votes(mesh, g, options, votes, st);
  VoxelGrid grid = grid_from_votes(g, votes);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = st;
  return grid;
}

double auto_voxel_size(const MeshReport& report) {
  // A plate of thickness t has 2V/A = t; as many as 96^3 voxels fill the box of a thin,
  // elongated part, so its longest side gets more than 96.
  double extent[3], longest = 0;
  for (int a = 0; a < 3; ++a) {
    extent[a] = report.bbox_max[a] - report.bbox_min[a];
    longest = std::max(longest, extent[a]);
  }
  if (!(longest > 0) || !std::isfinite(longest)) return 0;
  double fill = 1;
  for (double e : extent) fill *= std::max(e, longest / 64) / longest;
  double h = longest / std::clamp(std::round(96 / std::cbrt(fill)), 96.0, 224.0);
  const double volume = std::fabs(report.signed_volume);
  if (report.surface_area > 0 && volume > 0) h = std::min(h, 2 * volume / report.surface_area / 11);
  h = std::max(h, longest / 256);
  double cells = 1;
  for (double e : extent) cells *= std::max(e, h) / h;
  const double max_cells = 160.0 * 160.0 * 160.0;
  if (cells > max_cells) h *= std::cbrt(cells / max_cells);
  return std::isfinite(h) && h > 0 ? h : 0;
}

}  // namespace csgfit
