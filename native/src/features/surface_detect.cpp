// CGAL's efficient RANSAC (Schnabel, Wahl, Klein 2007) rather than a detector of our own: it is
// the well-kept implementation of the method InverseCSG also uses, and CGAL 5.5 is a Debian
// package. What is ours: the tolerances relative to the part, the convexity of each patch
// (seed 002's sign), and a least-squares polish of the parameters on the patch's points.
#include "csgfit/features/surface_detect.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Shape_detection/Efficient_RANSAC.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "model/linalg.h"
#include "patch_fit.h"

namespace csgfit {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// The index travels with each point because the detector sorts its input in place (into its
// octree): the shapes' indices are positions in the sorted list.
using PointWithNormal = std::tuple<Kernel::Point_3, Kernel::Vector_3, int>;
using PointList = std::vector<PointWithNormal>;
using Traits = CGAL::Shape_detection::Efficient_RANSAC_traits<
    Kernel, PointList, CGAL::Nth_of_tuple_property_map<0, PointWithNormal>,
    CGAL::Nth_of_tuple_property_map<1, PointWithNormal>>;
using Ransac = CGAL::Shape_detection::Efficient_RANSAC<Traits>;
namespace sd = CGAL::Shape_detection;
using namespace linalg;

Vec3 vec(const Kernel::Vector_3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 vec(const Kernel::Point_3& p) { return {p.x(), p.y(), p.z()}; }


Ransac::Parameters ransac_parameters(const SurfaceDetectOptions& o, double diagonal,
                                     std::size_t n) {
  Ransac::Parameters p;
  p.probability = o.probability;
  p.epsilon = o.epsilon > 0 ? o.epsilon : 0.0025 * diagonal;
  p.cluster_epsilon = o.cluster_epsilon > 0 ? o.cluster_epsilon : 0.015 * diagonal;
  p.normal_threshold = o.normal_threshold;
  p.min_points = o.min_points > 0 ? static_cast<std::size_t>(o.min_points)
                                  : std::max<std::size_t>(40, n / 250);
  return p;
}

void add_factories(Ransac& ransac, const SurfaceDetectOptions& o) {
  if (o.planes) ransac.add_shape_factory<sd::Plane<Traits>>();
  if (o.spheres) ransac.add_shape_factory<sd::Sphere<Traits>>();
  if (o.cylinders) ransac.add_shape_factory<sd::Cylinder<Traits>>();
  if (o.cones) ransac.add_shape_factory<sd::Cone<Traits>>();
  if (o.tori) ransac.add_shape_factory<sd::Torus<Traits>>();
}

// The CGAL shape's parameters in our form; false for a shape type we did not ask for.
bool read_shape(const sd::Shape_base<Traits>& shape, SurfacePatch& out) {
  if (auto* plane = dynamic_cast<const sd::Plane<Traits>*>(&shape)) {
    out.kind = SurfaceKind::Plane;
    out.axis = normalized(vec(plane->plane_normal()));
  } else if (auto* sphere = dynamic_cast<const sd::Sphere<Traits>*>(&shape)) {
    out.kind = SurfaceKind::Sphere;
    out.point = vec(sphere->center());
    out.radius = sphere->radius();
  } else if (auto* cylinder = dynamic_cast<const sd::Cylinder<Traits>*>(&shape)) {
    out.kind = SurfaceKind::Cylinder;
    out.point = vec(cylinder->axis().point(0));
    out.axis = normalized(vec(cylinder->axis().to_vector()));
    out.radius = cylinder->radius();
  } else if (auto* cone = dynamic_cast<const sd::Cone<Traits>*>(&shape)) {
    out.kind = SurfaceKind::Cone;
    out.point = vec(cone->apex());
    out.axis = normalized(vec(cone->axis()));
    out.angle = cone->angle();
  } else if (auto* torus = dynamic_cast<const sd::Torus<Traits>*>(&shape)) {
    out.kind = SurfaceKind::Torus;
    out.point = vec(torus->center());
    out.axis = normalized(vec(torus->axis()));
    out.radius = torus->major_radius();
    out.minor_radius = torus->minor_radius();
  } else {
    return false;
  }
  return true;
}

// One RANSAC run over the points not yet taken.
std::vector<SurfacePatch> detect_pass(const std::vector<Vec3>& points,
                                      const std::vector<Vec3>& normals,
                                      const std::vector<char>& taken,
                                      const SurfaceDetectOptions& kinds,
                                      const Ransac::Parameters& parameters,
                                      const std::atomic<bool>* cancel) {
  PointList list;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (taken[i]) continue;
    list.emplace_back(Kernel::Point_3(points[i][0], points[i][1], points[i][2]),
                      Kernel::Vector_3(normals[i][0], normals[i][1], normals[i][2]),
                      static_cast<int>(i));
  }
  std::vector<SurfacePatch> found;
  if (list.size() < parameters.min_points) return found;
  Ransac ransac;
  ransac.set_input(list);
  add_factories(ransac, kinds);
  // CGAL asks between candidates whether to go on.
  ransac.detect(parameters, [cancel](double) { return !(cancel && cancel->load()); });
  for (const auto& shape : ransac.shapes()) {
    SurfacePatch patch;
    if (!read_shape(*shape, patch)) continue;
    for (std::size_t at : shape->indices_of_assigned_points())
      patch.points.push_back(std::get<2>(list[at]));
    found.push_back(std::move(patch));
  }
  return found;
}

// CGAL assigns points to a shape before its final fit; points the polished surface does not
// explain (further than epsilon, or with a normal across it) go back to the pool.
void keep_fitting_points(SurfacePatch& patch, const std::vector<Vec3>& points,
                         const std::vector<Vec3>& normals, const Ransac::Parameters& p) {
  std::vector<int> kept;
  for (int i : patch.points)
    if (std::abs(surface_distance(patch, points[i])) <= p.epsilon &&
        std::abs(dot(normals[i], surface_normal(patch, points[i]))) >= p.normal_threshold)
      kept.push_back(i);
  patch.points = std::move(kept);
}

// A sphere or cylinder much wider than the part is a plane seen by RANSAC's general form.
// A torus whose core circle is far smaller than its tube is a sphere (RANSAC's torus fits a
// ball by a tube around a tiny circle): the sphere's own polish refits it.
bool ball_like(const SurfacePatch& s) {
  return s.kind == SurfaceKind::Torus && s.radius < 0.5 * s.minor_radius;
}

bool flat_enough(const SurfacePatch& s, double diagonal) {
  return (s.kind == SurfaceKind::Sphere || s.kind == SurfaceKind::Cylinder) && s.radius > 3 * diagonal;
}

// A curved surface whose curvature is lost in the part's size (a cylinder wider than the part,
// a cone that has become a cylinder, a torus without a hole) stands for a simpler surface
// that an earlier pass either found or refused: it is not a primitive of its own.
bool plausible(const SurfacePatch& s, double diagonal) {
  const auto finite = [](const Vec3& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
  };
  if (!finite(s.point) || !finite(s.axis)) return false;
  switch (s.kind) {
    case SurfaceKind::Plane: return true;
    case SurfaceKind::Sphere:
    case SurfaceKind::Cylinder: return s.radius > 0 && s.radius < diagonal;
    case SurfaceKind::Cone: return s.angle > 0.05 && s.angle < 1.3;
    case SurfaceKind::Torus:
      return s.minor_radius > 0 && s.radius > 0.5 * s.minor_radius && s.radius < diagonal;
  }
  return false;
}

SurfaceDetectOptions none_of_the_kinds() {
  SurfaceDetectOptions o;
  o.planes = o.spheres = o.cylinders = o.cones = o.tori = false;
  return o;
}

// The scatter of a patch's normals about the origin: eigenvalues largest first, and the
// direction of least spread (a cylinder's axis).
struct NormalSpread {
  Vec3 values;
  Vec3 least;
};

NormalSpread normal_spread(const SurfacePatch& s, const std::vector<Vec3>& normals) {
  Mat3 c{};
  for (int i : s.points)
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) c[r][q] += normals[i][r] * normals[i][q];
  NormalSpread out;
  Mat3 vectors;
  symmetric_eigen3(c, out.values, vectors);
  out.least = column(vectors, 2);
  return out;
}

