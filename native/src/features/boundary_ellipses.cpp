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

struct Ellipse {
  double cx = 0, cy = 0, rx = 0, ry = 0, c = 1, s = 0;  // c, s: cosine and sine of the rx axis

  // Sampson-like distance: the implicit value over its gradient, and the outward normal there.
  double distance(double x, double y, double& nx, double& ny) const {
    const double dx = x - cx, dy = y - cy, u = c * dx + s * dy, v = -s * dx + c * dy;
    const double f = u * u / (rx * rx) + v * v / (ry * ry) - 1;
    const double gu = 2 * u / (rx * rx), gv = 2 * v / (ry * ry), g = std::hypot(gu, gv);
    if (g < 1e-12) return 1e9;
    nx = (c * gu - s * gv) / g, ny = (s * gu + c * gv) / g;
    return f / g;
  }
  double parameter(double x, double y) const {
    const double dx = x - cx, dy = y - cy;
    return std::atan2((-s * dx + c * dy) / ry, (c * dx + s * dy) / rx);
  }
};

// The ellipse of the conic a x^2 + b xy + c y^2 + d x + e y + f = 0 in coordinates shifted by
// (ox, oy) and scaled by `scale`; nothing when the conic is no real ellipse.
std::optional<Ellipse> from_conic(const Eigen::Matrix<double, 6, 1>& q, double ox, double oy, double scale) {
  Eigen::Matrix2d m;
  m << q[0], q[1] / 2, q[1] / 2, q[2];
  if (m.determinant() <= 0) return std::nullopt;
  const Eigen::Vector2d centre = m.ldlt().solve(-0.5 * Eigen::Vector2d(q[3], q[4]));
  const double at_centre = q[5] + 0.5 * (q[3] * centre.x() + q[4] * centre.y());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(m);
  const double l0 = eig.eigenvalues()[0], l1 = eig.eigenvalues()[1];
  if (!(-at_centre / l0 > 0 && -at_centre / l1 > 0)) return std::nullopt;
  Ellipse e;
  e.cx = ox + centre.x() * scale, e.cy = oy + centre.y() * scale;
  // The smaller eigenvalue has the longer axis: that is rx.
  e.rx = std::sqrt(-at_centre / l0) * scale, e.ry = std::sqrt(-at_centre / l1) * scale;
  e.c = eig.eigenvectors()(0, 0), e.s = eig.eigenvectors()(1, 0);
  return e;
}

