// Mesh -> tree: the fitting frame, the two voxel sizes (coarse search, fine polish) and the
// way back into the mesh's coordinates.
#include "csgfit/pipeline/fit_mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/eval/evaluator3d.h"
#include "csgfit/features/mesh_features.h"
#include "csgfit/model/voxelize.h"
#include "optimize_last.h"
#include "csgfit/optimise/snap3d.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/refine/surface_fit3d.h"
#include "csgfit/seed/surface_candidates.h"
#include "mesh_construction.h"
#include "pipeline/fit_request.h"

namespace csgfit {

namespace {

using Clock = std::chrono::steady_clock;

// The construction from the mesh's faces may take this share of --time; it is deterministic
// and takes seconds at most, the rest is the search's when it is needed.
constexpr double kConstructShare = 0.5;
// A built tree that does not explain the mesh is the search's first tree only up to this many
// primitives: the search's pruning tries each leaf against the whole tree, and a tree of
// hundreds (a part whose faces were read wrongly) took three times --time on that alone.
constexpr std::size_t kMostBuiltPrimitivesToSearch = 64;

// The mesh in the fitting frame (frame = R^T mesh) and its bounding box there.
struct FramedMesh {
  TriangleMesh mesh;
  MeshReport report;
};

FramedMesh in_fitting_frame(const TriangleMesh& mesh, const MeshReport& report,
                            const Quaternion& frame) {
  FramedMesh out{mesh, report};
  if (frame.is_identity()) return out;
  const Mat3 m = frame.matrix();
  for (auto& v : out.mesh.vertices) {
    const Vec3 r{m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
                 m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
                 m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2]};
    v = {r[0], r[1], r[2]};
  }
  for (int a = 0; a < 3; ++a) {
    out.report.bbox_min[a] = std::numeric_limits<double>::infinity();
    out.report.bbox_max[a] = -std::numeric_limits<double>::infinity();
  }
  for (const auto& v : out.mesh.vertices)
    for (int a = 0; a < 3; ++a) {
      out.report.bbox_min[a] = std::min(out.report.bbox_min[a], v[a]);
      out.report.bbox_max[a] = std::max(out.report.bbox_max[a], v[a]);
    }
  return out;
}

// The voxel edges of the two grids: the coarse one the search runs on and the fine one of
// auto_voxel_size the polish runs on (0 when there is none: a given resolution or voxel size).
struct VoxelSizes {
  double search = 0, fine = 0;
};

VoxelSizes voxel_sizes(const MeshReport& framed, const MeshFitOptions& o) {
  double extent[3], longest = 0, box = 1;
  for (int a = 0; a < 3; ++a) {
    extent[a] = framed.bbox_max[a] - framed.bbox_min[a];
    longest = std::max(longest, extent[a]);
  }
  for (double e : extent) box *= std::max(e, longest / 64);
  VoxelSizes h;
  h.fine = auto_voxel_size(framed);
  h.search = h.fine;
  if (o.voxel_size > 0) {
    h.search = o.voxel_size;
  } else if (o.resolution > 0) {
    h.search = longest / o.resolution;
  } else if (h.fine > 0) {
    // The search makes thousands of trees: half a million voxels, and no coarser than 64
    // along the longest side, keep each one cheap; the polish then works on the fine grid.
    h.search = std::max(h.fine, std::min(std::cbrt(box / 5e5), longest / 64));
  }
  if (o.voxel_size > 0 || o.resolution > 0) h.fine = 0;
  return h;
}

// The mesh's surface read as primitives, in the fitting frame: the precedence graph's tree and
// its signed primitives. 20000 samples find every patch of a few percent of the surface.
SurfaceSeeds surface_seeds(const TriangleMesh& local, const VoxelGrid& coarse,
                           const FitOptions3D& o, const std::atomic<bool>* cancel) {
  std::vector<Vec3> normals;
  const std::vector<Vec3> points = surface_samples(local, 20000, o.seed, &normals);
  SurfaceSeeds seeds;
  if (points.size() < 100) return seeds;
  orient_outwards(normals, points, coarse);
  const SurfaceReading r =
      read_surface(points, normals, SurfaceDetectOptions{}, o.primitives, o.seed, cancel);
  if (r.graph.nodes.empty()) return seeds;
  seeds.trees.push_back(precedence_tree(r.graph));
  for (const SignedPrimitive& n : r.graph.nodes)
    (n.positive ? seeds.positives : seeds.negatives).push_back(n.primitive);
  return seeds;
}

// How far past the box [lo, hi] `positive` holds material that `tree` cuts away (at most
// `cap`), looked for on a lattice in each slab between a side of the box and the primitive's
// bound beyond it. Material the tree keeps out there is the reading's error, which the search
// shrinks away, and needs no room.
double cut_back_reach(const Primitive3D& positive, const Node3D& tree, const Vec3& lo,
                      const Vec3& hi, double cap) {
  constexpr int kAcross = 32, kDeep = 8;
  const Bounds3 b = positive.bounds();
  double reach = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const double face = side ? hi[axis] : lo[axis];
      const double depth = std::min(cap, side ? b.hi[axis] - hi[axis] : lo[axis] - b.lo[axis]);
      if (!(depth > reach)) continue;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      // The deepest layer with such material; the reach rounded up to the next layer.
      for (int d = kDeep; d >= 1 && depth * (d + 1) / kDeep > reach; --d)
        for (int i = 0; i < kAcross * kAcross; ++i) {
          Vec3 p;
          p[axis] = face + (side ? 1 : -1) * depth * d / kDeep;
          p[u] = b.lo[u] + (i % kAcross + 0.5) * (b.hi[u] - b.lo[u]) / kAcross;
          p[v] = b.lo[v] + (i / kAcross + 0.5) * (b.hi[v] - b.lo[v]) / kAcross;
          if (positive.contains(p[0], p[1], p[2]) && !contains(tree, p[0], p[1], p[2])) {
            reach = std::max(reach, depth * std::min(d + 1, kDeep) / kDeep);
            break;
          }
        }
    }
  return reach;
}

