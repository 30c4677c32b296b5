// Trims are tried as whole graphs, scored by ViewScorer (view_reading.h).
#include "csgfit/search/hidden_trim.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "csgfit/seed/surface_candidates.h"
#include "model/linalg.h"

#include "view_reading.h"

namespace csgfit {

using namespace linalg;

namespace {

constexpr double kTrimShare = 0.05;     // of the tree's hidden volume: what a trim must take
constexpr double kTargetShare = 0.01;   // ... and what each primitive it cuts must give up

struct Trim {
  PrecedenceGraph graph;
  std::vector<double> cut;  // the new node's distances
  std::size_t erased = 0;
};

PrecedenceGraph cutting(const PrecedenceGraph& g, const SignedPrimitive& cut, const std::vector<int>& targets) {
  const int at = static_cast<int>(g.nodes.size());
  std::vector<PrecedenceArc> arcs;
  for (int t : targets) arcs.push_back({t, at, ArcKind::Subtracting});
  return with_node(g, cut, arcs);
}

// The trim by `cut` of every positive node that gives up hidden volume to it alone unseen; empty
// graph when the trim as a whole does not keep the views or take enough.
Trim trim_by(const PrecedenceGraph& g, const SignedPrimitive& cut, ViewScorer& scorer,
             const Reading& base, double slack) {
  Trim trim;
  trim.cut = scorer.distances(cut.primitive);
  const auto unseen_taking = [&](const PrecedenceGraph& t, double share) {
    const Reading r = scorer.read(t, &trim.cut);
    const bool unseen = r.seen <= base.seen + slack;
    const bool enough = static_cast<double>(r.hidden) <= (1 - share) * static_cast<double>(base.hidden);
    return unseen && enough ? base.hidden - r.hidden : std::size_t{0};
  };
  std::vector<int> targets;
  for (std::size_t n = 0; n < g.nodes.size(); ++n)
    if (g.nodes[n].positive && unseen_taking(cutting(g, cut, {static_cast<int>(n)}), kTargetShare) > 0)
      targets.push_back(static_cast<int>(n));
  if (targets.empty()) return trim;
  PrecedenceGraph t = cutting(g, cut, targets);
  trim.erased = unseen_taking(t, kTrimShare);
  if (trim.erased > 0) trim.graph = std::move(t);
  return trim;
}

// Block `cut` mirrored in the plane through `centre` square to the block's axis that points
// from the centre towards it: the opposite flat at the same distance.
SignedPrimitive opposite(const SignedPrimitive& cut, const Vec3& centre) {
  const Primitive3D& b = cut.primitive;
  const Mat3 r = b.rotation.matrix();
  const Vec3 c{b.cx, b.cy, b.cz};
  int a = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(dot(column(r, i), sub(c, centre))) > std::abs(dot(column(r, a), sub(c, centre)))) a = i;
  const Vec3 n = column(r, a);
  const auto reflect = [&](const Vec3& v) { return sub(v, scale(n, 2 * dot(v, n))); };
  const Vec3 moved = sub(c, scale(n, 2 * dot(sub(c, centre), n)));
  // The frame reflected, one axis turned back so that it stays a rotation (a block is the same
  // under any axis reversed).
  const Vec3 x = reflect(column(r, 0)), y = scale(reflect(column(r, 1)), -1), z = reflect(column(r, 2));
  SignedPrimitive out = cut;
  out.conjectured = out.halfspace = true;
  out.primitive = Primitive3D::box(moved[0], moved[1], moved[2], b.dims[0], b.dims[1], b.dims[2],
                                   quaternion_from_matrix({{{x[0], y[0], z[0]}, {x[1], y[1], z[1]}, {x[2], y[2], z[2]}}}));
  return out;
}

// The flats a turned or spherical part has opposite its seen ones: each block cut from a
// round node mirrored through that node's centre (a ball's six flats, of which a view sees
// three).
struct Flat {
  SignedPrimitive cut;
  int round = 0;  // the node it cuts
};

std::vector<Flat> opposite_flats(const PrecedenceGraph& g, double near) {
  std::vector<Flat> out;
  for (const PrecedenceArc& arc : g.arcs) {
    const SignedPrimitive& cut = g.nodes[static_cast<std::size_t>(arc.to)];
    const Primitive3D& round = g.nodes[static_cast<std::size_t>(arc.from)].primitive;
    if (arc.kind != ArcKind::Subtracting || cut.positive || cut.primitive.kind != PrimitiveKind3D::Box) continue;
    if (round.kind == PrimitiveKind3D::Sphere || round.kind == PrimitiveKind3D::Cylinder ||
        round.kind == PrimitiveKind3D::Ellipsoid)
    {
      Flat f{opposite(cut, Vec3{round.cx, round.cy, round.cz}), arc.from};
      const auto same = [&](const SignedPrimitive& o) { return alike(f.cut, o, near); };
      if (std::none_of(g.nodes.begin(), g.nodes.end(), same)) out.push_back(std::move(f));
    }
  }
  return out;
}

// Each opposite flat that cuts its round node where no view sees the difference: the hidden
// side of a part finished as its seen side was (the caps there may lie outside the seen box,
// where the hidden lattice has no samples to count, so no share is asked).
PrecedenceGraph add_opposite_flats(PrecedenceGraph graph, ViewScorer& scorer, double slack, double near) {
  for (Flat& f : opposite_flats(graph, near)) {
    const Reading base = scorer.read(graph);
    std::vector<double> d = scorer.distances(f.cut.primitive);
    PrecedenceGraph t = cutting(graph, f.cut, {f.round});
    if (scorer.read(t, &d).seen > base.seen + slack) continue;
    graph = std::move(t);
    scorer.add_node(std::move(d));
  }
  return graph;
}

}  // namespace

PrecedenceGraph trim_hidden(PrecedenceGraph graph, const std::vector<SignedPrimitive>& pool,
                            const RangeEvidence& evidence, double k, const std::atomic<bool>* cancel) {
  if (evidence.hidden.empty() || graph.nodes.empty()) return graph;
  ViewScorer scorer(evidence, graph.nodes);
  for (;;) {
    const Reading base = scorer.read(graph);
    if (base.hidden == 0) break;
    Trim best;
    for (const SignedPrimitive& cut : pool) {
      if (!cut.halfspace || (cancel && cancel->load())) continue;
      Trim t = trim_by(graph, cut, scorer, base, kSeenSlack * k);
      if (t.erased > best.erased) best = std::move(t);
    }
    if (best.erased == 0) break;
    graph = std::move(best.graph);
    scorer.add_node(std::move(best.cut));
  }
  return add_opposite_flats(std::move(graph), scorer, kSeenSlack * k, 2 * evidence.tolerance);
}

}  // namespace csgfit
