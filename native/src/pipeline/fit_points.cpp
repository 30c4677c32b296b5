// The point-cloud stages in order (seed 004): the cloud checked and read as a target, a NURBS
// patch where the scan is a height field, first trees from the range detector, then the GP/ES
// islands (or the voxel hill climbing, to compare on the same points and budget).
#include "csgfit/pipeline/fit_points.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "csgfit/error.h"
#include "csgfit/pipeline/fit_range.h"
#include "csgfit/pipeline/fit_voxels.h"
#include "csgfit/refine/nurbs_fit.h"
#include "pipeline/height_levels.h"

namespace csgfit {

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kMinPoints = 20;

struct Cloud {
  std::vector<Vec3> points, normals;
};

Cloud merged_cloud(const std::vector<RangeScan>& scans) {
  Cloud c;
  for (const RangeScan& s : scans) {
    if (s.normals.size() != s.points.size())
      throw std::invalid_argument("fit_points: every scan needs one normal per point");
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      const Vec3& p = s.points[i];
      const Vec3& n = s.normals[i];
      if (!std::isfinite(p[0] + p[1] + p[2]))
        throw InputError("'" + s.source + "': point " + std::to_string(i + 1) + " is not finite");
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!std::isfinite(len)) continue;  // an outlier the reader could not give a normal
      if (!(len > 1e-12))
        throw InputError("'" + s.source + "': the normal of point " + std::to_string(i + 1) + " has zero length");
      c.points.push_back(p);
      c.normals.push_back({n[0] / len, n[1] / len, n[2] / len});
    }
  }
  if (c.points.size() < kMinPoints)
    throw InputError("too few points to fit a solid (" + std::to_string(c.points.size()) +
                     ", at least " + std::to_string(kMinPoints) + " needed)");
  return c;
}

// The spread of the cloud along its principal axes, largest first.
Vec3 principal_spread(const std::vector<Vec3>& points) {
  Vec3 mean{};
  for (const Vec3& p : points)
    for (int a = 0; a < 3; ++a) mean[a] += p[a] / static_cast<double>(points.size());
  Mat3 cov{};
  for (const Vec3& p : points)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) cov[a][b] += (p[a] - mean[a]) * (p[b] - mean[b]);
  Vec3 values;
  Mat3 vectors;
  symmetric_eigen3(cov, values, vectors);
  return values;
}

ScanKind scan_kind(const Cloud& c, const PointsFitOptions& o) {
  if (o.scan) return *o.scan;
  // A scanner above the part sees nothing that faces down; a scan all around sees the bottom.
  std::size_t down = 0;
  for (const Vec3& n : c.normals) down += n[2] < -0.3 ? 1 : 0;
  return static_cast<double>(down) < 0.01 * static_cast<double>(c.normals.size()) ? ScanKind::Top
                                                                                   : ScanKind::All;
}

void check_solid(const Cloud& c, ScanKind scan, double floor) {
  const Vec3 s = principal_spread(c.points);
  if (!(s[1] > 1e-12 * s[0]) || !(s[0] > 0)) throw InputError("all points lie on a line: no solid to fit");
  if (scan == ScanKind::All && !(s[2] > 1e-10 * s[0]))
    throw InputError("all points lie on a plane: a scan all around a solid cannot be flat");
  if (scan == ScanKind::Top) {
    double top = -std::numeric_limits<double>::infinity();
    for (const Vec3& p : c.points) top = std::max(top, p[2]);
    if (!(top > floor))
      throw InputError("every point of the scan from above lies at or below the floor (z = " +
                       std::to_string(floor) + "): no solid stands on it");
  }
}

// The seed-002 detector's tree on the same points, when it finds one: a first genome.
std::vector<Node3D> detected_trees(const std::vector<RangeScan>& scans, const PointsFitOptions& o,
                                   double seconds, const std::atomic<bool>* cancel) {
  RangeFitOptions r;
  r.time_limit = seconds;
  r.seed = o.seed;
  r.threads = o.threads;
  r.primitives = analytic_kinds(o.primitives);
  if (r.primitives.empty()) return {};
  try {
    return {fit_range(scans, r, nullptr, cancel).tree};
  } catch (const InputError&) {
    return {};  // nothing recognised: the islands start from random terminals
  }
}

