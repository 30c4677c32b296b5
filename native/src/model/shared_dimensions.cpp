#include "csgfit/model/shared_dimensions.h"

#include <algorithm>
#include <functional>
#include <initializer_list>
#include <map>
#include <optional>
#include <utility>

namespace csgfit {

namespace {

template <typename P>
void mark_subtracted(const CsgNode<P>& n, bool subtracted, std::vector<bool>& out) {
  if (n.kind == NodeKind::Primitive) {
    out.push_back(subtracted);
    return;
  }
  for (std::size_t i = 0; i < n.children.size(); ++i) {
    const bool cut = n.kind == NodeKind::Difference && i > 0;
    mark_subtracted(n.children[i], subtracted != cut, out);
  }
}

bool is_round(PrimitiveKind k) { return k == PrimitiveKind::Circle || k == PrimitiveKind::Ellipse; }

// Uses grouped by a key; groups of one are dropped, the rest ordered by their first use so that
// names follow the order of the file.
template <typename Key, typename P, typename KeyOf>
std::vector<std::vector<DimensionUse>> equal_groups(
    const std::vector<const P*>& ls, std::initializer_list<DimensionField> fields, KeyOf key_of,
    const std::function<bool(const DimensionUse&)>& drawn = {}) {
  std::map<Key, std::vector<DimensionUse>> by_key;
  for (std::size_t i = 0; i < ls.size(); ++i)
    for (DimensionField f : fields)
      if (auto key = key_of(*ls[i], f); key && (!drawn || drawn({i, f})))
        by_key[*key].push_back({i, f});
  std::vector<std::vector<DimensionUse>> groups;
  for (auto& [key, members] : by_key)
    if (members.size() > 1) groups.push_back(std::move(members));
  std::sort(groups.begin(), groups.end());
  return groups;
}

// "hole_r", then "hole_r2", "hole_r3": one name per group of the same base.
class Names {
 public:
  std::string next(const std::string& base) {
    const int n = ++used_[base];
    return n > 1 ? base + std::to_string(n) : base;
  }

 private:
  std::map<std::string, int> used_;
};

}  // namespace

std::string_view field_name(DimensionField field) {
  switch (field) {
    case DimensionField::CentreX: return "cx";
    case DimensionField::CentreY: return "cy";
    case DimensionField::Width: return "w";
    case DimensionField::Height: return "h";
    case DimensionField::Radius: return "r";
    case DimensionField::Length: return "h";
  }
  return "?";
}

double field_value(const Primitive& p, DimensionField field) {
  switch (field) {
    case DimensionField::CentreX: return p.cx;
    case DimensionField::CentreY: return p.cy;
    case DimensionField::Width: return p.w;
    case DimensionField::Height: return p.h;
    case DimensionField::Radius: return 0.5 * p.w;
    case DimensionField::Length: return 0;
  }
  return 0;
}

double field_value(const Primitive3D& p, DimensionField field) {
  switch (field) {
    case DimensionField::CentreX: return p.cx;
    case DimensionField::CentreY: return p.cy;
    case DimensionField::Radius: return p.dims[0];
    case DimensionField::Length: return p.dims[2];
    case DimensionField::Width:
    case DimensionField::Height: return 0;
  }
  return 0;
}

template <typename P>
std::vector<bool> subtracted_leaves(const CsgNode<P>& tree) {
  std::vector<bool> out;
  mark_subtracted(tree, false, out);
  return out;
}

template std::vector<bool> subtracted_leaves(const Node&);
template std::vector<bool> subtracted_leaves(const Node3D&);

std::vector<SharedDimension> shared_dimensions(const Node& tree) {
  const std::vector<const Primitive*> ls = leaves(tree);
  const std::vector<bool> holes = subtracted_leaves(tree);
  std::vector<SharedDimension> out;
  Names names;
  // A concentric set is one centre point: its x and y are named together.
  using Point = std::pair<double, double>;
  for (const auto& g : equal_groups<Point>(ls, {DimensionField::CentreX}, [](const Primitive& p, auto) {
         return is_round(p.kind) ? std::optional<Point>({p.cx, p.cy}) : std::nullopt;
       })) {
    const std::string centre = names.next("centre");
    SharedDimension x{centre + "_x", g}, y{centre + "_y", g};
    for (DimensionUse& u : y.uses) u.field = DimensionField::CentreY;
    out.push_back(std::move(x));
    out.push_back(std::move(y));
  }
  for (auto& g : equal_groups<double>(ls, {DimensionField::Radius}, [](const Primitive& p, auto) {
         return p.kind == PrimitiveKind::Circle ? std::optional<double>(p.w) : std::nullopt;
       })) {
    const bool all_holes =
        std::all_of(g.begin(), g.end(), [&](const DimensionUse& u) { return holes[u.leaf]; });
    out.push_back({names.next(all_holes ? "hole_r" : "circle_r"), std::move(g)});
  }
  for (auto& g : equal_groups<double>(
           ls, {DimensionField::Width, DimensionField::Height},
           [](const Primitive& p, DimensionField f) {
             return p.kind == PrimitiveKind::Rectangle ? std::optional<double>(field_value(p, f))
                                                       : std::nullopt;
           }))
    out.push_back({names.next("rect_side"), std::move(g)});
  return out;
}

std::vector<SharedDimension> shared_dimensions(const Node3D& tree) {
  return shared_dimensions(tree, {});
}

std::vector<SharedDimension> shared_dimensions(
    const Node3D& tree, const std::function<bool(const DimensionUse&)>& drawn) {
  const std::vector<const Primitive3D*> ls = leaves(tree);
  const std::vector<bool> holes = subtracted_leaves(tree);
  auto all = [&](const std::vector<DimensionUse>& g, auto pred) {
    return std::all_of(g.begin(), g.end(), [&](const DimensionUse& u) { return pred(u.leaf); });
  };
  auto cylinder = [&](std::size_t i) { return ls[i]->kind == PrimitiveKind3D::Cylinder; };
  auto sphere = [&](std::size_t i) { return ls[i]->kind == PrimitiveKind3D::Sphere; };
  auto hole = [&](std::size_t i) { return holes[i]; };
  std::vector<SharedDimension> out;
  Names names;
  for (auto& g : equal_groups<double>(ls, {DimensionField::Radius}, [](const Primitive3D& p, auto) {
         // A polygon's circumradius is not a circle's radius (nor drawn as one: no fn_r).
         const bool round =
             (p.kind == PrimitiveKind3D::Cylinder || p.kind == PrimitiveKind3D::Sphere) &&
             !p.is_polygonal();
         return round ? std::optional<double>(p.dims[0]) : std::nullopt;
       }, drawn)) {
    const char* base = all(g, sphere) ? "sphere_r" : !all(g, cylinder) ? "round_r"
                       : all(g, hole)  ? "hole_r" : "cyl_r";
    out.push_back({names.next(base), std::move(g)});
  }
  for (auto& g : equal_groups<double>(ls, {DimensionField::Length}, [](const Primitive3D& p, auto) {
         return p.kind == PrimitiveKind3D::Cylinder ? std::optional<double>(p.dims[2]) : std::nullopt;
       }, drawn))
    out.push_back({names.next(all(g, hole) ? "hole_h" : "cyl_h"), std::move(g)});
  return out;
}

}  // namespace csgfit
