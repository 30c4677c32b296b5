// Cylinders read off a tessellation: a cylinder's facets are strips whose shared edges all run
// along its axis, and their edges lie on one circle across it. A chain of such facets may hold
// several arcs joined by flat faces (a slot: arc, side, arc, side), so each chain is cut into the
// longest runs one circle explains.
#include <algorithm>
#include <cmath>
#include <map>

#include "mesh_facets.h"
#include "model/linalg.h"
#include "patch_fit.h"

namespace csgfit {

namespace {

using namespace linalg;

// A fold runs along a facet's axis when both facets' normals are across it within this sine
// (half a degree): tessellations of one cylinder share it to the rounding of the file.
constexpr double kAcrossAxis = 0.009;
// Two folds share an axis when their directions agree within this sine (half a degree).
constexpr double kSameAxis = 0.009;
// Regular polygon sides turn by 360 / n; the turns of one polygon agree within this (degrees).
constexpr double kTurnSlack = 0.25;
// Fewest sides read as a regular polygon: a square is a box's, a triangle a wedge's.
constexpr int kFewestSides = 5;
constexpr int kMostSides = 1000;

bool parallel(const Vec3& a, const Vec3& b, double sine) { return norm(cross(a, b)) <= sine; }

// The folds that may join facets of one cylinder.
bool along_axis(const FacetMesh& fm, const Fold& f, double max_fold) {
  return f.straight && f.degrees > 0 && f.degrees <= max_fold &&
         std::abs(dot(fm.facets[f.a].normal, f.direction)) <= kAcrossAxis &&
         std::abs(dot(fm.facets[f.b].normal, f.direction)) <= kAcrossAxis;
}

struct Chain {
  Vec3 axis{0, 0, 1};
  std::vector<int> facets;                   // in order along the chain
  bool cyclic = false;
};

// Facets joined by folds along one axis, from `seed`, each to its chain neighbours.
// Facets joined by folds along one axis, from `seed`, each to its chain neighbours; `taken`
// facets (in an arc already) stay out, and every fold followed is marked `seen` so that the
// same chain is not grown again from another of its folds.
std::map<int, std::vector<int>> grow_chain(const FacetMesh& fm, int seed, const Vec3& axis, double max_fold,
                                           const std::vector<char>& taken, std::vector<char>& seen) {
  std::map<int, std::vector<int>> next;
  std::vector<int> stack{seed};
  next[seed];
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    for (int k : fm.folds_of[f]) {
      const Fold& fold = fm.folds[k];
      if (!along_axis(fm, fold, max_fold) || !parallel(fold.direction, axis, kSameAxis)) continue;
      const int g = fold.a == f ? fold.b : fold.a;
      if (taken[g]) continue;
      seen[static_cast<std::size_t>(k)] = 1;
      next[f].push_back(g);
      if (!next.count(g)) {
        next[g];
        stack.push_back(g);
      }
    }
  }
  return next;
}

// The chain without its facets of more than two neighbours (a flat face several arcs meet, as a
// bar's side meets the bosses at its ends), split into the runs that are left.
std::vector<std::map<int, std::vector<int>>> simple_chains(const std::map<int, std::vector<int>>& next) {
  std::vector<std::map<int, std::vector<int>>> out;
  const auto simple = [&](int f) { return next.at(f).size() <= 2; };
  std::map<int, bool> done;
  for (const auto& entry : next) {
    if (done[entry.first] || !simple(entry.first)) continue;
    std::map<int, std::vector<int>> run;
    std::vector<int> stack{entry.first};
    done[entry.first] = true;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      run[f];
      for (int g : next.at(f)) {
        if (!simple(g)) continue;
        run[f].push_back(g);
        if (!done[g]) done[g] = true, stack.push_back(g);
      }
    }
    out.push_back(std::move(run));
  }
  return out;
}

// The chain as a path (or a cycle) when every facet has at most two neighbours in it. A path
// starts at an end; a cycle at its widest facet, a flat side between arcs if there is one.
bool order_chain(const FacetMesh& fm, const std::map<int, std::vector<int>>& next, Chain& out) {
  int start = -1;
  for (const auto& [f, ns] : next) {
    if (ns.size() > 2) return false;
    if (ns.size() == 1 && start < 0) start = f;
  }
  out.cyclic = start < 0;
  if (out.cyclic) {
    start = next.begin()->first;
    for (const auto& entry : next)
      if (fm.facets[entry.first].area > fm.facets[start].area) start = entry.first;
  }
  int prev = -1, at = start;
  while (at >= 0 && out.facets.size() < next.size()) {
    out.facets.push_back(at);
    int step = -1;
    for (int g : next.at(at))
      if (g != prev && std::find(out.facets.begin(), out.facets.end(), g) == out.facets.end()) step = g;
    prev = at, at = step;
  }
  return out.facets.size() == next.size();
}