// The conic through (or, for more points, closest to) `idx`, in coordinates centred on their
// mean and scaled to unit spread.
std::optional<Ellipse> conic_through(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& idx) {
  double ox = 0, oy = 0;
  for (std::size_t i : idx) ox += pts[i].x, oy += pts[i].y;
  ox /= static_cast<double>(idx.size()), oy /= static_cast<double>(idx.size());
  double spread = 0;
  for (std::size_t i : idx) spread += std::hypot(pts[i].x - ox, pts[i].y - oy);
  spread = std::max(spread / static_cast<double>(idx.size()), 1e-6);
  // The smallest eigenvector of the scatter matrix: the exact conic through five points, the
  // algebraic least squares one through more.
  Eigen::Matrix<double, 6, 6> scatter = Eigen::Matrix<double, 6, 6>::Zero();
  for (std::size_t i : idx) {
    const double x = (pts[i].x - ox) / spread, y = (pts[i].y - oy) / spread;
    Eigen::Matrix<double, 6, 1> row;
    row << x * x, x * y, y * y, x, y, 1;
    scatter += row * row.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(scatter);
  return from_conic(eig.eigenvectors().col(0), ox, oy, spread);
}

// +1 when p's normal agrees with the ellipse's outward normal (a disc), -1 when opposed (a
// hole), 0 when it is off by more than 25 degrees or p is more than `tolerance` off the curve.
int vote(const ContourPoint& p, const Ellipse& e, double tolerance) {
  double nx = 0, ny = 0;
  if (std::fabs(e.distance(p.x, p.y, nx, ny)) > tolerance) return 0;
  const double cosine = nx * p.nx + ny * p.ny, limit = std::cos(25 * kPi / 180);
  return cosine >= limit ? 1 : cosine <= -limit ? -1 : 0;
}

bool plausible(const Ellipse& e, double max_r) {
  return e.ry >= 2.5 && e.rx <= max_r && e.rx > 1.04 * e.ry;
}

// The RMS radial residual of the algebraic (Kasa) circle through `on`: an arc that a circle
// follows as closely is a circle's, not an ellipse's.
double circle_rms(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& on) {
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (std::size_t i : on) {
    const Eigen::Vector3d row(pts[i].x, pts[i].y, 1);
    ata += row * row.transpose();
    atb += row * -(pts[i].x * pts[i].x + pts[i].y * pts[i].y);
  }
  const Eigen::Vector3d q = ata.ldlt().solve(atb);
  const double cx = -q[0] / 2, cy = -q[1] / 2, r2 = cx * cx + cy * cy - q[2];
  if (!(r2 > 0)) return 1e9;
  double sum = 0;
  for (std::size_t i : on) sum += std::pow(std::hypot(pts[i].x - cx, pts[i].y - cy) - std::sqrt(r2), 2);
  return std::sqrt(sum / static_cast<double>(on.size()));
}

using Hypothesis = contour_ransac::SignedHypothesis<Ellipse>;

Hypothesis best_hypothesis(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& active,
                           double max_r, rnd::Rng& rng) {
  Hypothesis best;
  const std::size_t stride = contour_ransac::vote_stride(active);
  std::vector<std::size_t> near, sample(5);
  for (int trial = 0; trial < 200; ++trial) {
    const ContourPoint& a = contour_ransac::draw_neighbourhood(pts, active, 12.0, rng, near);
    if (near.size() < 8) continue;
    for (int inner = 0; inner < 3; ++inner) {
      for (std::size_t& k : sample) k = near[rnd::pick(rng, near.size())];
      const auto e = conic_through(pts, sample);
      if (!e || !plausible(*e, max_r)) continue;
      const int sign = vote(a, *e, 0.5);
      if (sign == 0 || std::any_of(sample.begin(), sample.end(),
                                   [&](std::size_t k) { return vote(pts[k], *e, 0.5) != sign; }))
        continue;
      std::size_t votes = 0;
      for (std::size_t j = 0; j < active.size(); j += stride) votes += vote(pts[active[j]], *e, 0.5) == sign;
      if (votes > best.votes) best = {*e, sign, votes};
    }
  }
  return best;
}

bool on_arc(const ContourPoint& p, const BoundaryArc& a) {
  const double dx = p.x - a.cx, dy = p.y - a.cy, d = std::hypot(dx, dy);
  const double facing = d > 0 ? (dx * p.nx + dy * p.ny) / d * (a.hole ? -1 : 1) : 0;
  return std::fabs(d - a.r) < 0.5 && facing > std::cos(25 * kPi / 180);
}

bool on_segment(const ContourPoint& p, const BoundaryLine& l) {
  const double t = -l.ny * p.x + l.nx * p.y;
  return std::fabs(l.nx * p.x + l.ny * p.y - l.offset) < 0.5 && t > l.t0 - 1 && t < l.t1 + 1 &&
         l.nx * p.nx + l.ny * p.ny > std::cos(25 * kPi / 180);
}

// The fraction of the ellipse's points that an arc or segment explains which is not itself a
// piece of the ellipse (most of its points off it): a flat ellipse bridging a disc's arc and the
// straight edge it meets is all such points, a real ellipse's end read as a short arc is not.
template <typename Reading, typename On>
void mark_rival(const std::vector<ContourPoint>& pts, const std::vector<bool>& on_ellipse,
                const Reading& r, On on, std::vector<bool>& rival) {
  std::size_t own = 0, shared = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (on(pts[i], r)) ++own, shared += on_ellipse[i];
  if (own == 0 || static_cast<double>(shared) > 0.6 * static_cast<double>(own)) return;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (on_ellipse[i] && on(pts[i], r)) rival[i] = true;
}

double explained_by_rivals(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& on,
                           const std::vector<BoundaryArc>& arcs, const std::vector<BoundaryLine>& lines) {
  std::vector<bool> on_ellipse(pts.size(), false), rival(pts.size(), false);
  for (std::size_t i : on) on_ellipse[i] = true;
  for (const BoundaryArc& a : arcs) mark_rival(pts, on_ellipse, a, on_arc, rival);
  for (const BoundaryLine& l : lines) mark_rival(pts, on_ellipse, l, on_segment, rival);
  return static_cast<double>(std::count(rival.begin(), rival.end(), true)) / static_cast<double>(on.size());
}

}  // namespace