// Voxels of margin the grid needs beyond its own so that the surface's positive primitives fit
// in it where the surface's tree cuts them back: a surface's solid may reach past the mesh where
// a cut takes it back (a sphere whose poles three bores remove), and Mismatch::outside, which
// counts a difference's first box, would otherwise shrink it into the grid (sphere minus three
// cylinders: r 15 -> 14.6, IoU 0.90). Only there: a positive the reading let stick out (a
// cylinder read too long) grew the grid of 4 of 50 CAD meshes by 2-4 x, and their search got
// as many times fewer evaluations. At most a quarter of the grid's longest side.
int margin_for(const SurfaceSeeds& seeds, const VoxelGrid& grid) {
  if (seeds.trees.empty()) return 0;
  const double h = grid.voxel_size();
  const Vec3 lo{grid.origin_x(), grid.origin_y(), grid.origin_z()};
  const Vec3 hi{lo[0] + grid.nx() * h, lo[1] + grid.ny() * h, lo[2] + grid.nz() * h};
  const double cap = 0.25 * h * std::max({grid.nx(), grid.ny(), grid.nz()});
  double reach = 0;
  for (const Primitive3D& p : seeds.positives) {
    const Bounds3 b = p.bounds();
    bool past = false;
    for (int a = 0; a < 3; ++a) past = past || b.hi[a] > hi[a] || b.lo[a] < lo[a];
    if (past) reach = std::max(reach, cut_back_reach(p, seeds.trees.front(), lo, hi, cap));
  }
  if (!(reach > 0)) return 0;
  return static_cast<int>(std::ceil(std::min(reach, cap) / h)) + 1;
}

// The polish's grids: the fine grid of auto_voxel_size (or the search's own when there is
// none) and the same part on a lattice staggered by 0.6 voxel.
struct PolishGrids {
  VoxelGrid fine, staggered;
  bool on_fine = false;
  const VoxelGrid& grid(const VoxelGrid& coarse) const { return on_fine ? fine : coarse; }
};

PolishGrids polish_grids(const TriangleMesh& local, const VoxelGrid& coarse,
                         const VoxelizeOptions& coarse_options, double h_fine) {
  PolishGrids g;
  VoxelizeOptions fopt;
  if (h_fine > 0) {
    fopt.voxel_size = h_fine;
    // As wide a margin as the coarse grid's: a face the search left anywhere in a coarse
    // voxel of margin must not count as beyond the fine grid (Mismatch::outside).
    fopt.margin = 1 + static_cast<int>(std::ceil(coarse_options.margin * coarse.voxel_size() / h_fine));
    g.fine = voxelize(local, fopt);
  }
  g.on_fine = h_fine > 0 && g.fine.count() > 0;
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
  VoxelizeOptions sopt = g.on_fine ? fopt : coarse_options;
  sopt.lattice_shift = kStaggeredShift;
  g.staggered = voxelize(local, sopt);
  return g;
}