std::vector<Vec3> points_of(const FacetMesh& fm, const std::vector<int>& facets) {
  std::vector<Vec3> pts;
  for (int v : facet_vertices(fm, facets))
    pts.push_back({fm.mesh.vertices[v][0], fm.mesh.vertices[v][1], fm.mesh.vertices[v][2]});
  return pts;
}

// The points across the axis where consecutive facets of the run meet: corners of the polygon
// the run's sides belong to, on the circle exactly (a vertex that only one side has may be
// where another surface cut the side, anywhere along it).
std::vector<Vec3> corners_of(const FacetMesh& fm, const std::vector<int>& run) {
  std::vector<Vec3> pts;
  for (std::size_t k = 0; k + 1 < run.size(); ++k)
    for (int i : fm.folds_of[run[k]])
      if (fm.folds[i].a == run[k + 1] || fm.folds[i].b == run[k + 1]) pts.push_back(fm.folds[i].point);
  return pts;
}

// Whether each facet of the run is one side of the circle's polygon: no vertex outside the
// circle, and seen from the axis it spans no more than the run turns per side (a flat face
// that meets the arc along a corner spans far more).
bool sides_of(const FacetMesh& fm, const std::vector<int>& run, const Vec3& axis,
              const AxisCircle& circle, double tolerance) {
  double turn = 0;
  for (std::size_t k = 0; k + 1 < run.size(); ++k)
    turn = std::max(turn, std::acos(std::clamp(dot(fm.facets[run[k]].normal, fm.facets[run[k + 1]].normal), -1.0, 1.0)));
  const double widest = 2 * turn + M_PI / 180;
  for (int f : run) {
    Vec3 first{0, 0, 0};
    for (int v : fm.facets[f].vertices) {
      const Vec3 r = reject(sub(Vec3{fm.mesh.vertices[v][0], fm.mesh.vertices[v][1], fm.mesh.vertices[v][2]}, circle.centre), axis);
      if (norm(r) > circle.radius + tolerance) return false;
      if (norm(first) == 0) first = r;
      else if (std::acos(std::clamp(dot(normalized(first), normalized(r)), -1.0, 1.0)) > widest) return false;
    }
  }
  return true;
}

// The circle of a run of facets, when one explains all their corners (all their vertices for
// a run too short to have three corners) and each facet is a side of its polygon.
bool circle_of(const FacetMesh& fm, const std::vector<int>& facets, const Vec3& axis,
               double tolerance, double longest, AxisCircle& circle) {
  std::vector<Vec3> pts = corners_of(fm, facets);
  if (pts.size() < 3) pts = points_of(fm, facets);
  if (pts.size() < 3) return false;
  circle = fit_axis_circle(pts, pts.front(), axis);
  return circle.ok && circle.max_error <= tolerance && circle.radius < longest &&
         sides_of(fm, facets, axis, circle, tolerance);
}

double angle_about(const Vec3& v, const Vec3& u, const Vec3& w) { return std::atan2(dot(v, w), dot(v, u)); }

FacetArc make_arc(const FacetMesh& fm, std::vector<int> facets, const Vec3& axis,
                  const AxisCircle& circle, double tolerance) {
  FacetArc arc;
  arc.facets = std::move(facets);
  arc.axis = axis;
  arc.centre = circle.centre;
  arc.radius = circle.radius;
  double outward = 0;
  for (int f : arc.facets) {
    const Facet& facet = fm.facets[f];
    const Vec3 on = scale(facet.normal, facet.offset);
    outward += facet.area * dot(facet.normal, reject(sub(on, circle.centre), axis));
  }
  arc.convex = outward > 0;
  arc.sides = regular_polygon(fm, arc.facets, arc.centre, arc.axis, arc.radius, arc.convex, tolerance,
                              arc.vertex_direction);
  return arc;
}