// Whether a cylinder about the normals' least-spread direction explains a sphere patch's
// points nearly as well as the sphere does: a band of a cylinder, not of a sphere.
bool cylinder_fits_as_well(const SurfacePatch& sphere, const Vec3& axis,
                           const std::vector<Vec3>& points, const std::vector<Vec3>& normals) {
  SurfacePatch cylinder = sphere;
  cylinder.kind = SurfaceKind::Cylinder;
  cylinder.axis = axis;
  polish_patch(cylinder, points, normals);
  return patch_rms(cylinder, points) < 2 * patch_rms(sphere, points);
}

// Whether the patch's normals turn as what RANSAC says it is. A sphere's normals fan out in
// two directions (a band of a cylinder fits a sphere within epsilon too, but its normals lie
// in one plane); `band` accepts a narrower fan where no cylinder explains the points as well
// (a sphere's band below a cut, seen past a block in front of it: one_sphere_two_cuboids, 3 %
// spread). A cylinder's or cone's normals turn by 10 degrees at least (a strip along a concave
// edge, where an image's normals blend, fits a wide cylinder as well).
bool curved_enough(const SurfacePatch& s, const std::vector<Vec3>& points,
                   const std::vector<Vec3>& normals, bool band) {
  if (s.kind == SurfaceKind::Plane) return true;
  const NormalSpread spread = normal_spread(s, normals);
  const Vec3& v = spread.values;
  if (s.kind == SurfaceKind::Sphere)
    return v[2] > 0.05 * v[0] ||
           (band && v[2] > 0.01 * v[0] && !cylinder_fits_as_well(s, spread.least, points, normals));
  return v[1] > 0.003 * v[0];
}

