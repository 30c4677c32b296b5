#include "csgfit/search/hidden_extents.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "model/linalg.h"
#include "view_reading.h"

namespace csgfit {

using namespace linalg;

namespace {

constexpr double kParallel = 0.9998;  // cos 1 degree: directions this close are one
constexpr double kSquare = 0.0175;    // sin 1 degree: directions this close to 90 degrees are square
constexpr double kReach = 0.5;        // of the block's size along the normal: how far a face moves
constexpr double kTurn = 0.9986;       // cos 3 degrees: a face this close to a cut's plane is that plane

// Offsets along unit `n` of the planes square to `n` that bound `p` (its faces, or its tangent
// planes where its surface meets them), as the designer's references for a face along `n`.
void bounding_planes(const Primitive3D& p, const Vec3& n, std::vector<double>& out) {
  const Vec3 c{p.cx, p.cy, p.cz};
  const double at = dot(c, n);
  const Mat3 r = p.rotation.matrix();
  const auto both = [&](double half) { out.push_back(at - half), out.push_back(at + half); };
  switch (p.kind) {
    case PrimitiveKind3D::Box:
    case PrimitiveKind3D::RoundedBox:  // its sides are flat where they are furthest out
      for (int a = 0; a < 3; ++a)
        if (std::abs(dot(column(r, a), n)) > kParallel) both(p.dims[a] / 2);
      break;
    case PrimitiveKind3D::Cylinder: {
      const double along = std::abs(dot(column(r, 2), n));
      if (along > kParallel) both(p.dims[2] / 2);
      else if (along < kSquare) both(p.dims[0]);
      break;
    }
    case PrimitiveKind3D::Sphere: both(p.dims[0]); break;
    default: break;
  }
}

// Face `side` of local axis `a` of a block (or a cylinder's end, along z): its outward normal
// and its offset along it.
struct Face {
  Vec3 n;
  double at;
};

Face face_of(const Primitive3D& b, int a, int side) {
  const Vec3 n = scale(column(b.rotation.matrix(), a), side);
  return {n, dot(Vec3{b.cx, b.cy, b.cz}, n) + b.dims[a] / 2};
}

// `b` with that face moved to offset `to` along its normal.
Primitive3D with_face_at(const Primitive3D& b, int a, int side, double to) {
  const Face f = face_of(b, a, side);
  Primitive3D moved = b;
  moved.dims[a] += to - f.at;
  const Vec3 shift = scale(f.n, (to - f.at) / 2);
  moved.cx += shift[0], moved.cy += shift[1], moved.cz += shift[2];
  return moved;
}

// The seen mismatch a move of face (axis a, side) of `p` may add: one sample where the face
// turns its back on every view (sensor noise is all there is), half of one where a view looks
// at it (a face hidden behind another part still brushes a sample's tolerance band: the cube
// behind three_cuboids' slab stayed a quarter cube for an eighth of a sample, the one behind
// nine_cuboids' for a half).
double noise_slack(const RangeEvidence& evidence, const Primitive3D& p, int a, int side) {
  const Face f = face_of(p, a, side);
  const Vec3 on_face = add(Vec3{p.cx, p.cy, p.cz}, scale(f.n, p.dims[a] / 2));
  return faces_away_from_every_view(evidence, on_face, f.n) ? EvidenceSamples::kUnitsPerSample
                                                            : EvidenceSamples::kUnitsPerSample / 2;
}

// Candidate offsets for the face (axis a, side) of `block`, node `b`: the other nodes' planes
// beyond it up to offset `until`, those that more of the part's planes agree with (within
// `near`) first, then those they agree with more closely, then the nearest: four rods along a
// plate's edges, each fitted a little off, outvote one read thin. And the block's own sizes
// along the axes in `sized`, growing by at most `grow_limit`.
std::vector<double> face_targets(const PrecedenceGraph& g, const Primitive3D& block, int b, int a, int side,
                                 double near, double until, double grow_limit,
                                 const std::array<bool, 3>& sized) {
  const Face f = face_of(block, a, side);
  std::vector<double> planes, out;
  // Only what the part has: a cut's extent past the material it takes is arbitrary (a hole's
  // cylinder reaches anywhere beyond the block it goes through).
  for (std::size_t j = 0; j < g.nodes.size(); ++j)
    if (static_cast<int>(j) != b && g.nodes[j].positive && !g.nodes[j].conjectured)
      bounding_planes(g.nodes[j].primitive, f.n, planes);
  const double floor = 1e-6 * block.dims[a];  // a plane the face already lies on is no move
  for (double o : planes)
    if (o > f.at + floor && o <= until) out.push_back(o);
  // The block's own sizes: a block as deep as it is wide or tall (a cube seen on two faces),
  // within the limit (a plate seen from above stays a plate), or a hair thinner than its
  // smallest extent (within `near`, the views' own tolerance).
  for (int other = 0; other < 3; ++other) {
    const double grow = block.dims[other] - block.dims[a];
    if (other != a && sized[other] && std::abs(grow) > floor && grow > -near && grow <= grow_limit)
      out.push_back(f.at + grow);
  }
  // How many planes agree (within `near`), then how closely: two rods' lowest line, each
  // within a hair of the other, before a disc's bottom buried in the plate 0.08 above it.
  std::vector<std::tuple<long, double, double>> ranked;  // -count, -closeness, offset
  for (double o : out) {
    long count = 0;
    double closeness = 0;
    for (double q : planes)
      if (std::abs(q - o) <= near) ++count, closeness += 1 - std::abs(q - o) / near;
    ranked.emplace_back(-count, -closeness, o);
  }
  std::sort(ranked.begin(), ranked.end());
  for (std::size_t i = 0; i < ranked.size(); ++i) out[i] = std::get<2>(ranked[i]);
  return out;
}

// Block node `b` with its face (axis a, side) moved inwards by halving steps, each kept while
// the views see no more than `seen`: seed 002's smallest hidden extent, to a sixty-fourth of
// the block, never thinner than `thinnest`.
Primitive3D smallest_extent(const PrecedenceGraph& g, ViewScorer& scorer, int b, int a, int side,
                            double seen, double thinnest) {
  Primitive3D block = g.nodes[static_cast<std::size_t>(b)].primitive;
  const double room = block.dims[a] - thinnest;
  for (double step = room / 2; room > 0 && step >= room / 64; step /= 2) {
    if (block.dims[a] - step < thinnest) continue;
    const Primitive3D moved = with_face_at(block, a, side, face_of(block, a, side).at - step);
    std::vector<double> d = scorer.distances(moved);
    if (scorer.read(g, &d, b).seen <= seen) block = moved;
  }
  return block;
}

// Half the width of `p` along unit `n`: exact for a box, a ball and a cylinder, the bounding
// ball's radius otherwise.
double half_width(const Primitive3D& p, const Vec3& n) {
  const Mat3 r = p.rotation.matrix();
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Box: {
      double w = 0;
      for (int a = 0; a < 3; ++a) w += std::abs(dot(column(r, a), n)) * d[a] / 2;
      return w;
    }
    case PrimitiveKind3D::Sphere: return d[0];
    case PrimitiveKind3D::Cylinder: {
      const double along = std::abs(dot(column(r, 2), n));
      return along * d[2] / 2 + d[0] * std::sqrt(std::max(0.0, 1 - along * along));
    }
    default: return norm(d) + norm(Vec3{d[0], d[1], 0});
  }
}

// Block node `b`'s face (axis a, side) where the designer would have put it: from its smallest
// hidden extent (from where it is, when `put` already) out to the first of face_targets the
// views see no difference in (noise_slack allowed); where none is, the face stays where the
// search left it. The targets reach half the block's size past that, and its own sizes (along
// the axes `sized`) its depth as found past that. True when a view (the face can come no
// further in) or a target put the face, false when it is where the search left it.
bool align_face(PrecedenceGraph& graph, ViewScorer& scorer, const RangeEvidence& evidence, int b, int a,
                int side, double seen, bool put, const std::array<bool, 3>& sized) {
  SignedPrimitive& node = graph.nodes[static_cast<std::size_t>(b)];
  const Primitive3D found = node.primitive;
  const Face f = face_of(found, a, side);
  const double slack = noise_slack(evidence, found, a, side);
  const Primitive3D smallest =
      put ? found : smallest_extent(graph, scorer, b, a, side, seen, 2 * evidence.tolerance);
  const double until = f.at + kReach * found.dims[a];
  for (double to :
       face_targets(graph, smallest, b, a, side, evidence.tolerance, until, found.dims[a], sized)) {
    const Primitive3D moved = with_face_at(smallest, a, side, to);
    std::vector<double> d = scorer.distances(moved);
    if (scorer.read(graph, &d, b).seen > seen + slack) continue;
    node.primitive = moved;
    scorer.set_node(b, std::move(d));
    return true;
  }
  return put || found.dims[a] - smallest.dims[a] <= evidence.tolerance;
}

// Every face of block node `b` aligned (align_face), over again while a pass moves one: a cube
// seen on one face grows one hidden side to its seen width, and only then may the other grow
// to it too (three_cuboids' cube behind its slab stayed half as deep). A face a view or a
// target put grows on from there, its smallest extent not sought again. Own sizes come only
// from axes whose faces a view or a target put (all, until a pass has looked): a side the
// search left long is no designer's size (six_cuboids' cube grew to one).
void align_block(PrecedenceGraph& graph, ViewScorer& scorer, const RangeEvidence& evidence, int b,
                 double seen) {
  constexpr int kPasses = 3;  // a block has three sizes; each pass may settle one more
  std::array<bool, 3> sized{true, true, true};
  std::array<std::array<bool, 2>, 3> put{};  // [axis][side -1, +1]
  for (int pass = 0; pass < kPasses; ++pass) {
    const Vec3 before = graph.nodes[static_cast<std::size_t>(b)].primitive.dims;
    for (std::size_t a = 0; a < 3; ++a) {
      for (std::size_t s = 0; s < 2; ++s)
        put[a][s] = align_face(graph, scorer, evidence, b, static_cast<int>(a), s == 0 ? -1 : 1, seen,
                               put[a][s], sized);
      sized[a] = put[a][0] && put[a][1];
    }
    if (graph.nodes[static_cast<std::size_t>(b)].primitive.dims == before) return;
  }
}

// Positive cylinder node `c`'s end (side) moved out to the nearest face of a block that its
// axis then meets (within `near` of that block): a leg no view sees the top of goes up to the
// underside of the top it carries, a post down to the plate it stands on; within the
// cylinder's own length, when the views see no more than `seen` (noise_slack allowed).
void extend_to_block(PrecedenceGraph& graph, ViewScorer& scorer, const RangeEvidence& evidence, int c, int side,
                     double seen) {
  SignedPrimitive& node = graph.nodes[static_cast<std::size_t>(c)];
  const Primitive3D& leg = node.primitive;
  const Face end = face_of(leg, 2, side);
  const Vec3 centre{leg.cx, leg.cy, leg.cz};
  std::vector<std::pair<double, int>> planes;  // offset along end.n, the block it bounds
  for (std::size_t j = 0; j < graph.nodes.size(); ++j) {
    const SignedPrimitive& other = graph.nodes[j];
    if (static_cast<int>(j) == c || !other.positive || other.conjectured || other.primitive.kind != PrimitiveKind3D::Box)
      continue;
    std::vector<double> offsets;
    bounding_planes(other.primitive, end.n, offsets);
    for (double o : offsets)
      if (o > end.at + 1e-6 * leg.dims[2] && o <= end.at + leg.dims[2]) planes.emplace_back(o, static_cast<int>(j));
  }
  std::sort(planes.begin(), planes.end());
  const double slack = noise_slack(evidence, leg, 2, side);
  for (const auto& [to, block] : planes) {
    const Vec3 landing = add(centre, scale(end.n, to - dot(centre, end.n)));
    const Primitive3D& b = graph.nodes[static_cast<std::size_t>(block)].primitive;
    if (b.signed_distance(landing[0], landing[1], landing[2]) > evidence.tolerance) continue;
    const Primitive3D moved = with_face_at(leg, 2, side, to);
    std::vector<double> d = scorer.distances(moved);
    if (scorer.read(graph, &d, c).seen > seen + slack) continue;
    node.primitive = moved;
    scorer.set_node(c, std::move(d));
    return;
  }
}

// Where along unit `axis` the positive nodes cut by node `cut` begin and end.
std::pair<double, double> cut_span(const PrecedenceGraph& g, int cut, const Vec3& axis) {
  double lo = 1e300, hi = -1e300;
  for (const PrecedenceArc& arc : g.arcs) {
    if (arc.to != cut || arc.kind != ArcKind::Subtracting) continue;
    const Primitive3D& t = g.nodes[static_cast<std::size_t>(arc.from)].primitive;
    const double at = dot(Vec3{t.cx, t.cy, t.cz}, axis), w = half_width(t, axis);
    lo = std::min(lo, at - w), hi = std::max(hi, at + w);
  }
  return {lo, hi};
}

// The face of halfspace box `cut` that faces against `n` (through which it cuts a block whose
// face points along `n`), within kTurn; nullopt when none does.
std::optional<Face> cut_face_against(const Primitive3D& cut, const Vec3& n) {
  for (int c = 0; c < 3; ++c)
    for (int side : {-1, 1}) {
      const Face f = face_of(cut, c, side);
      if (dot(f.n, n) < -kTurn) return f;
    }
  return std::nullopt;
}

// `b` turned about its centre so that unit `from` (one of its axes) points along unit `to`.
Primitive3D turned(Primitive3D b, const Vec3& from, const Vec3& to) {
  const Vec3 axis = cross(from, to);
  const double degrees = std::atan2(norm(axis), dot(from, to)) * 180 / M_PI;
  b.rotation = Quaternion::from_axis_angle(axis[0], axis[1], axis[2], degrees) * b.rotation;
  b.rotation.normalize();
  return b;
}

// Block `b` with the face that halfspace `cut` trims turned parallel to the cut's plane and
// moved onto it, when the plane lies inside the block and the cut then takes that whole face
// (its corners lie inside the cut, or within `near` of it); nullopt otherwise.
std::optional<Primitive3D> face_at_cut(const Primitive3D& b, const Primitive3D& cut, double near) {
  if (b.kind != PrimitiveKind3D::Box) return std::nullopt;
  for (int a = 0; a < 3; ++a)
    for (int side : {-1, 1}) {
      const Vec3 n = face_of(b, a, side).n;
      const auto plane = cut_face_against(cut, n);
      if (!plane) continue;
      const Primitive3D square = turned(b, n, scale(plane->n, -1));
      const Face f = face_of(square, a, side);
      const double at = -plane->at;  // the plane's offset along f.n
      if (!(at < f.at && at > f.at - b.dims[a])) continue;
      const Mat3 r = square.rotation.matrix();
      const Vec3 centre = add(Vec3{square.cx, square.cy, square.cz}, scale(f.n, b.dims[a] / 2));
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      bool covered = true;
      for (int su : {-1, 1})
        for (int sv : {-1, 1}) {
          const Vec3 corner = add(centre, add(scale(column(r, u), su * b.dims[u] / 2),
                                              scale(column(r, v), sv * b.dims[v] / 2)));
          covered &= cut.signed_distance(corner[0], corner[1], corner[2]) < near;
        }
      if (covered) return with_face_at(square, a, side, at);
    }
  return std::nullopt;
}

}  // namespace

