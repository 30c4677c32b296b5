// Surfaces of revolution read off a tessellation (turned parts, fillet rings, balls, cones).
// The normals of a surface of revolution all meet its axis, so the axis is the line the facets'
// normal lines meet best (Pottmann and Randrup's line-complex fit, a 6 x 6 eigenproblem); the
// facets' vertices, seen across the axis as (radius, height), then trace the profile, which is
// cut into straight pieces (cones, cylinders, flat rings) and circle arcs (tori, spheres).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>

#include "csgfit/features/mesh_surfaces.h"
#include "mesh_facets.h"
#include "model/linalg.h"
#include "patch_fit.h"

namespace csgfit {

namespace {

using namespace linalg;

// A facet's normal line meets the axis when it passes this share of the facet's distance from
// the axis (plus the file's tolerance): exact for the symmetric quads a revolve makes, a few
// percent off for a CAD exporter's strips of triangles.
constexpr double kMeetSlack = 0.05;
// A revolution's axis is first fitted to the facets up to kSeedRings folds from a seed, until
// kSeedFacets are in.
constexpr int kSeedRings = 6;
constexpr std::size_t kSeedFacets = 12;
// Of the first facets around a seed, this share must meet one axis for a revolution to grow.
constexpr double kSeedAgreement = 0.8;
// A swept surface's facets face this many directions about its axis (OpenSCAD's fewest
// fragments of a circle) and span this far about it (degrees).
constexpr std::size_t kSweptDirections = 5;
constexpr double kSweptDegrees = 20;
// A facet of a swept surface faces as the surface does at its centroid, within half the fold to
// its neighbours (a chord of the profile or of the turn) and this much more (degrees): the
// normals of a surface that only looks swept about an axis (two crossed cylinders seen about
// the axis across both) do not.
constexpr double kNormalSlack = 2;
// A profile arc's radius is at most this many times its chord: a dome of radius 100 over a
// chord of 20 is 5; past this it is a near-straight run with a kink, better read as lines.
constexpr double kMostArcRadiusPerChord = 50;
// Fewest profile points an arc is read from: three always lie on some circle.
constexpr std::size_t kArcPoints = 4;

struct Axis {
  Vec3 point{0, 0, 0}, direction{0, 0, 1};
  bool ok = false;
};

Vec3 centroid_of(const FacetMesh& fm, int f) {
  Vec3 c{0, 0, 0};
  for (int v : fm.facets[f].vertices)
    c = add(c, Vec3{fm.mesh.vertices[v][0], fm.mesh.vertices[v][1], fm.mesh.vertices[v][2]});
  return scale(c, 1.0 / static_cast<double>(fm.facets[f].vertices.size()));
}

// Normals all across one direction (a cylinder's, a flat ring's): the line complex is
// singular; the axis is that direction through the point nearest all normal lines.
Axis cylinder_axis(const FacetMesh& fm, const std::vector<int>& facets, const Eigen::Matrix3d& normals) {
  Axis out;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(normals);
  const Eigen::Vector3d d = eig.eigenvectors().col(0).normalized();
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int f : facets) {
    const Eigen::Vector3d n = view(fm.facets[f].normal);
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - n * n.transpose() - d * d.transpose();
    m += fm.facets[f].area * across;
    b += fm.facets[f].area * across * view(centroid_of(fm, f));
  }
  const Eigen::Vector3d p = m.completeOrthogonalDecomposition().solve(b);
  if (!p.allFinite() || !d.allFinite()) return out;
  out.direction = to_vec3(d);
  out.point = to_vec3(p);
  out.ok = true;
  return out;
}

// The line the facets' normal lines meet best: minimise sum w (a . (c x n) + abar . n)^2 with
// |a| = 1, abar eliminated through its normal equations (the Schur complement).
Axis fit_axis(const FacetMesh& fm, const std::vector<int>& facets) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), B = Eigen::Matrix3d::Zero(), C = Eigen::Matrix3d::Zero();
  for (int f : facets) {
    const Vec3 n = fm.facets[f].normal, moment = cross(centroid_of(fm, f), n);
    const Eigen::Vector3d l = view(n), lbar = view(moment);
    const double w = fm.facets[f].area;
    A += w * lbar * lbar.transpose();
    B += w * lbar * l.transpose();
    C += w * l * l.transpose();
  }
  Axis out;
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(C);
  if (!lu.isInvertible()) return out;
  const Eigen::Matrix3d schur = A - B * lu.inverse() * B.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (schur + schur.transpose()));
  const Eigen::Vector3d a = eig.eigenvectors().col(0).normalized();
  const Eigen::Vector3d abar = -lu.inverse() * B.transpose() * a;
  if (!a.allFinite() || !abar.allFinite()) return out;
  out.direction = to_vec3(a);
  out.point = to_vec3(a.cross(abar));  // the axis point nearest the origin
  out.ok = true;
  return out;
}