// A curved patch whose points a plane fits as well (and within a third of epsilon) is that
// plane.
bool fits_a_plane(const SurfacePatch& s, const std::vector<Vec3>& points,
                  const std::vector<Vec3>& normals, double epsilon) {
  if (s.kind == SurfaceKind::Plane || s.points.size() < 8) return false;
  SurfacePatch plane_patch = s;
  plane_patch.kind = SurfaceKind::Plane;
  polish_patch(plane_patch, points, normals);
  // A plane that explains the points about as well as the curve does (within sensor noise of
  // it) is the simpler reading; a short arc's sagitta shows as a clearly worse plane.
  const double plane = patch_rms(plane_patch, points), curved = patch_rms(s, points);
  return plane < epsilon / 3 && plane <= 1.5 * curved;
}

// The detector's state across its passes: which points are taken, what was found.
struct Detection {
  const std::vector<Vec3>& points;
  const std::vector<Vec3>& normals;
  double diagonal;
  Ransac::Parameters parameters;
  std::vector<char> taken;
  std::vector<SurfacePatch> patches;
  const std::atomic<bool>* cancel = nullptr;

  // RANSAC on the free points in rounds: a shape refused leaves its points in the pool, and
  // another round may find what they really are (a plane RANSAC first took for a cylinder as
  // wide as a house). `proposal_normals` are what RANSAC sees; the fit uses the true ones.
  enum class Pass { Hollows, Any, SphereBands };

  void run(const SurfaceDetectOptions& kinds, const Ransac::Parameters& params,
           const std::vector<Vec3>& proposal_normals, Pass pass = Pass::Any) {
    if (!(kinds.planes || kinds.spheres || kinds.cylinders || kinds.cones || kinds.tori)) return;
    for (int round = 0; round < 4; ++round) {
      std::size_t accepted = 0;
      // A cancelled fit still returns a tree: the detection stops only once it has a patch.
      const std::atomic<bool>* stop = patches.empty() ? nullptr : cancel;
      if (stop && stop->load()) return;
      for (SurfacePatch& patch : detect_pass(points, proposal_normals, taken, kinds, params, stop)) {
        if (flat_enough(patch, diagonal)) patch.kind = SurfaceKind::Plane;
        if (ball_like(patch)) patch.kind = SurfaceKind::Sphere;
        refit(patch, params);
        if (fits_a_plane(patch, points, normals, params.epsilon)) {
          patch.kind = SurfaceKind::Plane;
          refit(patch, params);
        }
        if (!plausible(patch, diagonal) || patch.points.size() < params.min_points) continue;
        if (!curved_enough(patch, points, normals, pass == Pass::SphereBands)) continue;
        patch.convex = is_convex(patch, points, normals);
        if (pass == Pass::Hollows && patch.convex) continue;  // a bulge seen with its normals turned
        patch.rms = patch_rms(patch, points);
        for (int i : patch.points) taken[i] = 1;
        patches.push_back(std::move(patch));
        ++accepted;
      }
      if (accepted == 0) break;
    }
  }

  // The least-squares polish, then only the points the polished surface explains, polished
  // again on them.
  void refit(SurfacePatch& patch, const Ransac::Parameters& params) const {
    polish_patch(patch, points, normals);
    keep_fitting_points(patch, points, normals, params);
    polish_patch(patch, points, normals);
  }

