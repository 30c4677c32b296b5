// Mesh -> tree: the fitting frame, the two voxel sizes (coarse search, fine polish) and the
// way back into the mesh's coordinates.
#include "csgfit/mesh_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/evaluator3d.h"
#include "csgfit/features3d.h"
#include "csgfit/local_opt3d.h"
#include "search/random.h"

namespace csgfit {

namespace {

using Clock = std::chrono::steady_clock;

Vec3 mul(const Mat3& m, const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
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

std::vector<Vec3> surface_samples(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed) {
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
  search::Rng rng(search::splitmix(seed ^ 0x5eed5a3b1e5ULL));
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double x = search::uniform(rng, 0, total);
    const std::size_t t = static_cast<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin());
    const auto& tri = mesh.triangles[std::min(t, mesh.triangles.size() - 1)];
    double u = search::uniform(rng, 0, 1), v = search::uniform(rng, 0, 1);
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
  }
  return out;
}

void rotate_tree(Node3D& tree, const Quaternion& q) {
  if (q.is_identity()) return;
  const Mat3 m = q.matrix();
  for (Primitive3D* p : leaves(tree)) {
    const Vec3 c = mul(m, Vec3{p->cx, p->cy, p->cz});
    p->cx = c[0];
    p->cy = c[1];
    p->cz = c[2];
    p->rotation = q * p->rotation;
    p->normalize();
  }
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
      const Vec3 c0{m[0][0], m[1][0], m[2][0]}, c1{m[0][1], m[1][1], m[2][1]},
          c2{m[0][2], m[1][2], m[2][2]};
      if (dot(cross(c0, c1), c2) < 0) continue;  // a reflection
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
    framed += aligned_area(facets, Vec3{best[0][a], best[1][a], best[2][a]}, cos_tol);
  }
  if (own >= 0.9 * framed || best_trace > 3 - 1e-6) return Quaternion{};
  Quaternion q = quaternion_from_matrix(best);
  q.normalize();
  return q;
}

MeshFitResult fit_mesh(const TriangleMesh& mesh, const FitOptions3D& options,
                       const MeshFitOptions& mesh_options, const ProgressCallback& progress,
                       const std::atomic<bool>* cancel) {
  return fit_mesh(mesh, analyze_mesh(mesh), options, mesh_options, progress, cancel);
}

