// Internal to openscad_export/: what the 2D and 3D .scad writers write the same way: the tree's
// geometry as nested blocks, the Customizer parameters (one tab per primitive), and the parts
// of the file around them.
#pragma once

#include <algorithm>
#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "csgfit/model/shared_dimensions.h"
#include "csgfit/model/tree.h"
#include "scad_format.h"
#include "scad_writer.h"

namespace csgfit::scad {

/// One Customizer parameter: `name = value; // range`, after `// description` when there is one.
struct Var {
  std::string name, value, range, description;
};

/// A Customizer tab: the parameters of one primitive.
struct Tab {
  std::string title;
  std::vector<Var> vars;
};

/// "circles 3 and 4", "cylinders 1, 6 and 7": the primitives a shared dimension stands for.
std::string users_text(std::vector<int> numbers, const std::string& kinds);

/// What a shared dimension is, for its comment: "radius", "centre x", "side" (of rectangles).
std::string shared_title(DimensionField field, bool rectangles);

/// Writes a tree's geometry: unions and intersections flattened, the subtracted unions of a
/// difference inlined (a - (b + c) = a - b - c), empty subtrees left out, one line per
/// primitive as `Derived::primitive(const P&)` writes it (which adds the primitive's tab and
/// calls numbered()). Dimensions shared by several primitives (share()) are written once, in a
/// tab of their own (shared_tab()), and used by name.
template <typename Derived, typename NodeT>
class TreeWriter {
  using P = std::decay_t<decltype(NodeT::primitive)>;

 public:
  /// Names each of the tree's shared dimensions once (shared_dimensions.h).
  void share(const NodeT& tree) { share(tree, shared_dimensions(tree)); }
  /// Names each of `dims` (shared dimensions of `tree`) once.
  void share(const NodeT& tree, const std::vector<SharedDimension>& dims) {
    const std::vector<const P*> ls = leaves(tree);
    for (const SharedDimension& d : dims) {
      for (const DimensionUse& u : d.uses) shared_[{ls[u.leaf], u.field}] = d.name;
      shared_list_.push_back({d, ls[d.uses.front().leaf]});
    }
  }

  /// The tab of the shared dimensions, values times `scale`, with a comment naming the
  /// primitives that use each (after geometry(), which numbers them).
  Tab shared_tab(double scale) const {
    Tab tab{"Shared dimensions", {}};
    const auto& self = *static_cast<const Derived*>(this);
    for (const auto& entry : shared_list_) {
      // Not structured bindings: clang 14 cannot capture them in the lambda below.
      const SharedDimension& d = entry.first;
      const P* first = entry.second;
      const DimensionField field = d.uses.front().field;
      const double v = field_value(*first, field) * scale;
      const bool position = field == DimensionField::CentreX || field == DimensionField::CentreY;
      std::vector<int> users;
      bool same_kind = true;
      for (const auto& [p, n] : numbers_) {
        const bool uses = std::any_of(d.uses.begin(), d.uses.end(), [&, p = p](const auto& u) {
          const auto it = shared_.find({p, u.field});
          return it != shared_.end() && it->second == d.name;
        });
        if (!uses) continue;
        users.push_back(n);
        same_kind = same_kind && p->kind == first->kind;
      }
      const std::string kinds = same_kind ? Derived::plural(first->kind) : "primitives";
      tab.vars.push_back({d.name, number(v, self.decimals()),
                          position ? self.position_range(v) : self.length_range(v),
                          shared_title(field, kinds == "rectangles") + " of " +
                              users_text(users, kinds)});
    }
    return tab;
  }

