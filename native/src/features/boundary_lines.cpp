#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>

#include "csgfit/features/boundary_curves.h"
#include "features/contour_ransac.h"
#include "model/random.h"

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Line {
  double nx = 0, ny = 0, offset = 0;
};

bool on_line(const ContourPoint& p, const Line& l, double tolerance) {
  return std::fabs(l.nx * p.x + l.ny * p.y - l.offset) <= tolerance &&
         l.nx * p.nx + l.ny * p.ny >= std::cos(20 * kPi / 180);
}

// Total least squares through the points of `on`, its normal turned the way theirs point.
Line refined(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& on, const Line& from) {
  double mx = 0, my = 0;
  for (std::size_t i : on) mx += pts[i].x, my += pts[i].y;
  mx /= static_cast<double>(on.size()), my /= static_cast<double>(on.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (std::size_t i : on) {
    const Eigen::Vector2d d(pts[i].x - mx, pts[i].y - my);
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  Eigen::Vector2d n = eig.eigenvectors().col(0);  // the smallest variance: across the line
  if (n.x() * from.nx + n.y() * from.ny < 0) n = -n;
  return {n.x(), n.y(), n.x() * mx + n.y() * my};
}

// The points of `on` in the longest run along the line with gaps of at most 2 px, and the run.
std::vector<std::size_t> longest_run(const std::vector<ContourPoint>& pts, std::vector<std::size_t> on,
                                     const Line& l, double& t0, double& t1) {
  auto along = [&](std::size_t i) { return -l.ny * pts[i].x + l.nx * pts[i].y; };
  std::sort(on.begin(), on.end(), [&](std::size_t a, std::size_t b) { return along(a) < along(b); });
  std::size_t best_begin = 0, best_end = 0, begin = 0;
  double best_length = -1;
  for (std::size_t k = 0; k < on.size(); ++k) {
    if (k > 0 && along(on[k]) - along(on[k - 1]) > 2) begin = k;
    const double length = along(on[k]) - along(on[begin]);
    if (length > best_length) best_length = length, best_begin = begin, best_end = k + 1;
  }
  if (best_end == 0) return {};
  t0 = along(on[best_begin]), t1 = along(on[best_end - 1]);
  return {on.begin() + static_cast<std::ptrdiff_t>(best_begin), on.begin() + static_cast<std::ptrdiff_t>(best_end)};
}

// The best-voted line through two active points at most 4 to 32 px apart whose normals agree
// with it, votes counted on a stride of the active points.
Line best_hypothesis(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& active,
                     rnd::Rng& rng, std::size_t& best_votes) {
  Line best;
  best_votes = 0;
  const std::size_t stride = contour_ransac::vote_stride(active);
  std::vector<std::size_t> near;
  for (int trial = 0; trial < 300; ++trial) {
    const ContourPoint& a = contour_ransac::draw_neighbourhood(pts, active, 4.0, rng, near);
    for (int inner = 0; inner < 4 && near.size() >= 2; ++inner) {
      const ContourPoint& b = pts[near[rnd::pick(rng, near.size())]];
      const double dx = b.x - a.x, dy = b.y - a.y, d = std::hypot(dx, dy);
      if (d < 2) continue;
      Line l{-dy / d, dx / d, 0};
      if (l.nx * a.nx + l.ny * a.ny < 0) l.nx = -l.nx, l.ny = -l.ny;
      l.offset = l.nx * a.x + l.ny * a.y;
      if (!on_line(a, l, 0.5) || !on_line(b, l, 0.5)) continue;
      std::size_t votes = 0;
      for (std::size_t j = 0; j < active.size(); j += stride) votes += on_line(pts[active[j]], l, 0.5);
      if (votes > best_votes) best = l, best_votes = votes;
    }
  }
  return best;
}

}  // namespace

std::vector<BoundaryLine> boundary_lines(const Contour& contour, std::size_t limit) {
  const std::vector<ContourPoint>& pts = contour.points;
  rnd::Rng rng(0x11e5);
  struct Hypothesis {
    Line line;
    double t0 = 0, t1 = 0;
  };
  auto hypothesise = [&](const std::vector<std::size_t>& active) -> std::optional<Hypothesis> {
    std::size_t votes = 0;
    const Line l = best_hypothesis(pts, active, rng, votes);
    return votes > 0 ? std::optional<Hypothesis>(Hypothesis{l}) : std::nullopt;
  };
  auto inliers = [&](Hypothesis& h, const std::vector<std::size_t>& active) {
    std::vector<std::size_t> on;
    for (double tolerance : {0.6, 0.4}) {
      on.clear();
      for (std::size_t i : active)
        if (on_line(pts[i], h.line, tolerance)) on.push_back(i);
      on = longest_run(pts, on, h.line, h.t0, h.t1);
      if (on.size() < 3) break;
      h.line = refined(pts, on, h.line);
    }
    return on;
  };
  auto read = [&](const Hypothesis& h, const std::vector<std::size_t>& on) -> std::optional<BoundaryLine> {
    const Line& l = h.line;
    double rms = 0;
    for (std::size_t i : on) rms += std::pow(l.nx * pts[i].x + l.ny * pts[i].y - l.offset, 2);
    rms = on.empty() ? 1e9 : std::sqrt(rms / static_cast<double>(on.size()));
    if (on.size() < 6 || h.t1 - h.t0 < 6 || rms > 0.3) return std::nullopt;
    return BoundaryLine{l.nx, l.ny, l.offset, h.t0, h.t1, on.size()};
  };
  std::vector<BoundaryLine> lines =
      contour_ransac::sequential<BoundaryLine>(pts.size(), limit, 6, hypothesise, inliers, read);
  std::stable_sort(lines.begin(), lines.end(), [](const BoundaryLine& a, const BoundaryLine& b) {
    return a.t1 - a.t0 > b.t1 - b.t0;
  });
  return lines;
}

std::vector<BoundaryLine> boundary_lines(const Bitmap& mask, std::size_t limit) {
  return boundary_lines(contour_of(mask), limit);
}

}  // namespace csgfit
