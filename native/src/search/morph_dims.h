// Internal to search/: how each dimension proposes the primitives of a morph's pair search
// (morph_operators.h): the single-tree operators of 2D (operators2d.h) and 3D (operators3d.h)
// behind one set of names.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/eval/evaluator3d.h"
#include "csgfit/optimise/snap2d.h"
#include "search/operators2d.h"
#include "search/operators3d.h"

namespace csgfit::morph {

/// The 2D pair search: seed 000's REP replaces a subtree with a random one, ADD grafts a
/// subtree at peaks of one target's distance map.
struct Dim2D {
  using Ops = Operators2D;
  using Problem = Problem2D;
  using Single = Candidate2D;
  using Tree = Node;
  using Prim = Primitive;
  using Evaluator = TreeEvaluator;
  static constexpr bool random_trees = true;  // seed 000's random first trees

  /// Boundaries moved off pixel centres (same raster), so that rounding the written values
  /// cannot flip a pixel (as the single fit's polish does).
  static void untie_edges(const Problem& pb, Tree& t) {
    TreeEvaluator ev(*pb.target, t);
    untie(ev);
  }
  static Bitmap raster(const Problem& pb, const Tree& t) {
    return render(t, pb.target->width(), pb.target->height());
  }
  /// Zero size at the partner's centroid (the centre of every kind but the triangle).
  static Prim vanished(const Prim& partner) {
    Prim p = partner;
    if (p.kind == PrimitiveKind::Triangle) {
      const auto v = partner.triangle_vertices();
      p.cx = (v[0][0] + v[1][0] + v[2][0]) / 3;
      p.cy = (v[0][1] + v[1][1] + v[2][1]) / 3;
    }
    p.w = p.h = 0;
    return p;
  }

  static const std::vector<PrimitiveKind>& kinds(const Problem& pb) { return pb.kinds; }

  static Tree random_subtree(Ops& x, int count, std::vector<Prim>& fresh) {
    return x.random_subtree(count, fresh);
  }
  static bool added(Ops& x, const Single&, bool as_union, Tree& added, std::vector<Prim>& fresh) {
    return x.added_subtree(as_union, added, fresh);
  }
  static bool trimming(Ops&, Prim&) { return false; }  // INT is a 3D operator
  static Prim rekinded(Ops& x, const Prim& p, PrimitiveKind kind) { return x.rekinded(p, kind); }

  static std::size_t rep_point(rnd::Rng& rng, const Tree& t) { return rnd::pick(rng, t.node_count()); }
  static Tree replacement(Ops& x, rnd::Rng& rng, const Tree& old, const SearchParams& params,
                          std::vector<Prim>& fresh) {
    const int e = static_cast<int>(old.primitive_count());
    return x.random_subtree(rnd::norm_count(rng, e, params.added_size_sd), fresh);
  }

  static Single evaluate(Ops& x, Tree tree, const std::vector<Prim>& fresh) {
    return x.evaluate(std::move(tree), fresh, false);
  }
};

/// The 3D pair search: REP gives one leaf another kind and orientation, ADD matches a
/// primitive to one tree's residual, INT trims with a round primitive matched to one target.
struct Dim3D {
  using Ops = Operators3D;
  using Problem = Problem3D;
  using Single = Candidate3D;
  using Tree = Node3D;
  using Prim = Primitive3D;
  using Evaluator = TreeEvaluator3D;
  static constexpr bool random_trees = false;  // 3D starts from seed 003's trees only

  static void untie_edges(const Problem&, Tree&) {}  // the 3D writer's decimals suffice
  static VoxelGrid raster(const Problem& pb, const Tree& t) { return render(t, *pb.target); }
  /// Zero size at the partner's centre (inside every kind; a prism's is on its triangle's
  /// mid-line, inside for the apex offsets the search uses).
  static Prim vanished(const Prim& partner) {
    Prim p = partner;
    p.dims = {0, 0, 0};
    return p;
  }

  static const std::vector<PrimitiveKind3D>& kinds(const Problem& pb) { return pb.kinds; }

  static bool added(Ops& x, const Single& parent, bool as_union, Tree& added,
                    std::vector<Prim>& fresh) {
    const std::optional<Prim> match = x.residual_match(parent.result, as_union);
    if (!match) return false;
    added = Tree::leaf(*match);
    fresh.push_back(*match);
    return true;
  }
  static bool trimming(Ops& x, Prim& hull) {
    const std::optional<Prim> h = x.trimming_hull();
    if (h) hull = *h;
    return h.has_value();
  }
  static Prim rekinded(Ops&, const Prim& p, PrimitiveKind3D kind) { return Ops::rekinded(p, kind); }

  static std::size_t rep_point(rnd::Rng& rng, const Tree& t) {
    std::vector<std::size_t> at;
    for_each_node(t, [&](const Tree& n, std::size_t i) {
      if (n.is_leaf()) at.push_back(i);
    });
    return at[rnd::pick(rng, at.size())];
  }
  static Tree replacement(Ops& x, rnd::Rng&, const Tree& old, const SearchParams&,
                          std::vector<Prim>& fresh) {
    const Prim p = x.changed_kind(old.primitive, true);
    fresh.push_back(p);
    return Tree::leaf(p);
  }

  static Single evaluate(Ops& x, Tree tree, const std::vector<Prim>& fresh) {
    // A cut changes no primitive: its neighbours get a short polish instead (as in 3D fits).
    return x.evaluate(std::move(tree), fresh, fresh.empty());
  }
};

}  // namespace csgfit::morph
