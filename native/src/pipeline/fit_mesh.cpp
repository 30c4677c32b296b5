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
#include "csgfit/optimise/snap3d.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/refine/surface_fit3d.h"

namespace csgfit {

namespace {

using Clock = std::chrono::steady_clock;

Vec3 mul(const Mat3& m, const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

}  // namespace

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
    LocalOptOptions lo;
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