std::vector<BoundaryEllipse> boundary_ellipses(const Contour& contour, const std::vector<BoundaryArc>& arcs,
                                               const std::vector<BoundaryLine>& lines, std::size_t limit) {
  const std::vector<ContourPoint>& pts = contour.points;
  const double max_r = contour.canvas;
  rnd::Rng rng(0xe111);
  auto hypothesise = [&](const std::vector<std::size_t>& active) -> std::optional<Hypothesis> {
    Hypothesis h = best_hypothesis(pts, active, max_r, rng);
    return h.votes > 0 ? std::optional<Hypothesis>(h) : std::nullopt;
  };
  auto inliers = [&](Hypothesis& h, const std::vector<std::size_t>& active) {
    return contour_ransac::tightened_inliers(
        active, 6, [&](std::size_t i, double tolerance) { return vote(pts[i], h.curve, tolerance) == h.sign; },
        [&](const std::vector<std::size_t>& on) {
          const auto refit = conic_through(pts, on);
          if (!refit || !plausible(*refit, max_r)) return false;
          h.curve = *refit;
          return true;
        });
  };
  auto read = [&](const Hypothesis& h, const std::vector<std::size_t>& on) -> std::optional<BoundaryEllipse> {
    const Ellipse& e = h.curve;
    double rms = 0, nx = 0, ny = 0;
    std::vector<double> params;
    for (std::size_t i : on) {
      rms += std::pow(e.distance(pts[i].x, pts[i].y, nx, ny), 2);
      params.push_back(e.parameter(pts[i].x, pts[i].y));
    }
    rms = on.empty() ? 1e9 : std::sqrt(rms / static_cast<double>(on.size()));
    // Ramanujan's perimeter, for bins of about 1.5 px.
    const double q = std::pow((e.rx - e.ry) / (e.rx + e.ry), 2);
    const double perimeter = kPi * (e.rx + e.ry) * (1 + 3 * q / (10 + std::sqrt(4 - 3 * q)));
    const double cover = contour_ransac::longest_run(params, perimeter / 1.5);
    if (on.size() < 15 || cover < 0.25 || rms > 0.3 || !plausible(e, max_r)) return std::nullopt;
    if (circle_rms(pts, on) < rms + 0.05) return std::nullopt;
    // A flat ellipse can bridge an arc and the straight edge it meets; a real one's points are
    // mostly its own.
    if (explained_by_rivals(pts, on, arcs, lines) > 0.5) return std::nullopt;
    const double angle = std::fmod(std::atan2(e.s, e.c) * 180 / kPi + 360, 180);
    return BoundaryEllipse{e.cx, e.cy, e.rx, e.ry, angle, h.sign < 0, cover, on.size()};
  };
  std::vector<BoundaryEllipse> found =
      contour_ransac::sequential<BoundaryEllipse>(pts.size(), limit, 15, hypothesise, inliers, read);
  std::stable_sort(found.begin(), found.end(), [](const BoundaryEllipse& a, const BoundaryEllipse& b) {
    return a.support > b.support;
  });
  return found;
}


}  // namespace csgfit