// The point nearest all the facets' normal lines (least squares): where they all meet for a
// ball, or for one ring of a cone.
Eigen::Vector3d nearest_to_normal_lines(const FacetMesh& fm, const std::vector<int>& facets) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int f : facets) {
    const Eigen::Vector3d n = view(fm.facets[f].normal);
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - n * n.transpose();
    m += fm.facets[f].area * across;
    b += fm.facets[f].area * across * view(centroid_of(fm, f));
  }
  return m.completeOrthogonalDecomposition().solve(b);
}

// When all normal lines pass through one point, every line through it meets them all and the
// line complex cannot choose; the axis a ring of facets turns about is then the direction of
// their normals' scatter unlike the other two (a cone's normals keep one angle to it).
Axis symmetry_axis(const FacetMesh& fm, const std::vector<int>& facets, const Eigen::Matrix3d& scatter) {
  Axis out;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  const Eigen::Vector3d v = eig.eigenvalues();
  int odd = 0;
  double apart = -1;
  for (int k = 0; k < 3; ++k) {
    const double others = 0.5 * (v.sum() - v(k));
    if (std::abs(v(k) - others) > apart) apart = std::abs(v(k) - others), odd = k;
  }
  const Eigen::Vector3d d = eig.eigenvectors().col(odd).normalized();
  const Eigen::Vector3d p = nearest_to_normal_lines(fm, facets);
  if (!d.allFinite() || !p.allFinite()) return out;
  out.direction = to_vec3(d);
  out.point = to_vec3(p);
  out.ok = true;
  return out;
}

double distance_to_axis(const Axis& axis, const Vec3& p) { return norm(reject(sub(p, axis.point), axis.direction)); }

// Whether the facet's normal line meets the axis (a flat ring across the axis always does).
bool meets(const FacetMesh& fm, int f, const Axis& axis, double tolerance) {
  const Vec3 c = centroid_of(fm, f), n = fm.facets[f].normal;
  const Vec3 across = cross(n, axis.direction);
  const double reach = kMeetSlack * distance_to_axis(axis, c) + 10 * tolerance;
  if (norm(across) < 1e-6) return true;
  return std::abs(dot(sub(c, axis.point), across)) / norm(across) <= reach;
}

Axis best_axis(const FacetMesh& fm, const std::vector<int>& facets, double tolerance);

// The facets of `group` reachable from `seed` whose normal lines meet one axis.
std::vector<int> grow_revolution(const FacetMesh& fm, const std::vector<char>& in_group, int seed,
                                 const std::vector<char>& used, double tolerance, Axis& axis) {
  // Enough of the surface around the seed to fix an axis: a 24 degree strip of a cone
  // leaves it loose, so rings are added until a dozen facets are in.
  const std::vector<int> near = neighbourhood(fm, in_group, used, seed, kSeedRings, kSeedFacets);
  if (near.size() < 4) return {};
  axis = best_axis(fm, near, tolerance);
  std::size_t agree = 0;
  for (int f : near) agree += axis.ok && meets(fm, f, axis, tolerance);
  if (!axis.ok || static_cast<double>(agree) < kSeedAgreement * static_cast<double>(near.size())) return {};
  std::vector<int> members = grow_region(fm, in_group, used, seed, [&](int g) { return meets(fm, g, axis, tolerance); });
  const Axis refit = best_axis(fm, members, tolerance);
  if (refit.ok) axis = refit;
  return members;
}

