#include "csgfit/features/boundary_walls.h"

#include <algorithm>
#include <cmath>

#include "csgfit/features/features2d.h"

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

struct EdgeSample {
  double x = 0, y = 0;  // pixel centre, solver frame
  double angle = 0;     // outward normal, degrees in [0, 360)
};

double wrap(double a, double period) {
  a = std::fmod(a, period);
  return a < 0 ? a + period : a;
}

// The outward normal of each boundary pixel: minus the weighted mean offset of the shape's
// pixels within three pixels (a sigma of 1.5 smooths the staircase of a slanted edge).
std::vector<EdgeSample> edge_samples(const Bitmap& mask) {
  const int w = mask.width(), h = mask.height(), reach = 3;
  std::vector<EdgeSample> out;
  for (const auto& [c, r] : boundary_pixels(mask)) {
    double gx = 0, gy = 0;
    for (int dr = -reach; dr <= reach; ++dr)
      for (int dc = -reach; dc <= reach; ++dc) {
        const int cc = c + dc, rr = r + dr;
        if (cc < 0 || rr < 0 || cc >= w || rr >= h || !mask.get(cc, rr)) continue;
        const double weight = std::exp(-(dc * dc + dr * dr) / (2 * 1.5 * 1.5));
        gx += weight * dc, gy -= weight * dr;  // rows run down, y up
      }
    if (gx * gx + gy * gy < 1e-6) continue;  // a lone pixel or a one-pixel line: no direction
    out.push_back({c + 0.5, h - r - 0.5, wrap(std::atan2(-gy, -gx) / kDeg, 360)});
  }
  return out;
}

// Peaks of the histogram of normal angles modulo 90 (1-degree bins, smoothed over five), as bin
// centres, strongest first: refined() makes them exact.
std::vector<double> orientations(const std::vector<EdgeSample>& samples) {
  std::array<double, 90> bins{};
  for (const EdgeSample& s : samples) bins[static_cast<std::size_t>(wrap(s.angle, 90)) % 90] += 1;
  std::array<double, 90> smooth{};
  for (int i = 0; i < 90; ++i)
    for (int d = -2; d <= 2; ++d) smooth[static_cast<std::size_t>(i)] += bins[static_cast<std::size_t>((i + d + 90) % 90)];
  // A peak stands above the 5.6 % of the samples five bins hold when every angle is as common
  // (a disc).
  const double least = std::max(12.0, 0.08 * static_cast<double>(samples.size()));
  std::vector<std::pair<double, int>> peaks;
  for (int i = 0; i < 90; ++i) {
    const double v = smooth[static_cast<std::size_t>(i)];
    if (v >= least && v >= smooth[static_cast<std::size_t>((i + 89) % 90)] &&
        v > smooth[static_cast<std::size_t>((i + 1) % 90)])
      peaks.emplace_back(v, i);
  }
  std::sort(peaks.begin(), peaks.end(), std::greater<>());
  std::vector<double> out;
  for (const auto& peak : peaks) out.push_back(peak.second + 0.5);
  return out;
}

// The samples whose normal is within 12 degrees of `facing`, in runs along the normal where
// consecutive offsets are within 1.25 pixels (a ragged edge's pixels lie a pixel apart); each
// run of four or more is a wall.
struct Run {
  std::vector<const EdgeSample*> samples;
  double offset = 0;
};

std::vector<Run> runs_facing(const std::vector<EdgeSample>& samples, double facing) {
  const double nx = std::cos(facing * kDeg), ny = std::sin(facing * kDeg);
  // A boundary pixel's centre lies between 0 and max(|nx|, |ny|) inside the edge.
  const double inset = 0.5 * std::max(std::fabs(nx), std::fabs(ny));
  std::vector<std::pair<double, const EdgeSample*>> along;
  for (const EdgeSample& s : samples)
    if (std::fabs(wrap(s.angle - facing + 180, 360) - 180) <= 12)
      along.emplace_back(s.x * nx + s.y * ny + inset, &s);
  std::sort(along.begin(), along.end(),
            [](const auto& p, const auto& q) { return p.first < q.first; });
  std::vector<Run> runs;
  for (std::size_t a = 0, b = 0; a < along.size(); a = b) {
    Run run;
    double sum = 0;
    for (b = a; b < along.size() && (b == a || along[b].first - along[b - 1].first <= 1.25); ++b) {
      sum += along[b].first;
      run.samples.push_back(along[b].second);
    }
    run.offset = sum / static_cast<double>(b - a);
    if (run.samples.size() >= 4) runs.push_back(std::move(run));
  }
  return runs;
}

// The angle of the family near `angle` from the straight lines through its walls' pixels (total
// least squares): the gradient's normals are biased by the staircase of a slanted edge.
double refined(const std::vector<EdgeSample>& samples, double angle) {
  double sx = 0, sy = 0;
  for (int k = 0; k < 4; ++k)
    for (const Run& run : runs_facing(samples, angle + 90 * k)) {
      if (run.samples.size() < 8) continue;
      double mx = 0, my = 0;
      for (const EdgeSample* e : run.samples) mx += e->x, my += e->y;
      const double n = static_cast<double>(run.samples.size());
      mx /= n, my /= n;
      double xx = 0, xy = 0, yy = 0;
      for (const EdgeSample* e : run.samples) {
        const double dx = e->x - mx, dy = e->y - my;
        xx += dx * dx, xy += dx * dy, yy += dy * dy;
      }
      // The direction of least spread is the line's normal; doubled angles avoid the sign.
      const double normal = 0.5 * std::atan2(2 * xy, xx - yy) / kDeg + 90;
      sx += n * n * std::cos(4 * normal * kDeg), sy += n * n * std::sin(4 * normal * kDeg);
    }
  if (sx == 0 && sy == 0) return angle;
  return wrap(std::atan2(sy, sx) / kDeg / 4, 90);
}

std::vector<BoundaryWall> walls_facing(const std::vector<EdgeSample>& samples, double facing) {
  std::vector<BoundaryWall> walls;
  for (const Run& run : runs_facing(samples, facing)) walls.push_back({run.offset, run.samples.size()});
  std::stable_sort(walls.begin(), walls.end(),
                   [](const BoundaryWall& p, const BoundaryWall& q) { return p.support > q.support; });
  return walls;
}

}  // namespace

std::vector<WallFamily> boundary_walls(const Bitmap& mask, std::size_t max_families) {
  const std::vector<EdgeSample> samples = edge_samples(mask);
  std::vector<WallFamily> out;
  for (double coarse : orientations(samples)) {
    if (out.size() == max_families) break;
    WallFamily f;
    f.angle = refined(samples, refined(samples, coarse));
    // Neighbouring histogram peaks refine to one orientation.
    if (std::any_of(out.begin(), out.end(), [&](const WallFamily& o) {
          return std::fabs(wrap(o.angle - f.angle + 45, 90) - 45) < 3;
        }))
      continue;
    for (int k = 0; k < 4; ++k) f.walls[static_cast<std::size_t>(k)] = walls_facing(samples, f.angle + 90 * k);
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace csgfit