// After the search: least squares against the surface, the pattern search and the snaps on
// the fine grid (or the search's own), counting two staggered lattices. Updates out.fit.
void polish(MeshFitResult& out, const TriangleMesh& local, const VoxelGrid& coarse,
            const VoxelizeOptions& coarse_options, double h_fine, std::uint64_t seed,
            Clock::time_point deadline) {
  PolishGrids grids = polish_grids(local, coarse, coarse_options, h_fine);
  const bool on_fine = grids.on_fine;
  VoxelGrid& fine = grids.fine;
  const VoxelGrid& grid = grids.grid(coarse);
  const VoxelGrid& staggered = grids.staggered;
  const double ratio = coarse.voxel_size() / grid.voxel_size();
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
  const auto samples = surface_samples(local, 30000, seed);
  refine_to_surface(ev, samples, sf);
  // No prune here: the search pruned at its k already, and a prune rebuilds the fine
  // evaluator once per primitive removed (seconds past the budget on big trees). On the
  // search's own grid too: the staggered lattice shows what the search could not see.
  LocalOptOptions lo = LocalOptOptions::pattern(12, std::max(1.0, 0.5 * ratio), 0.25);
  lo.deadline = deadline;
  optimize_leaves(ev, lo);
  // The pattern search judges by voxels alone and leaves a face anywhere between the rows of
  // both lattices' centres; the samples put it back on the surface, now within the snaps'
  // small allowance, so that what the pattern search gained stays.
  SurfaceFitOptions3D settle = sf;
  settle.voxel_slack = snap_slack;
  refine_to_surface(ev, samples, settle);
  snap_to_design_values(ev, snap_slack);
  // Last, the faces onto the input's own planes: exact dimensions, and faces that several
  // primitives share become one plane. Within 0.6 voxel, the widest gap between the two
  // lattices' rows: anywhere inside it the voxels cannot tell, and a face left there is a
  // whole layer of voxels on a lattice that happens to have its rows in the gap.
  const double h = grid.voxel_size();
  snap_to_planes(ev, axis_planes(local, 0.01 * h, 4 * h * h), 0.6 * h, snap_slack);
  FitStats& s = out.fit.stats;
  // Both lattices' counts: the IoU of the two samplings pooled, and k doubled to match.
  const std::size_t search_evaluations = s.evaluations;
  set_mismatch_stats(s, ev.mismatch(), grid.count() + staggered.count(), tree.primitive_count(),
                     2 * s.k * ratio * ratio * ratio);
  s.evaluations = search_evaluations + ev.evaluations();
  out.fit.tree = std::move(tree);
  if (on_fine) out.grid = std::move(fine);
}

}  // namespace

Input3D Input3D::from_mesh(TriangleMesh mesh) {
  Input3D in;
  in.report = analyze_mesh(mesh);
  in.mesh = std::move(mesh);
  return in;
}

Input3D Input3D::from_voxels(VoxelGrid voxels) {
  Input3D in;
  in.mesh_input = false;
  in.voxels = std::move(voxels);
  return in;
}

std::string Input3D::warning() const { return mesh_input ? describe_mesh_problems(report) : ""; }

MeshFitResult fit_input3d(const Input3D& input, const FitOptions3D& options,
                          const MeshFitOptions& mesh_options, const ProgressCallback& progress,
                          const std::atomic<bool>* cancel) {
  if (input.is_mesh())
    return fit_mesh(input.mesh, input.report, options, mesh_options, progress, cancel);
  if (input.voxels.empty() || input.voxels.count() == 0)
    throw InputError("no solid found (no voxel is set)");
  MeshFitResult out;
  out.fit = fit_voxels(input.voxels, options, progress, cancel);
  out.grid = input.voxels;
  out.search_voxel_size = input.voxels.voxel_size();
  return out;
}

