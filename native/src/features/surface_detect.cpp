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

double diagonal_of(const std::vector<Vec3>& points) {
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points)
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
  return std::sqrt(squared(sub(hi, lo)));
}

Ransac::Parameters ransac_parameters(const SurfaceDetectOptions& o, double diagonal,
                                     std::size_t n) {
  Ransac::Parameters p;
  p.probability = o.probability;
  p.epsilon = o.epsilon > 0 ? o.epsilon : 0.004 * diagonal;
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
                                      const Ransac::Parameters& parameters) {
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
  ransac.detect(parameters);
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

}  // namespace

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
                                          std::uint64_t seed) {
  if (points.size() != normals.size())
    throw std::invalid_argument("detect_surfaces: one normal per point is needed");
  if (points.size() < 3) return {};
  const double diagonal = diagonal_of(points);
  const Ransac::Parameters parameters = ransac_parameters(options, diagonal, points.size());
  // CGAL draws from its default generator: seeding it makes the detection repeatable.
  CGAL::get_default_random() = CGAL::Random(static_cast<unsigned>(seed & 0x7fffffffu));

  // Planes, spheres and cylinders first, cones and tori on what they leave: a near-cylinder is
  // also a cone with a far apex and a sphere a torus with no hole, and RANSAC, which ranks
  // candidates by points explained, would otherwise take the general form for the simple one.
  SurfaceDetectOptions simple = options, general = options;
  simple.cones = simple.tori = false;
  general.planes = general.spheres = general.cylinders = false;
  std::vector<char> taken(points.size(), 0);
  std::vector<SurfacePatch> patches;
  // The general kinds must also explain more before they are believed: on what the simple ones
  // leave (edges, noise) a cone or torus fits any small curved strip.
  Ransac::Parameters general_parameters = parameters;
  general_parameters.min_points = std::max(parameters.min_points, points.size() / 100);
  for (const SurfaceDetectOptions* pass : {&simple, &general}) {
    if (!(pass->planes || pass->spheres || pass->cylinders || pass->cones || pass->tori))
      continue;
    const Ransac::Parameters& params = pass == &simple ? parameters : general_parameters;
    // A shape refused below leaves its points in the pool: another round may find what they
    // really are (a plane that RANSAC first took for a cylinder as wide as a house).
    for (int round = 0; round < 4; ++round) {
      std::size_t accepted = 0;
      for (SurfacePatch& patch : detect_pass(points, normals, taken, *pass, params)) {
        if (flat_enough(patch, diagonal)) patch.kind = SurfaceKind::Plane;
        polish_patch(patch, points, normals);
        keep_fitting_points(patch, points, normals, params);
        polish_patch(patch, points, normals);
        if (!plausible(patch, diagonal) || patch.points.size() < params.min_points) continue;
        patch.convex = is_convex(patch, points, normals);
        patch.rms = patch_rms(patch, points);
        for (int i : patch.points) taken[i] = 1;
        patches.push_back(std::move(patch));
        ++accepted;
      }
      if (accepted == 0) break;
    }
  }
  return patches;
}

}  // namespace csgfit