// The profile: distinct (radius, height) points of the facets' vertices, and per facet the
// edge of the profile it sweeps.
struct Profile {
  std::vector<std::array<double, 2>> points;
  std::map<std::pair<int, int>, std::vector<int>> edges;  // (lower, higher point) -> facets
};

int profile_point(Profile& p, double rho, double h, double merge) {
  for (std::size_t i = 0; i < p.points.size(); ++i)
    if (std::abs(p.points[i][0] - rho) <= merge && std::abs(p.points[i][1] - h) <= merge) return static_cast<int>(i);
  p.points.push_back({rho, h});
  return static_cast<int>(p.points.size()) - 1;
}

Profile trace_profile(const FacetMesh& fm, const std::vector<int>& facets, const Axis& axis, double tolerance) {
  Profile p;
  for (int f : facets) {
    std::vector<int> ids;
    for (int v : fm.facets[f].vertices) {
      const Vec3 d = sub(Vec3{fm.mesh.vertices[v][0], fm.mesh.vertices[v][1], fm.mesh.vertices[v][2]}, axis.point);
      const double h = dot(d, axis.direction);
      ids.push_back(profile_point(p, norm(reject(d, axis.direction)), h, 4 * tolerance));
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    if (ids.size() == 2) p.edges[{ids[0], ids[1]}].push_back(f);
  }
  return p;
}

// Of the axes the facets may turn about (the line complex's, the symmetry axis through the
// normals' common point, the cylinder's), the one their vertices trace the fewest profile
// points about: a ring of facets about its true axis gives two.
Axis best_axis(const FacetMesh& fm, const std::vector<int>& facets, double tolerance) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int f : facets) scatter += fm.facets[f].area * view(fm.facets[f].normal) * view(fm.facets[f].normal).transpose();
  Axis best;
  std::size_t fewest = 0;
  for (const Axis& a : {fit_axis(fm, facets), symmetry_axis(fm, facets, scatter), cylinder_axis(fm, facets, scatter)}) {
    if (!a.ok) continue;
    const std::size_t points = trace_profile(fm, facets, a, tolerance).points.size();
    if (!best.ok || points < fewest) best = a, fewest = points;
  }
  return best;
}

// Walks of the profile graph: each a run of points from an end (or around a loop).
std::vector<std::vector<int>> profile_walks(const Profile& p) {
  std::vector<std::vector<int>> next(p.points.size());
  for (const auto& e : p.edges) next[e.first.first].push_back(e.first.second), next[e.first.second].push_back(e.first.first);
  std::vector<char> done(p.points.size(), 0);
  std::vector<std::vector<int>> walks;
  for (int pass = 0; pass < 2; ++pass)  // ends first, then what is left (loops)
    for (std::size_t s = 0; s < p.points.size(); ++s) {
      if (done[s] || next[s].empty() || next[s].size() > 2 || (pass == 0 && next[s].size() != 1)) continue;
      std::vector<int> walk{static_cast<int>(s)};
      done[s] = 1;
      for (bool moved = true; moved;) {
        moved = false;
        for (int g : next[walk.back()])
          if (!done[g] && next[g].size() <= 2) {
            walk.push_back(g), done[g] = 1, moved = true;
            break;
          }
      }
      if (pass == 1 && walk.size() > 2 && std::find(next[walk.back()].begin(), next[walk.back()].end(), walk.front()) != next[walk.back()].end())
        walk.push_back(walk.front());  // close the loop
      if (walk.size() >= 2) walks.push_back(std::move(walk));
    }
  return walks;
}

struct Piece {
  bool arc = false;
  double a0 = 0, a1 = 0, b0 = 0, b1 = 0;  // line: its end points (rho, h)
  double rho = 0, h = 0, radius = 0;       // arc: its circle
};

bool line_fits(const Profile& p, const std::vector<int>& w, std::size_t i, std::size_t j, double tol, Piece& piece) {
  const auto& s = p.points[w[i]];
  const auto& e = p.points[w[j]];
  const double dx = e[0] - s[0], dy = e[1] - s[1], len = std::hypot(dx, dy);
  if (!(len > 0)) return false;
  for (std::size_t k = i + 1; k < j; ++k) {
    const auto& q = p.points[w[k]];
    if (std::abs((q[0] - s[0]) * dy - (q[1] - s[1]) * dx) / len > tol) return false;
  }
  piece = {false, s[0], e[0], s[1], e[1], 0, 0, 0};
  return true;
}