PrecedenceGraph faces_from_cuts(PrecedenceGraph graph, const RangeEvidence& evidence, double k) {
  // Whole graphs, read afresh: a scorer knows nodes by index, and dropping a cut renumbers them.
  const auto seen_of = [&](const PrecedenceGraph& g) { return ViewScorer(evidence, g.nodes).read(g).seen; };
  double seen = graph.nodes.empty() ? 0 : seen_of(graph);
  for (int h = static_cast<int>(graph.nodes.size()) - 1; h >= 0; --h) {
    const SignedPrimitive& cut = graph.nodes[static_cast<std::size_t>(h)];
    if (cut.positive || !cut.halfspace || cut.primitive.kind != PrimitiveKind3D::Box) continue;
    PrecedenceGraph trial = graph;
    bool every = true;
    for (const PrecedenceArc& arc : graph.arcs) {
      if (arc.to != h || arc.kind != ArcKind::Subtracting) continue;
      const auto moved = face_at_cut(graph.nodes[static_cast<std::size_t>(arc.from)].primitive, cut.primitive,
                                     evidence.tolerance);
      every &= moved.has_value();
      if (moved) trial.nodes[static_cast<std::size_t>(arc.from)].primitive = *moved;
    }
    if (!every) continue;
    trial = without_node(trial, h);
    const double trial_seen = seen_of(trial);
    if (trial_seen > seen + kSeenSlack * k) continue;
    graph = std::move(trial);
    seen = trial_seen;
  }
  return graph;
}

