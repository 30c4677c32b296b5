#include "csgfit/model/tree2d.h"

#include "model/tree_impl.h"

namespace csgfit {

INSTANTIATE_CSG_TREE(Primitive);

std::string_view to_string(NodeKind kind) {
  switch (kind) {
    case NodeKind::Primitive: return "primitive";
    case NodeKind::Union: return "union";
    case NodeKind::Difference: return "difference";
    case NodeKind::Intersection: return "intersection";
  }
  return "?";
}

Bitmap render(const Node& root, int width, int height) {
  Bitmap out(width, height);
  tree_walk::render_into(root, out);
  return out;
}

}  // namespace csgfit