VoxelGrid input_voxels(const Input3D& input, const MeshFitResult& fit) {
  if (!input.is_mesh()) return input.voxels;
  if (fit.frame.is_identity()) return fit.grid;
  VoxelizeOptions v;
  v.voxel_size = fit.grid.voxel_size();
  return voxelize(input.mesh, v);
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
  check_search_options(options.time_limit, options.threads, options.k);
  if (mesh_options.resolution < 0) throw std::invalid_argument("the resolution must be >= 0");
  if (!(mesh_options.voxel_size >= 0) || !std::isfinite(mesh_options.voxel_size))
    throw std::invalid_argument("the voxel size must be >= 0");
  MeshFitResult out;
  out.report = report;
  out.frame = mesh_options.align ? dominant_frame(mesh) : Quaternion{};
  const FramedMesh local = in_fitting_frame(mesh, report, out.frame);
  const VoxelSizes h = voxel_sizes(local.report, mesh_options);
  VoxelizeOptions vopt;
  if (h.search > 0 && std::isfinite(h.search)) vopt.voxel_size = h.search;
  // Settling split ray votes by the winding number may take a fifth of --time (about 1e8
  // solid angles a second on two cores): a 1M-triangle soup at --time 1 spent seconds in it.
  vopt.winding_budget = std::min(vopt.winding_budget, 0.2 * 1e8 * options.time_limit);
  VoxelGrid coarse = voxelize(local.mesh, vopt);
  if (coarse.empty() || coarse.count() == 0)
    throw InputError("no solid found in the mesh (no voxel centre is inside it)");
  out.search_voxel_size = coarse.voxel_size();

  const bool polish_fine =
      mesh_options.polish_share > 0 && h.fine > 0 && h.fine < 0.8 * coarse.voxel_size();
  FitOptions3D search = options;
  search.optimize_tree = false;  // here, after the polish below
  if (mesh_options.construct) {
    ConstructedFit built = construct_mesh_fit(local.mesh, polish_fine ? h.fine : coarse.voxel_size(), vopt.margin,
                                              options, at_fraction(start, options.time_limit, kConstructShare));
    if (built.explains) {
      out.fit = std::move(built.fit);
      out.grid = std::move(built.grid);
      const VoxelGrid& grid = out.grid;
      if (options.optimize_tree)
        optimize_last(out.fit.tree, out.fit.stats, options.seed,
                      [&](const Node3D& a, const Node3D& b) { return render(a, grid) == render(b, grid); });
      rotate_tree(out.fit.tree, out.frame);
      out.fit.stats.seconds = elapsed();
      return out;
    }
    // What the faces did not explain is the search's to finish, from the built tree.
    if (built.built && built.fit.tree.primitive_count() <= kMostBuiltPrimitivesToSearch)
      search.surface.trees.push_back(std::move(built.fit.tree));
  }
  if (mesh_options.surface_seeds) {
    SurfaceSeeds read = surface_seeds(local.mesh, coarse, options, cancel);
    read.trees.insert(read.trees.begin(), search.surface.trees.begin(), search.surface.trees.end());
    search.surface = std::move(read);
    if (const int extra = margin_for(search.surface, coarse); extra > 0) {
      vopt.margin += extra;
      coarse = voxelize(local.mesh, vopt);
    }
  }
  // The refinement against surface samples needs its own share of the time, a fine polish more.
  const double share = std::clamp(
      polish_fine ? mesh_options.polish_share : 0.5 * mesh_options.polish_share, 0.0, 0.9);
  search.time_limit =
      std::max(0.05 * options.time_limit, (1 - share) * options.time_limit - elapsed());
  out.fit = fit_voxels(coarse, search, progress, cancel);
  out.grid = coarse;
  const bool stopped = out.fit.stats.stop_reason == "cancelled";
  if (!stopped && elapsed() < 0.98 * options.time_limit) {
    // The last step (snapping) and the caller's writing need a moment after the deadline.
    const auto deadline = at_fraction(start, options.time_limit, 0.98);
    polish(out, local.mesh, coarse, vopt, polish_fine ? h.fine : 0, options.seed, deadline);
  }
  if (options.optimize_tree)  // in the grid's frame, where its raster is the fit's
    optimize_last(out.fit.tree, out.fit.stats, options.seed,
                  [&](const Node3D& a, const Node3D& b) { return render(a, coarse) == render(b, coarse); });
  rotate_tree(out.fit.tree, out.frame);
  out.fit.stats.seconds = elapsed();
  return out;
}

}  // namespace csgfit
