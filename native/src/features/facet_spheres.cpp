// Balls read off a tessellation. A ball's normal lines all meet at its centre, so the line
// complex that finds other surfaces of revolution cannot choose its axis (every line through
// the centre would do), and a ball cut by bores has facets no ring of vertices explains. Its
// vertices simply lie on one sphere: fitted algebraically, then grown facet by facet.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "csgfit/features/mesh_surfaces.h"
#include "mesh_facets.h"
#include "model/linalg.h"

namespace csgfit {

// A ball must span this many degrees of normals: less, and a gentle curve of any kind fits.
constexpr double kBallSpan = 40;
// Its first fit takes rings of facets about the seed until they span half that (a fine or
// a cut ball's facets are small triangles), at most this many rings or facets.
constexpr int kBallRings = 12;
constexpr std::size_t kBallFacets = 400;
// Any two coaxial circles lie on a sphere, so one band of a cylinder or a cone (a washer's
// wall) fits one too; its facet normals all make one angle with the axis, so their scatter is
// flat along it. A ball's normals spread both ways: on a 40 degree cap the thinnest direction
// holds about a hundredth of the widest; a band, none but rounding.
constexpr double kBandFlatness = 1e-3;
// A tessellated ball's facets are chords of it reaching at most this many degrees from their
// middle to their corners (OpenSCAD's coarsest $fn = 12 ball: about 21); a flat face whose
// plane lies deeper in the ball is a face of its own.
constexpr double kChordDegrees = 25;
// Refits without the corners inside the ball (those of cut facets): they settle in two or three.
constexpr int kTrimRounds = 5;

namespace {

using namespace linalg;

Vec3 vertex(const TriangleMesh& m, int v) { return {m.vertices[v][0], m.vertices[v][1], m.vertices[v][2]}; }

// |p|^2 + D . p + G = 0 by least squares over `points`; false when degenerate.
bool fit_sphere(const std::vector<Vec3>& points, Vec3& centre, double& radius) {
  if (points.size() < 6) return false;
  Eigen::MatrixXd a(points.size(), 4);
  Eigen::VectorXd b(points.size());
  for (std::size_t r = 0; r < points.size(); ++r) {
    const Vec3& p = points[r];
    a.row(static_cast<Eigen::Index>(r)) << p[0], p[1], p[2], 1;
    b(static_cast<Eigen::Index>(r)) = -squared(p);
  }
  const Eigen::Vector4d x = a.colPivHouseholderQr().solve(b);
  centre = {-x(0) / 2, -x(1) / 2, -x(2) / 2};
  const double r2 = squared(centre) - x(3);
  if (!(r2 > 0) || !std::isfinite(r2)) return false;
  radius = std::sqrt(r2);
  return true;
}

// The sphere through the facets' corners. A facet cut by another surface (a bore) has corners
// on its own plane, inside the ball by up to the facet's sagitta: fitted with all, then again
// without the corners that lie inside, until the corners kept no longer change.
bool fit_sphere(const FacetMesh& fm, const std::vector<int>& facets, double tol, Vec3& centre, double& radius) {
  std::vector<Vec3> all;
  for (int v : facet_vertices(fm, facets)) all.push_back(vertex(fm.mesh, v));
  if (!fit_sphere(all, centre, radius)) return false;
  std::size_t kept = all.size();
  for (int round = 0; round < kTrimRounds; ++round) {
    std::vector<Vec3> on;
    for (const Vec3& p : all)
      if (norm(sub(p, centre)) >= radius - tol) on.push_back(p);
    if (on.size() == kept) break;
    kept = on.size();
    if (!fit_sphere(on, centre, radius)) return false;
  }
  return true;
}

// On the ball: no corner outside it, the facet's plane a chord of it (a facet of the ball's
// tessellation, or a piece of one that another surface cut), facing out from its centre.
bool on_sphere(const FacetMesh& fm, int f, const Vec3& centre, double radius, double tol) {
  const Facet& facet = fm.facets[f];
  for (int v : facet.vertices)
    if (norm(sub(vertex(fm.mesh, v), centre)) > radius + tol) return false;
  const double chord = std::abs(dot(facet.normal, sub(vertex(fm.mesh, facet.vertices.front()), centre)));
  if (chord < radius * std::cos(kChordDegrees * M_PI / 180) - tol) return false;
  Vec3 c{0, 0, 0};
  for (int v : facet.vertices) c = add(c, vertex(fm.mesh, v));
  c = scale(c, 1.0 / static_cast<double>(facet.vertices.size()));
  return std::abs(dot(facet.normal, normalized(sub(c, centre)))) > std::cos(kBallSpan * M_PI / 180);
}

double normal_span(const FacetMesh& fm, const std::vector<int>& facets) {
  double widest = 0;
  for (int f : facets) widest = std::max(widest, std::acos(std::clamp(dot(fm.facets[f].normal, fm.facets[facets.front()].normal), -1.0, 1.0)));
  return widest * 180 / M_PI;
}

// True when the facets' normals all make one angle with some axis: a band of a revolution.
bool one_band(const FacetMesh& fm, const std::vector<int>& facets) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int f : facets) mean += Eigen::Vector3d(fm.facets[f].normal[0], fm.facets[f].normal[1], fm.facets[f].normal[2]);
  mean /= static_cast<double>(facets.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int f : facets) {
    const Eigen::Vector3d d = Eigen::Vector3d(fm.facets[f].normal[0], fm.facets[f].normal[1], fm.facets[f].normal[2]) - mean;
    scatter += d * d.transpose();
  }
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  return ev(0) <= kBandFlatness * ev(2);
}

}  // namespace

bool grow_sphere(const FacetMesh& fm, const std::vector<char>& in_group, int seed,
                 const std::vector<char>& used, double tolerance, MeshSurface& ball) {
  std::vector<int> near{seed};
  for (int rings = 1; rings <= kBallRings && near.size() < kBallFacets && normal_span(fm, near) < kBallSpan / 2; ++rings)
    near = neighbourhood(fm, in_group, used, seed, rings, kBallFacets);
  Vec3 centre;
  double radius = 0;
  const double tol = 2 * tolerance;
  if (near.size() < 4 || normal_span(fm, near) < kBallSpan / 2 || !fit_sphere(fm, near, tol, centre, radius)) return false;
  for (int f : near)
    if (!on_sphere(fm, f, centre, radius, tol)) return false;
  const std::vector<int> members =
      grow_region(fm, in_group, used, seed, [&](int g) { return on_sphere(fm, g, centre, radius, tol); });
  if (normal_span(fm, members) < kBallSpan || one_band(fm, members)) return false;
  ball = MeshSurface{};
  ball.shape.kind = SurfaceKind::Sphere;
  ball.shape.point = centre;
  ball.shape.radius = radius;
  for (int f : members) {
    ball.triangles.insert(ball.triangles.end(), fm.facets[f].triangles.begin(), fm.facets[f].triangles.end());
    ball.area += fm.facets[f].area;
  }
  return true;
}

}  // namespace csgfit