// Where face `f` of block cut `cut` goes to leave no skin: `margin` past the face, parallel to
// it, of a positive it is subtracted from that it stops short of, or passes, by less than
// `margin` (a cut drawn to a block's face and read a hair inside leaves a sheet that OpenSCAD
// and OCCT render, and a view sees as a silhouette); nullopt when it leaves none.
std::optional<double> past_skins(const PrecedenceGraph& g, int cut, const Face& f, double margin) {
  std::optional<double> to;
  for (const PrecedenceArc& arc : g.arcs) {
    if (arc.to != cut || arc.kind != ArcKind::Subtracting) continue;
    std::vector<double> planes;
    bounding_planes(g.nodes[static_cast<std::size_t>(arc.from)].primitive, f.n, planes);
    if (planes.empty()) continue;
    const double far = *std::max_element(planes.begin(), planes.end());
    if (std::abs(f.at - far) < margin && (!to || *to < far + margin)) to = far + margin;
  }
  return to;
}

// Each face of block cut `c` moved past the skins it leaves (past_skins), when the views see
// no more than `slack` of difference from the graph's reading `seen` as it came.
void clear_skins_of(PrecedenceGraph& graph, int c, ViewScorer& scorer, double seen, double margin,
                    double slack) {
  for (int a = 0; a < 3; ++a)
    for (int side : {-1, 1}) {
      const Primitive3D& cut = graph.nodes[static_cast<std::size_t>(c)].primitive;
      const Face f = face_of(cut, a, side);
      const std::optional<double> to = past_skins(graph, c, f, margin);
      if (!to || *to <= f.at) continue;
      const Primitive3D cleared = with_face_at(cut, a, side, *to);
      std::vector<double> d = scorer.distances(cleared);
      if (scorer.read(graph, &d, c).seen > seen + slack) continue;
      graph.nodes[static_cast<std::size_t>(c)].primitive = cleared;
      scorer.set_node(c, std::move(d));
    }
}

