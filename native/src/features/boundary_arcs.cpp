#include "csgfit/features/boundary_curves.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>

#include "features/contour_ransac.h"
#include "model/random.h"

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSigma = 1.0;  // the blur, pixels
constexpr int kPad = 4;         // the blur reaches three pixels past the shape

// The mask as 0 / 1 floats on a canvas padded by kPad background pixels, blurred separably.
struct Blurred {
  int w = 0, h = 0;  // padded size
  std::vector<double> v;
  double at(int c, int r) const { return v[static_cast<std::size_t>(r) * w + c]; }
};

Blurred blurred(const Bitmap& mask) {
  Blurred b;
  b.w = mask.width() + 2 * kPad, b.h = mask.height() + 2 * kPad;
  std::vector<double> in(static_cast<std::size_t>(b.w) * b.h, 0.0), tmp(in.size(), 0.0);
  for (int r = 0; r < mask.height(); ++r)
    for (int c = 0; c < mask.width(); ++c)
      if (mask.get(c, r)) in[static_cast<std::size_t>(r + kPad) * b.w + c + kPad] = 1;
  double kernel[2 * 3 + 1], sum = 0;
  for (int d = -3; d <= 3; ++d) sum += kernel[d + 3] = std::exp(-d * d / (2 * kSigma * kSigma));
  for (double& k : kernel) k /= sum;
  auto pass = [&](const std::vector<double>& src, std::vector<double>& dst, int dc, int dr) {
    for (int r = 0; r < b.h; ++r)
      for (int c = 0; c < b.w; ++c) {
        double acc = 0;
        for (int d = -3; d <= 3; ++d) {
          const int cc = c + d * dc, rr = r + d * dr;
          if (cc >= 0 && rr >= 0 && cc < b.w && rr < b.h)
            acc += kernel[d + 3] * src[static_cast<std::size_t>(rr) * b.w + cc];
        }
        dst[static_cast<std::size_t>(r) * b.w + c] = acc;
      }
  };
  pass(in, tmp, 1, 0);
  b.v.assign(in.size(), 0.0);
  pass(tmp, b.v, 0, 1);
  return b;
}

// Central-difference gradient in the solver frame (x right, y up), clamped at the pad's edge.
void gradient(const Blurred& b, int c, int r, double& gx, double& gy) {
  const int cl = std::max(c - 1, 0), cr = std::min(c + 1, b.w - 1);
  const int ru = std::max(r - 1, 0), rd = std::min(r + 1, b.h - 1);
  gx = (b.at(cr, r) - b.at(cl, r)) / (cr - cl);
  gy = (b.at(c, ru) - b.at(c, rd)) / (rd - ru);
}

struct Circle {
  double cx = 0, cy = 0, r = 0;
};

bool circumcircle(const ContourPoint& a, const ContourPoint& b, const ContourPoint& c, Circle& out) {
  const double d = 2 * (a.x * (b.y - c.y) + b.x * (c.y - a.y) + c.x * (a.y - b.y));
  if (std::fabs(d) < 1e-9) return false;
  const double a2 = a.x * a.x + a.y * a.y, b2 = b.x * b.x + b.y * b.y, c2 = c.x * c.x + c.y * c.y;
  out.cx = (a2 * (b.y - c.y) + b2 * (c.y - a.y) + c2 * (a.y - b.y)) / d;
  out.cy = (a2 * (c.x - b.x) + b2 * (a.x - c.x) + c2 * (b.x - a.x)) / d;
  out.r = std::hypot(a.x - out.cx, a.y - out.cy);
  return true;
}

// +1 when `p`'s normal points away from the centre (the shape is inside: a disc), -1 when it
// points at it (a hole), 0 when it is more than 25 degrees off either.
int facing(const ContourPoint& p, const Circle& k) {
  const double dx = p.x - k.cx, dy = p.y - k.cy, d = std::hypot(dx, dy);
  if (d < 1e-9) return 0;
  const double cosine = (dx * p.nx + dy * p.ny) / d;
  const double limit = std::cos(25 * kPi / 180);
  return cosine >= limit ? 1 : cosine <= -limit ? -1 : 0;
}

bool on_circle(const ContourPoint& p, const Circle& k, int sign, double tolerance) {
  return std::fabs(std::hypot(p.x - k.cx, p.y - k.cy) - k.r) <= tolerance && facing(p, k) == sign;
}

// Geometric least squares (Gauss-Newton on the radial distances), from `k`.
Circle refined(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& on, Circle k) {
  for (int it = 0; it < 6; ++it) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jte = Eigen::Vector3d::Zero();
    for (std::size_t i : on) {
      const double dx = pts[i].x - k.cx, dy = pts[i].y - k.cy, d = std::hypot(dx, dy);
      if (d < 1e-9) continue;
      const Eigen::Vector3d j(-dx / d, -dy / d, -1);
      jtj += j * j.transpose();
      jte += j * (d - k.r);
    }
    const Eigen::Vector3d step = jtj.ldlt().solve(-jte);
    if (!step.allFinite()) break;
    k.cx += step[0], k.cy += step[1], k.r += step[2];
    if (step.norm() < 1e-6) break;
  }
  return k;
}

// The fraction of the circle's length that the longest arc of points of `on` spans (bins of
// 1.5 px of arc).
double coverage(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& on,
                const Circle& k) {
  std::vector<double> angles;
  for (std::size_t i : on) angles.push_back(std::atan2(pts[i].y - k.cy, pts[i].x - k.cx));
  return contour_ransac::longest_run(angles, 2 * kPi * k.r / 1.5);
}