bool arc_fits(const Profile& p, const std::vector<int>& w, std::size_t i, std::size_t j, double tol, Piece& piece) {
  if (j - i + 1 < kArcPoints) return false;
  std::vector<Vec3> pts;
  for (std::size_t k = i; k <= j; ++k) pts.push_back({p.points[w[k]][0], p.points[w[k]][1], 0});
  const AxisCircle c = fit_axis_circle(pts, pts.front(), Vec3{0, 0, 1});
  if (!c.ok || c.max_error > tol) return false;
  // Only a circle about the axis (a ball) or off it by more than its radius (a torus) is swept
  // by a primitive; a wider one through a few near-straight points is a line and a kink.
  if (std::abs(c.centre[0]) > 2 * tol && c.radius >= c.centre[0]) return false;
  // A nearly straight run bent by a kink fits a huge circle too (CAD model 039: a torus of radii
  // 14511 and 14510 in a part 10 wide, which no $fn polygon of it renders): lines, not an arc.
  const double chord = std::hypot(pts.back()[0] - pts.front()[0], pts.back()[1] - pts.front()[1]);
  if (c.radius > kMostArcRadiusPerChord * chord) return false;
  piece = {true, 0, 0, 0, 0, c.centre[0], c.centre[1], c.radius};
  return true;
}

// The facets of the profile edges from point k0 to k1 of the walk.
std::vector<int> swept_facets(const Profile& p, const std::vector<int>& w, std::size_t k0, std::size_t k1) {
  std::vector<int> out;
  for (std::size_t k = k0; k < k1; ++k) {
    const auto it = p.edges.find({std::min(w[k], w[k + 1]), std::max(w[k], w[k + 1])});
    if (it != p.edges.end()) out.insert(out.end(), it->second.begin(), it->second.end());
  }
  return out;
}

// The surface a profile piece sweeps about the axis; false when no primitive is swept so.
bool swept_surface(const Piece& piece, const Axis& axis, double tol, MeshSurface& s) {
  SurfacePatch& shape = s.shape;
  const Vec3 foot = axis.point, d = axis.direction;
  if (piece.arc) {
    shape.point = add(foot, scale(d, piece.h));
    shape.axis = d;
    shape.radius = piece.radius;
    if (std::abs(piece.rho) <= 2 * tol) {
      shape.kind = SurfaceKind::Sphere;
    } else if (piece.radius < piece.rho) {
      shape.kind = SurfaceKind::Torus;
      shape.radius = piece.rho;
      shape.minor_radius = piece.radius;
    } else {
      return false;  // a spindle torus: no primitive of ours
    }
    return true;
  }
  const double drho = piece.a1 - piece.a0, dh = piece.b1 - piece.b0;
  shape.axis = d;
  if (std::abs(drho) <= tol) {
    shape.kind = SurfaceKind::Cylinder;
    shape.point = foot;
    shape.radius = 0.5 * (piece.a0 + piece.a1);
  } else if (std::abs(dh) <= tol) {
    shape.kind = SurfaceKind::Plane;
    shape.point = add(foot, scale(d, piece.b0));
  } else {
    // A cone's apex where the line meets the axis; its axis points into the cone (radius growing).
    shape.kind = SurfaceKind::Cone;
    const double apex_h = piece.b0 - piece.a0 * dh / drho;
    const bool grows_up = (dh > 0) == (drho > 0);
    shape.point = add(foot, scale(d, apex_h));
    shape.axis = grows_up ? d : scale(d, -1);
    shape.angle = std::atan(std::abs(drho / dh));
  }
  return true;
}