// The longest runs of the chain that one circle explains, three facets at least.
void cut_into_arcs(const FacetMesh& fm, const Chain& chain, double tolerance, double longest,
                   std::vector<FacetArc>& arcs) {
  AxisCircle circle;
  if (chain.cyclic && circle_of(fm, chain.facets, chain.axis, tolerance, longest, circle)) {
    arcs.push_back(make_arc(fm, chain.facets, chain.axis, circle, tolerance));
    return;
  }
  const std::size_t m = chain.facets.size();
  std::size_t i = 0;
  while (i + 2 < m) {
    std::vector<int> run(chain.facets.begin() + static_cast<long>(i), chain.facets.begin() + static_cast<long>(i) + 3);
    if (!circle_of(fm, run, chain.axis, tolerance, longest, circle)) {
      ++i;
      continue;
    }
    AxisCircle grown;
    std::size_t j = i + 3;
    for (; j < m; ++j) {
      run.push_back(chain.facets[j]);
      if (!circle_of(fm, run, chain.axis, tolerance, longest, grown)) {
        run.pop_back();
        break;
      }
      circle = grown;
    }
    arcs.push_back(make_arc(fm, run, chain.axis, circle, tolerance));
    i = j;
  }
}

}  // namespace

int regular_polygon(const FacetMesh& fm, const std::vector<int>& facets, const Vec3& centre,
                    const Vec3& axis, double radius, bool convex, double tolerance,
                    Vec3& vertex_direction) {
  const Vec3 u = normalized(reject(std::abs(axis[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}, axis));
  const Vec3 w = cross(axis, u);
  const double sign = convex ? 1 : -1;  // normals out of the axis
  const double slack = kTurnSlack * M_PI / 180;
  // The sides' directions about the axis, each once (a CAD strip may be cut into rows).
  std::vector<double> angles;
  for (int f : facets) angles.push_back(angle_about(scale(fm.facets[f].normal, sign), u, w));
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end(), [&](double a, double b) { return b - a <= slack; }), angles.end());
  if (angles.size() < 3) return 0;
  double step = 2 * M_PI;
  for (std::size_t k = 0; k + 1 < angles.size(); ++k) step = std::min(step, angles[k + 1] - angles[k]);
  const int n = static_cast<int>(std::lround(2 * M_PI / step));
  if (n < kFewestSides || n > kMostSides) return 0;
  step = 2 * M_PI / n;
  // Consecutive sides turn by the step, or by whole steps where others are missing.
  for (std::size_t k = 0; k + 1 < angles.size(); ++k) {
    const double turn = angles[k + 1] - angles[k];
    if (std::abs(turn - step * std::round(turn / step)) > slack) return 0;
  }
  // A prism's sides stand at the apothem; a pyramid frustum's lean and need not.
  const double apothem = radius * std::cos(M_PI / n);
  for (int f : facets) {
    const Facet& facet = fm.facets[f];
    if (norm(reject(facet.normal, axis)) < 0.999) continue;
    if (std::abs(std::abs(facet.offset - dot(facet.normal, centre)) - apothem) > tolerance) return 0;
  }
  const double vertex_angle = angles.front() + M_PI / n;
  vertex_direction = normalized(add(scale(u, std::cos(vertex_angle)), scale(w, std::sin(vertex_angle))));
  return n;
}

std::vector<FacetArc> find_facet_arcs(const FacetMesh& fm, const std::vector<char>& used_before,
                                      double tolerance, double max_fold_degrees) {
  // No circle is wider than the part: past that, a run of facets is flat.
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& v : fm.mesh.vertices)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
  const double longest = norm(sub(hi, lo));
  std::vector<char> taken = used_before, seen(fm.folds.size(), 0);
  std::vector<FacetArc> arcs;
  for (std::size_t k = 0; k < fm.folds.size(); ++k) {
    const Fold& seed = fm.folds[k];
    if (seen[k] || taken[seed.a] || taken[seed.b] || !along_axis(fm, seed, max_fold_degrees)) continue;
    for (const auto& next : simple_chains(grow_chain(fm, seed.a, seed.direction, max_fold_degrees, taken, seen))) {
      Chain chain;
      chain.axis = seed.direction;
      if (next.size() < 3 || !order_chain(fm, next, chain)) continue;
      const std::size_t before = arcs.size();
      cut_into_arcs(fm, chain, tolerance, longest, arcs);
      for (std::size_t a = before; a < arcs.size(); ++a)
        for (int f : arcs[a].facets) taken[f] = 1;
    }
  }
  return arcs;
}

}  // namespace csgfit