PrecedenceGraph holes_through(PrecedenceGraph graph, const RangeEvidence& evidence) {
  if (evidence.hidden.empty() || graph.nodes.empty()) return graph;
  ViewScorer scorer(evidence, graph.nodes);
  const double seen = scorer.read(graph).seen;
  const double margin = evidence.tolerance;
  for (std::size_t h = 0; h < graph.nodes.size(); ++h) {
    SignedPrimitive& hole = graph.nodes[h];
    if (hole.positive) continue;
    // A cylinder's ends are its faces along local z; a pocket's every face may be a floor (a
    // pocket read off the silhouette is conjectured, and goes through as well).
    const bool pocket = hole.primitive.kind == PrimitiveKind3D::Box;
    if (!pocket && (hole.conjectured || hole.primitive.kind != PrimitiveKind3D::Cylinder)) continue;
    for (int a = pocket ? 0 : 2; a < 3; ++a)
      for (int side : {-1, 1}) {
        const Face end = face_of(hole.primitive, a, side);
        const auto [lo, hi] = cut_span(graph, static_cast<int>(h), end.n);
        if (lo > hi || end.at >= hi + margin) continue;
        const Primitive3D through = with_face_at(hole.primitive, a, side, hi + margin);
        std::vector<double> d = scorer.distances(through);
        if (scorer.read(graph, &d, static_cast<int>(h)).seen > seen) continue;
        hole.primitive = through;
        scorer.set_node(static_cast<int>(h), std::move(d));
      }
  }
  return graph;
}