using Hypothesis = contour_ransac::SignedHypothesis<Circle>;

// The best-voted circle through three active points near one another (within a window drawn
// from 8 to 64 px, so that small holes and large discs are both sampled), votes counted on a
// stride of the active points.
Hypothesis best_hypothesis(const std::vector<ContourPoint>& pts, const std::vector<std::size_t>& active,
                           double max_r, rnd::Rng& rng) {
  Hypothesis best;
  const std::size_t stride = contour_ransac::vote_stride(active);
  std::vector<std::size_t> near;
  for (int trial = 0; trial < 400; ++trial) {
    const ContourPoint& a = contour_ransac::draw_neighbourhood(pts, active, 8.0, rng, near);
    if (near.size() < 3) continue;
    for (int inner = 0; inner < 4; ++inner) {
      const ContourPoint& b = pts[near[rnd::pick(rng, near.size())]];
      const ContourPoint& c = pts[near[rnd::pick(rng, near.size())]];
      Circle k;
      if (!circumcircle(a, b, c, k) || k.r < 2.5 || k.r > max_r) continue;
      const int sign = facing(a, k);
      if (sign == 0 || facing(b, k) != sign || facing(c, k) != sign) continue;
      std::size_t votes = 0;
      for (std::size_t j = 0; j < active.size(); j += stride)
        votes += on_circle(pts[active[j]], k, sign, 0.5);
      if (votes > best.votes) best = {k, sign, votes};
    }
  }
  return best;
}

}  // namespace

std::vector<ContourPoint> subpixel_contour(const Bitmap& mask) {
  const Blurred b = blurred(mask);
  const int h = mask.height();
  std::vector<ContourPoint> out;
  auto cross = [&](int c0, int r0, int c1, int r1) {
    const double v0 = b.at(c0, r0), v1 = b.at(c1, r1);
    if ((v0 < 0.5) == (v1 < 0.5)) return;
    const double t = (0.5 - v0) / (v1 - v0);
    double g0x, g0y, g1x, g1y;
    gradient(b, c0, r0, g0x, g0y);
    gradient(b, c1, r1, g1x, g1y);
    const double gx = g0x + t * (g1x - g0x), gy = g0y + t * (g1y - g0y), g = std::hypot(gx, gy);
    if (g < 1e-9) return;
    // Padded (col, row) to the solver frame: the pixel centre (col - pad + 0.5, h - row + pad - 0.5).
    const double col = c0 + t * (c1 - c0), row = r0 + t * (r1 - r0);
    out.push_back({col - kPad + 0.5, h - (row - kPad) - 0.5, -gx / g, -gy / g});
  };
  for (int r = 0; r < b.h; ++r)
    for (int c = 0; c < b.w; ++c) {
      if (c + 1 < b.w) cross(c, r, c + 1, r);
      if (r + 1 < b.h) cross(c, r, c, r + 1);
    }
  return out;
}

std::vector<BoundaryArc> boundary_arcs(const Contour& contour, std::size_t limit) {
  const std::vector<ContourPoint>& pts = contour.points;
  const double max_r = contour.canvas;
  rnd::Rng rng(0x2d0a4c5);
  auto hypothesise = [&](const std::vector<std::size_t>& active) -> std::optional<Hypothesis> {
    Hypothesis h = best_hypothesis(pts, active, max_r, rng);
    return h.votes > 0 ? std::optional<Hypothesis>(h) : std::nullopt;
  };
  auto inliers = [&](Hypothesis& h, const std::vector<std::size_t>& active) {
    return contour_ransac::tightened_inliers(
        active, 3, [&](std::size_t i, double tolerance) { return on_circle(pts[i], h.curve, h.sign, tolerance); },
        [&](const std::vector<std::size_t>& on) { return h.curve = refined(pts, on, h.curve), true; });
  };
  auto read = [&](const Hypothesis& h, const std::vector<std::size_t>& on) -> std::optional<BoundaryArc> {
    const Circle& k = h.curve;
    double rms = 0;
    for (std::size_t i : on) rms += std::pow(std::hypot(pts[i].x - k.cx, pts[i].y - k.cy) - k.r, 2);
    rms = on.empty() ? 1e9 : std::sqrt(rms / static_cast<double>(on.size()));
    const double cover = coverage(pts, on, k);
    if (on.size() < 10 || cover < 0.25 || rms > 0.3 || k.r < 2.5 || k.r > max_r) return std::nullopt;
    // The blur moves the 0.5 level of a disc (or of a hole) towards its centre by sigma^2 / 2r.
    return BoundaryArc{k.cx, k.cy, k.r + kSigma * kSigma / (2 * k.r), h.sign < 0, cover, on.size()};
  };
  std::vector<BoundaryArc> arcs =
      contour_ransac::sequential<BoundaryArc>(pts.size(), limit, 12, hypothesise, inliers, read);
  std::stable_sort(arcs.begin(), arcs.end(),
                   [](const BoundaryArc& a, const BoundaryArc& b) { return a.support > b.support; });
  return arcs;
}

std::vector<BoundaryArc> boundary_arcs(const Bitmap& mask, std::size_t limit) {
  return boundary_arcs(contour_of(mask), limit);
}

Contour contour_of(const Bitmap& mask) {
  return {subpixel_contour(mask), static_cast<double>(std::max(mask.width(), mask.height()))};
}

}  // namespace csgfit