// The level trees stand on the table of a scan from above, on the lowest point of one all
// around (a part resting on its bottom face; the fitness judges the trees of one that does not).
LevelOptions level_options(const PointTarget& t, const PointsFitOptions& o) {
  LevelOptions l;
  l.floor = t.scan == ScanKind::Top ? o.floor : bounds_of(t.points).lo[2];
  l.seconds = 0.1 * o.time_limit;
  l.primitives = o.primitives;
  l.threads = o.threads;
  l.seed = o.seed;
  return l;
}

// The voxels the points enclose, for the hill climbing, by parity along z: in each column the
// points facing down are where the part begins and those facing up where it ends (walls say
// nothing along z); a scan from above has only ends, so its columns start at the floor.
VoxelGrid enclosed_voxels(const PointTarget& t, int resolution) {
  Bounds3 box = bounds_of(t.points);
  if (t.scan == ScanKind::Top) box.lo[2] = std::min(box.lo[2], t.floor);
  double side = 0;
  for (int a = 0; a < 3; ++a) side = std::max(side, box.hi[a] - box.lo[a]);
  const double vs = side / resolution, margin = 2 * vs;
  int n[3];
  for (int a = 0; a < 3; ++a) n[a] = static_cast<int>(std::ceil((box.hi[a] - box.lo[a] + 2 * margin) / vs));
  VoxelGrid g(n[0], n[1], n[2], box.lo[0] - margin, box.lo[1] - margin, box.lo[2] - margin, vs);
  // Each point stands for a disc of the scan's spacing: it reaches the columns within it.
  const double reach = std::max(t.spacing, 0.5 * vs);
  std::vector<std::vector<std::pair<double, int>>> columns(static_cast<std::size_t>(n[0] * n[1]));
  for (std::size_t p = 0; p < t.points.size(); ++p) {
    const Vec3& q = t.points[p];
    const double nz = t.normals[p][2];
    if (std::fabs(nz) < 0.3) continue;
    const int i0 = std::max(0, static_cast<int>(std::floor((q[0] - reach - g.origin_x()) / vs)));
    const int i1 = std::min(n[0] - 1, static_cast<int>(std::floor((q[0] + reach - g.origin_x()) / vs)));
    const int j0 = std::max(0, static_cast<int>(std::floor((q[1] - reach - g.origin_y()) / vs)));
    const int j1 = std::min(n[1] - 1, static_cast<int>(std::floor((q[1] + reach - g.origin_y()) / vs)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if (std::hypot(g.center_x(i) - q[0], g.center_y(j) - q[1]) <= reach)
          columns[static_cast<std::size_t>(i + n[0] * j)].push_back({q[2], nz > 0 ? 1 : -1});
  }
  for (int j = 0; j < n[1]; ++j)
    for (int i = 0; i < n[0]; ++i) {
      auto& c = columns[static_cast<std::size_t>(i + n[0] * j)];
      if (c.empty()) continue;
      std::sort(c.begin(), c.end());
      double start = t.scan == ScanKind::Top ? t.floor : std::numeric_limits<double>::quiet_NaN();
      double end = start;
      for (const auto& [z, up] : c) {
        if (up < 0 && t.scan == ScanKind::All) {
          if (!std::isnan(end) && z > end + 2 * reach) start = z;  // a new solid above a gap
          else if (std::isnan(start)) start = z;
        } else if (!std::isnan(start)) {
          end = z;
          for (int k = 0; k < n[2]; ++k)
            if (g.center_z(k) >= start && g.center_z(k) <= end) g.set(i, j, k);
        }
      }
    }
  return g;
}

Node3D hill_climb(const PointTarget& t, const PointsFitOptions& o, double seconds,
                  const ProgressCallback& progress, const std::atomic<bool>* cancel, FitStats& stats) {
  FitOptions3D v;
  v.time_limit = seconds;
  v.seed = o.seed;
  v.threads = o.threads;
  v.primitives = analytic_kinds(o.primitives);
  if (v.primitives.empty()) v.primitives = PrimitiveSet3D::parse("box");
  FitResult3D r = fit_voxels(enclosed_voxels(t, 64), v, progress, cancel);
  stats = r.stats;
  return r.tree;
}

}  // namespace

PointsFitResult fit_points(const std::vector<RangeScan>& scans, const PointsFitOptions& o,
                           const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  if (!(o.time_limit > 0) || o.islands == 0)
    throw std::invalid_argument("fit_points: the time limit and the island count must be positive");
  const auto t0 = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  Cloud cloud = merged_cloud(scans);
  PointsFitResult out;
  out.scan = scan_kind(cloud, o);
  check_solid(cloud, out.scan, o.floor);
  const PointTarget target = make_point_target(cloud.points, cloud.normals, out.scan, o.floor);
  out.points = target.points.size();
  out.diagonal = target.diagonal;

  std::optional<Primitive3D> patch;
  if (out.scan == ScanKind::Top && o.primitives.has(PrimitiveKind3D::Nurbs)) {
    const PatchFit f = fit_height_patch(target.points, o.floor);
    patch = f.terminal;
    out.patch_rms = f.rms;
  }
  GpParams gp;
  gp.islands = o.islands;
  gp.seed = o.seed;
  gp.threads = o.threads;
  gp.primitives = o.primitives;
  gp.max_generations = o.max_generations;
  if (o.search == PointSearch::Hill) {
    out.tree = hill_climb(target, o, std::max(0.1, o.time_limit - elapsed()), progress, cancel, out.stats);
    out.first_tree = "voxels";
  } else {
    const std::vector<Node3D> detected = detected_trees(scans, o, 0.15 * o.time_limit, cancel);
    std::vector<Node3D> first = level_trees(target, detected, level_options(target, o), cancel);
    out.first_tree = first.empty() ? (detected.empty() ? "random" : "detected")
                                   : (detected.empty() ? "levels" : "levels and detected");
    first.insert(first.end(), detected.begin(), detected.end());
    gp.time_limit = std::max(0.1, o.time_limit - elapsed());
    const GpResult r = run_gp(target, gp, first, patch ? &*patch : nullptr, progress, cancel);
    out.tree = r.tree;
    out.generations = r.generations;
    out.stats.evaluations = r.evaluations;
    out.stats.stop_reason = r.stop;
  }
  out.islands = o.search == PointSearch::Gp ? o.islands : 0;
  out.terms = point_fitness(out.tree, target, gp.weights);
  out.stats.primitives = out.tree.primitive_count();
  out.stats.score = out.terms.fitness;
  out.stats.seconds = elapsed();
  return out;
}

std::string fitness_report(const PointsFitResult& r) {
  const FitnessTerms& f = r.terms;
  char line[400];
  std::string out;
  std::snprintf(line, sizeof line, "scan: %s, %zu points; search: %s", r.scan == ScanKind::Top ? "top" : "all",
                r.points, r.islands ? "gp" : "hill");
  out += line;
  if (r.islands) {
    std::snprintf(line, sizeof line, " on %zu islands, %zu generations, from %s", r.islands, r.generations,
                  r.first_tree.c_str());
    out += line;
  }
  std::snprintf(line, sizeof line, "\nfitness %.5f = distance %.5f + normals %.5f + curvature %.5f - nodes %zu\n",
                f.fitness, f.distance, f.normals, f.curvature, f.nodes);
  out += line;
  std::snprintf(line, sizeof line, "mean distance %.4g (%.3f %% of the diagonal); floor term %.4f", f.mean_distance,
                100 * f.mean_distance / r.diagonal, f.floor);
  out += line;
  if (r.patch_rms >= 0) {
    std::snprintf(line, sizeof line, "; NURBS patch rms %.4g", r.patch_rms);
    out += line;
  }
  return out + "\n";
}

}  // namespace csgfit