  std::string geometry(const NodeT& n, int indent) {
    Derived& self = *static_cast<Derived*>(this);
    if (self.writes_whole(n)) return self.whole(n, indent);
    const std::string pad(static_cast<std::size_t>(indent) * 2, ' ');
    auto keep_whole = [&self](const NodeT& c) { return self.writes_whole(c); };
    switch (n.kind) {
      case NodeKind::Primitive:
        return pad + self.primitive(n.primitive) + "\n";
      case NodeKind::Union:
      case NodeKind::Intersection: {
        std::vector<const NodeT*> kids;
        collect_flat(n, n.kind, kids, keep_whole);
        if (kids.size() == 1) return geometry(*kids.front(), indent);
        return block(n.kind == NodeKind::Union ? "union()" : "intersection()", kids, indent);
      }
      case NodeKind::Difference: {
        std::vector<const NodeT*> kids{&n.children.front()};
        for (std::size_t i = 1; i < n.children.size(); ++i) {
          const NodeT& c = n.children[i];
          if (is_empty(c)) continue;
          if (c.kind == NodeKind::Union && !self.writes_whole(c))
            collect_flat(c, NodeKind::Union, kids, keep_whole);
          else
            kids.push_back(&c);
        }
        if (kids.size() == 1) return geometry(*kids.front(), indent);
        return block("difference()", kids, indent);
      }
    }
    return {};
  }

  const std::vector<Tab>& tabs() const { return tabs_; }

 protected:
  // Derived may write a subtree its own way, as one block that is never flattened into its
  // parent (the 3D writer's sweeps), by hiding these two: whether it does for n, and the
  // lines it writes then.
  bool writes_whole(const NodeT&) const { return false; }
  std::string whole(const NodeT&, int) { return {}; }

  /// Adds `prefix_field = v` to the tab and returns the variable's name.
  static std::string add(Tab& tab, const std::string& prefix, const char* field, double v,
                         const std::string& range, int decimals) {
    const std::string name = prefix + "_" + field;
    tab.vars.push_back({name, number(v, decimals), range, {}});
    return name;
  }

  /// The shared parameter that stands for p's `field`, or nullptr.
  const std::string* shared_name(const P& p, DimensionField field) const {
    const auto it = shared_.find({&p, field});
    return it == shared_.end() ? nullptr : &it->second;
  }

  /// Records p's number in the file (count_), for the shared tab's comments.
  void numbered(const P& p) { numbers_[&p] = count_; }

  int count_ = 0;  // primitives written so far: the number in their names
  std::vector<Tab> tabs_;

 private:
  std::map<std::pair<const P*, DimensionField>, std::string> shared_;
  std::vector<std::pair<SharedDimension, const P*>> shared_list_;
  std::map<const P*, int> numbers_;

 private:
  std::string block(const std::string& head, const std::vector<const NodeT*>& kids, int indent) {
    const std::string pad(static_cast<std::size_t>(indent) * 2, ' ');
    std::string out = pad + head + " {\n";
    for (const NodeT* k : kids) out += geometry(*k, indent + 1);
    out += pad + "}\n";
    return out;
  }
};

/// The `segments` parameter: the file's $fn, in a tab of its own.
void write_resolution(std::ostream& out, int fn);

/// Every primitive's tab of parameters.
void write_tabs(std::ostream& out, const std::vector<Tab>& tabs);

/// A morph's slider: `morph` (Customizer shows literals only, so its default -1 stands for $t)
/// and `m`, the morph the file draws.
void write_morph_slider(std::ostream& out, const std::string& source_a, const std::string& source_b);

/// A morph's tabs: each primitive's values at both ends (`name_a`, `name_b`), or once where
/// both ends agree.
void write_morph_tabs(std::ostream& out, const std::vector<Tab>& a, const std::vector<Tab>& b);

/// mix() and every value the geometry uses as a mix of its two ends (after write_morph_tabs).
void write_morph_values(std::ostream& out, const std::vector<Tab>& a, const std::vector<Tab>& b);

/// fn_r(r): the radius a circle of radius r is drawn with as OpenSCAD's $fn-gon.
void write_circle_radius(std::ostream& out, CircleFit fit);

}  // namespace csgfit::scad