  // A plane, sphere or cylinder patch that a cone or torus explains is part of that surface
  // (a torus's crown fits a plane or a sphere within epsilon): it joins the general patch.
  void absorb_into_general(const Ransac::Parameters& params) {
    std::vector<char> absorbed(patches.size(), 0);
    for (std::size_t g = 0; g < patches.size(); ++g)
      for (std::size_t k = 0; k < patches.size(); ++k) {
        const SurfaceKind gk = patches[g].kind, kk = patches[k].kind;
        if (absorbed[g] || absorbed[k] || !(gk == SurfaceKind::Torus || gk == SurfaceKind::Cone) ||
            kk == SurfaceKind::Torus || kk == SurfaceKind::Cone)
          continue;
        std::size_t fit = 0;
        for (int i : patches[k].points)
          fit += std::abs(surface_distance(patches[g], points[i])) <= params.epsilon &&
                 std::abs(dot(normals[i], surface_normal(patches[g], points[i]))) >= params.normal_threshold;
        if (10 * fit < 9 * patches[k].points.size()) continue;
        patches[g].points.insert(patches[g].points.end(), patches[k].points.begin(), patches[k].points.end());
        absorbed[k] = 1;
      }
    std::vector<SurfacePatch> kept;
    for (std::size_t k = 0; k < patches.size(); ++k)
      if (!absorbed[k]) kept.push_back(std::move(patches[k]));
    patches = std::move(kept);
    for (std::size_t g = 0; g < patches.size(); ++g) patches[g].rms = patch_rms(patches[g], points);
  }
};

}  // namespace

double part_diagonal(const std::vector<Vec3>& points) {
  if (points.empty()) return 0;
  Vec3 mean{0, 0, 0};
  for (const Vec3& p : points) mean = add(mean, p);
  mean = scale(mean, 1.0 / static_cast<double>(points.size()));
  Mat3 c{};
  for (const Vec3& p : points) {
    const Vec3 d = sub(p, mean);
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) c[r][q] += d[r] * d[q];
  }
  Vec3 values;
  Mat3 axes;
  symmetric_eigen3(c, values, axes);
  double sum = 0;
  for (int a = 0; a < 3; ++a) {
    const Vec3 e = column(axes, a);
    double lo = 1e300, hi = -1e300;
    for (const Vec3& p : points) lo = std::min(lo, dot(p, e)), hi = std::max(hi, dot(p, e));
    sum += (hi - lo) * (hi - lo);
  }
  return std::sqrt(sum);
}

std::string_view to_string(SurfaceKind kind) {
  switch (kind) {
    case SurfaceKind::Plane: return "plane";
    case SurfaceKind::Sphere: return "sphere";
    case SurfaceKind::Cylinder: return "cylinder";
    case SurfaceKind::Cone: return "cone";
    case SurfaceKind::Torus: return "torus";
  }
  return "plane";
}

std::vector<SurfacePatch> detect_surfaces(const std::vector<Vec3>& points,
                                          const std::vector<Vec3>& normals,
                                          const SurfaceDetectOptions& options,
                                          std::uint64_t seed, const std::atomic<bool>* cancel) {
  if (points.size() != normals.size())
    throw std::invalid_argument("detect_surfaces: one normal per point is needed");
  if (points.size() < 3) return {};
  Detection d{points, normals, part_diagonal(points), {}, std::vector<char>(points.size(), 0), {}, cancel};
  d.parameters = ransac_parameters(options, d.diagonal, points.size());
  // CGAL draws from its default generator: seeding it makes the detection repeatable.
  CGAL::get_default_random() = CGAL::Random(static_cast<unsigned>(seed & 0x7fffffffu));

  // CGAL proposes a sphere only where the normals point away from its centre, so hollows are
  // looked for first with the normals turned round. Then planes, spheres and cylinders, and
  // cones and tori last on what they leave: a near-cylinder is also a cone with a far apex and
  // a sphere a torus with no hole (such a torus becomes a sphere), and RANSAC, which ranks
  // candidates by points explained, would otherwise take the general form for the simple one.
  // The general kinds must also explain more (1 % of the points): on leftovers a cone or torus
  // fits any curved strip. Bands of a torus or cone taken for spheres or cylinders are given
  // back to it at the end.
  SurfaceDetectOptions hollows = none_of_the_kinds(), simple = options, general = options;
  hollows.spheres = options.spheres;
  simple.cones = simple.tori = false;
  general.planes = general.spheres = general.cylinders = false;
  Ransac::Parameters general_parameters = d.parameters;
  general_parameters.min_points = std::max(d.parameters.min_points, points.size() / 100);
  std::vector<Vec3> turned(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) turned[i] = scale(normals[i], -1);
  d.run(hollows, d.parameters, turned, Detection::Pass::Hollows);
  d.run(simple, d.parameters, normals);
  d.run(general, general_parameters, normals);
  // Last, narrow bands of spheres on what every other kind left: earlier, a piece of a torus
  // would pass for one and keep the torus from being found.
  SurfaceDetectOptions spheres = none_of_the_kinds();
  spheres.spheres = options.spheres;
  d.run(spheres, d.parameters, normals, Detection::Pass::SphereBands);
  d.absorb_into_general(general_parameters);
  return std::move(d.patches);
}

}  // namespace csgfit