// Whether the facets go far enough about the axis, in enough directions, to be swept about it:
// a stray triangle or two of a CAD fan, or four faces of a square ring (two crossed cylinders
// seen about the axis across both), meet an axis by chance.
bool swept_about(const FacetMesh& fm, const std::vector<int>& facets, const Axis& axis) {
  const Vec3 first = normalized(reject(fm.facets[facets.front()].normal, axis.direction));
  const Vec3 second = cross(axis.direction, first);
  std::vector<double> angles;
  for (int f : facets) {
    const Vec3 d = normalized(reject(fm.facets[f].normal, axis.direction));
    angles.push_back(std::atan2(dot(d, second), dot(d, first)) * 180 / M_PI);
  }
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end(), [](double a, double b) { return b - a < 1; }), angles.end());
  return angles.size() >= kSweptDirections && angles.back() - angles.front() >= kSweptDegrees;
}

// Whether the facets face as the swept surface does (see kNormalSlack).
bool faces_as_swept(const FacetMesh& fm, const std::vector<int>& facets, const SurfacePatch& shape) {
  for (int f : facets) {
    double fold = 0;
    for (int k : fm.folds_of[f]) fold = std::max(fold, fm.folds[k].degrees);
    const double limit = std::min(fold, 60.0) / 2 + kNormalSlack;
    const double c = std::abs(dot(fm.facets[f].normal, surface_normal(shape, centroid_of(fm, f))));
    if (c < std::cos(limit * M_PI / 180)) return false;
  }
  return true;
}

// Cuts each walk of the profile into the longest lines and arcs, each a surface of its facets.
void cut_profile(const FacetMesh& fm, const Profile& p, const Axis& axis, double tol,
                 std::vector<MeshSurface>& out) {
  for (const auto& w : profile_walks(p)) {
    std::size_t i = 0;
    while (i + 1 < w.size()) {
      Piece best, trial;
      std::size_t end = i + 1;
      line_fits(p, w, i, end, tol, best);
      for (std::size_t j = i + 2; j < w.size(); ++j) {
        const bool fits = line_fits(p, w, i, j, tol, trial) || arc_fits(p, w, i, j, tol, trial);
        if (fits) best = trial, end = j;
        else if (j + 1 - i >= kArcPoints) break;  // three points bend: only a fourth can say arc
      }
      MeshSurface s;
      if (swept_surface(best, axis, tol, s)) {
        const std::vector<int> facets = swept_facets(p, w, i, end);
        if (!swept_about(fm, facets, axis) ||
            !faces_as_swept(fm, facets, s.shape)) {
          i = end;
          continue;
        }
        for (int f : facets) {
          s.triangles.insert(s.triangles.end(), fm.facets[f].triangles.begin(), fm.facets[f].triangles.end());
          s.area += fm.facets[f].area;
        }
        if (!best.arc && s.shape.kind != SurfaceKind::Plane)
          s.sides = regular_polygon(fm, facets, axis.point, axis.direction, std::max(best.a0, best.a1), true, tol, s.vertex_direction);
        if (!s.triangles.empty()) out.push_back(std::move(s));
      }
      i = end;
    }
  }
}

}  // namespace

std::vector<MeshSurface> find_revolutions(const FacetMesh& fm, const std::vector<int>& group,
                                          double tolerance, std::vector<char>& used) {
  std::vector<char> in_group(fm.facets.size(), 0);
  for (int f : group) in_group[f] = 1;
  std::vector<int> order = group;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return fm.facets[a].area > fm.facets[b].area; });
  std::vector<MeshSurface> out;
  std::vector<char> tried(fm.facets.size(), 0);  // in a revolution grown before: no seed again
  for (int seed : order) {
    if (used[seed] || tried[seed]) continue;
    // A ball first: its normals all meet at its centre, so every axis through it would do.
    MeshSurface ball;
    if (grow_sphere(fm, in_group, seed, used, tolerance, ball)) {
      for (int t : ball.triangles) used[fm.facet_of[t]] = 1;
      out.push_back(std::move(ball));
      continue;
    }
    Axis axis;
    const std::vector<int> members = grow_revolution(fm, in_group, seed, used, tolerance, axis);
    for (int f : members) tried[f] = 1;
    if (members.size() < 4) continue;
    const std::size_t before = out.size();
    cut_profile(fm, trace_profile(fm, members, axis, tolerance), axis, 2 * tolerance, out);
    for (std::size_t k = before; k < out.size(); ++k)
      for (int t : out[k].triangles) used[fm.facet_of[t]] = 1;
  }
  return out;
}

}  // namespace csgfit