PrecedenceGraph clear_skins(PrecedenceGraph graph, const RangeEvidence& evidence, double k) {
  if (graph.nodes.empty()) return graph;
  ViewScorer scorer(evidence, graph.nodes);
  const double seen = scorer.read(graph).seen;
  // The surface samples a skin held where the cut's walls overlap a seen face, read a hair
  // off, may go: within kSeenSlack of k, as faces_from_cuts allows.
  for (std::size_t c = 0; c < graph.nodes.size(); ++c)
    if (!graph.nodes[c].positive && graph.nodes[c].primitive.kind == PrimitiveKind3D::Box)
      clear_skins_of(graph, static_cast<int>(c), scorer, seen, evidence.tolerance, kSeenSlack * k);
  return graph;
}

PrecedenceGraph align_hidden_faces(PrecedenceGraph graph, const RangeEvidence& evidence) {
  if (evidence.hidden.empty() || graph.nodes.empty()) return graph;
  ViewScorer scorer(evidence, graph.nodes);
  // Against the graph as it came, and without the other changes' slack: a thin block's face
  // moved up across a seen surface covers too few samples to cost a quarter of k.
  const double seen = scorer.read(graph).seen;
  for (std::size_t b = 0; b < graph.nodes.size(); ++b) {
    const SignedPrimitive& node = graph.nodes[b];
    if (!node.positive || node.conjectured) continue;
    if (node.primitive.kind == PrimitiveKind3D::Box)
      align_block(graph, scorer, evidence, static_cast<int>(b), seen);
    if (node.primitive.kind == PrimitiveKind3D::Cylinder)
      for (int side : {-1, 1}) extend_to_block(graph, scorer, evidence, static_cast<int>(b), side, seen);
  }
  return graph;
}

}  // namespace csgfit