MeshFitResult fit_mesh(const TriangleMesh& mesh, const MeshReport& report,
                       const FitOptions3D& options, const MeshFitOptions& mesh_options,
                       const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  if (!(options.time_limit > 0)) throw std::invalid_argument("the time budget must be positive");
  if (mesh_options.resolution < 0) throw std::invalid_argument("the resolution must be >= 0");
  MeshFitResult out;
  out.report = report;
  out.frame = mesh_options.align ? dominant_frame(mesh) : Quaternion{};

  // The mesh in the fitting frame: frame = R^T mesh.
  TriangleMesh local = mesh;
  MeshReport local_report = out.report;
  if (!out.frame.is_identity()) {
    const Mat3 m = out.frame.matrix();
    const Mat3 mt{{{m[0][0], m[1][0], m[2][0]}, {m[0][1], m[1][1], m[2][1]}, {m[0][2], m[1][2], m[2][2]}}};
    for (auto& v : local.vertices) {
      const Vec3 r = mul(mt, Vec3{v[0], v[1], v[2]});
      v = {r[0], r[1], r[2]};
    }
    for (int a = 0; a < 3; ++a) {
      local_report.bbox_min[a] = std::numeric_limits<double>::infinity();
      local_report.bbox_max[a] = -std::numeric_limits<double>::infinity();
    }
    for (const auto& v : local.vertices)
      for (int a = 0; a < 3; ++a) {
        local_report.bbox_min[a] = std::min(local_report.bbox_min[a], v[a]);
        local_report.bbox_max[a] = std::max(local_report.bbox_max[a], v[a]);
      }
  }

  double extent[3], longest = 0, box = 1;
  for (int a = 0; a < 3; ++a) {
    extent[a] = local_report.bbox_max[a] - local_report.bbox_min[a];
    longest = std::max(longest, extent[a]);
  }
  for (double e : extent) box *= std::max(e, longest / 64);
  const double h_fine = auto_voxel_size(local_report);
  double h_search = h_fine;
  if (mesh_options.resolution > 0) {
    h_search = longest / mesh_options.resolution;
  } else if (h_fine > 0) {
    // The search makes thousands of trees: half a million voxels, and no coarser than 64
    // along the longest side, keep each one cheap; the polish then works on the fine grid.
    h_search = std::max(h_fine, std::min(std::cbrt(box / 5e5), longest / 64));
  }
  VoxelizeOptions vopt;
  if (h_search > 0 && std::isfinite(h_search)) vopt.voxel_size = h_search;
  const VoxelGrid coarse = voxelize(local, vopt);
  if (coarse.empty() || coarse.count() == 0)
    throw InputError("no solid found in the mesh (no voxel centre is inside it)");
  out.search_voxel_size = coarse.voxel_size();

  const bool polish = mesh_options.polish_share > 0 && h_fine > 0 && h_fine < 0.8 * coarse.voxel_size() &&
                      mesh_options.resolution == 0;
  FitOptions3D search = options;
  // The refinement against surface samples needs its own share of the time, a fine polish more.
  const double share = std::clamp(polish ? mesh_options.polish_share : 0.5 * mesh_options.polish_share, 0.0, 0.9);
  search.time_limit = std::max(0.05 * options.time_limit, (1 - share) * options.time_limit - elapsed());
  out.fit = fit_voxels(coarse, search, progress, cancel);
  out.grid = coarse;
  const std::size_t search_evaluations = out.fit.stats.evaluations;
  const bool stopped = out.fit.stats.stop_reason == "cancelled";

  if (!stopped && elapsed() < 0.98 * options.time_limit) {
    // The last step (snapping) and the caller's writing need a moment after the deadline.
    const auto deadline = start + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(0.98 * options.time_limit));
    VoxelGrid fine;
    VoxelizeOptions fopt;
    if (polish) {
      fopt.voxel_size = h_fine;
      // As wide a margin as the coarse grid's: a face the search left anywhere in a coarse
      // voxel of margin must not count as beyond the fine grid (Mismatch::outside).
      fopt.margin = 1 + static_cast<int>(std::ceil(coarse.voxel_size() / h_fine));
      fine = voxelize(local, fopt);
    }
    const bool on_fine = polish && fine.count() > 0;
    const VoxelGrid& grid = on_fine ? fine : coarse;
    const double ratio = coarse.voxel_size() / grid.voxel_size();
    // The polish counts voxels on two staggered lattices: on one, the search leaves sheets
    // thinner than a voxel between its rows of centres at no cost (model 167: a disc 0.045
    // thick over the whole part, 7 % of its volume in the rendering and 0 voxels in the fit).
    // Not exactly half a voxel: the grid is the bounding box centred in whole voxels, so the
    // box's faces lie on voxel boundaries along its longest side (on all sides for a part
    // whose dimensions are whole voxels), and half a voxel would put the staggered centres on
    // those faces, where inside and outside are a tie. Ties went both ways and the polish
    // paid for them with whole layers (a 20 x 10 x 5 box at 48 voxels: IoU 0.961). At 0.6 the
    // staggered centres stay a tenth of a voxel off such faces, and no sheet thicker than 0.6
    // voxel hides between the two lattices' rows.
    VoxelizeOptions sopt = on_fine ? fopt : vopt;
    sopt.lattice_shift = 0.6;
    const VoxelGrid staggered = voxelize(local, sopt);
    const double lattice_voxels = static_cast<double>(grid.count() + staggered.count());
    Node3D tree = out.fit.tree;
    TreeEvaluator3D ev(grid, staggered, tree);
    // Sub-voxel accuracy first: least squares against points of the mesh's surface puts the
    // coarse search's faces where the surface is (the coarse voxels only knew them to half a
    // voxel), then the pattern search on the fine voxels, then the snaps that cost (almost)
    // nothing. The refinement may give up voxels: a tree fitted to voxel centres can leave a
    // face anywhere between two rows of centres, and one shift of the lattice by a quarter
    // voxel showed it (mount_with_hole: IoU 0.981 on the fit's own centres, 0.941 on shifted
    // ones). The samples see the surface exactly, the voxels only to half a voxel, so the
    // samples win unless the voxels object strongly: up to 1.5 % of the part's voxels in all
    // (rendered IoU 0.947 -> 0.975 on that model). The snaps keep to a twentieth of that.
    const double snap_slack = std::max(8.0, 5e-4 * lattice_voxels);
    SurfaceFitOptions3D sf;
    sf.voxel_slack = 30 * snap_slack;
    sf.deadline = deadline;
    const auto samples = surface_samples(local, 30000, options.seed);
    refine_to_surface(ev, samples, sf);
    // No prune here: the search pruned at its k already, and a prune rebuilds the fine
    // evaluator once per primitive removed (seconds past the budget on big trees). On the
    // search's own grid too: the staggered lattice shows what the search could not see.
    LocalOptOptions3D lo;
    lo.max_sweeps = 12;
    lo.initial_step = std::max(1.0, 0.5 * ratio);
    lo.min_step = 0.25;
    lo.deadline = deadline;
    optimize_leaves(ev, lo);
    snap_to_design_values(ev, snap_slack);
    // Last, the faces onto the input's own planes: exact dimensions, and faces that several
    // primitives share become one plane. Within a third of a voxel: the voxels cannot tell.
    const double h = grid.voxel_size();
    snap_to_planes(ev, axis_planes(local, 0.01 * h, 4 * h * h), h / 3, snap_slack);
    FitStats& s = out.fit.stats;
    // Both lattices' counts: the IoU of the two samplings pooled, and k doubled to match.
    set_mismatch_stats(s, ev.mismatch(), grid.count() + staggered.count(), tree.primitive_count(),
                       2 * s.k * ratio * ratio * ratio);
    s.evaluations = search_evaluations + ev.evaluations();
    out.fit.tree = std::move(tree);
    if (on_fine) out.grid = std::move(fine);
  }
  rotate_tree(out.fit.tree, out.frame);
  out.fit.stats.seconds = elapsed();
  return out;
}

}  // namespace csgfit
