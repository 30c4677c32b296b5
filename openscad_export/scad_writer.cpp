#include "scad_writer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/model/shared_dimensions.h"
#include "scad_format.h"
#include "scad_tree_writer.h"

namespace csgfit {

namespace {

// The writers' shared helpers (scad_format.h, scad_tree_writer.h).
using namespace scad;


class Writer : public TreeWriter<Writer, Node> {
 public:
  /// `morph_end`: this tree is one end of a morph, so every size may be 0 and every turnable
  /// primitive is written with its rotate(), as at the other end.
  Writer(const ModelFrame& frame, int decimals, double extent, bool morph_end)
      : frame_(frame), decimals_(decimals), extent_(extent), morph_end_(morph_end) {}

  std::string primitive(const Primitive& p);

 private:
  friend class TreeWriter<Writer, Node>;

  // `prefix_field`, or the shared parameter that stands for it.
  std::string dimension(Tab& tab, const Primitive& p, DimensionField f, const std::string& prefix,
                        double v, const std::string& range) {
    if (const std::string* name = shared_name(p, f)) return *name;
    return add(tab, prefix, std::string(field_name(f)).c_str(), v, range, decimals_);
  }

  static std::string plural(PrimitiveKind k) {
    switch (k) {
      case PrimitiveKind::Rectangle: return "rectangles";
      case PrimitiveKind::Circle: return "circles";
      case PrimitiveKind::Ellipse: return "ellipses";
      case PrimitiveKind::Triangle: return "triangles";
    }
    return "primitives";
  }
  int decimals() const { return decimals_; }

  // Checks one solver value and converts it to model units.
  double model(double v, double scale, const char* what, const std::string& prim) const {
    const double m = v * scale;
    if (!std::isfinite(v) || !std::isfinite(m) || std::fabs(m) > kMaxMagnitude)
      throw InputError("cannot write .scad: " + prim + " has a non-finite or out-of-range " +
                       what);
    return m;
  }

  std::string length_range(double v) const {
    const double hi = nice_ceiling(std::max(extent_, std::fabs(v)));
    return "[0:" + number(step(), 12) + ":" + number(hi, 12) + "]";
  }
  std::string position_range(double v) const {
    const double hi = nice_ceiling(std::max(extent_, std::fabs(v)));
    const double lo = v < 0 ? -hi : 0;
    return "[" + number(lo, 12) + ":" + number(step(), 12) + ":" + number(hi, 12) + "]";
  }
  static std::string angle_range(double a) {
    return a < 0 ? "[-360:0.1:360]" : "[0:0.1:360]";
  }
  // About a thousandth of the drawing's size, so a slider has ~1000 useful positions.
  double step() const { return slider_step(extent_); }

  const ModelFrame& frame_;
  int decimals_;
  double extent_;
  bool morph_end_;
};

std::string Writer::primitive(const Primitive& p) {
  ++count_;
  numbered(p);
  const std::string num = std::to_string(count_);
  const double s = frame_.pixel_size;
  std::string prefix, title;
  switch (p.kind) {
    case PrimitiveKind::Rectangle: prefix = "rect_" + num, title = "Rectangle " + num; break;
    case PrimitiveKind::Circle: prefix = "circle_" + num, title = "Circle " + num; break;
    case PrimitiveKind::Ellipse: prefix = "ellipse_" + num, title = "Ellipse " + num; break;
    case PrimitiveKind::Triangle: prefix = "tri_" + num, title = "Triangle " + num; break;
  }
  const std::string what = "primitive " + num + " (" + std::string(to_string(p.kind)) + ")";
  const double cx = model(p.cx, s, "centre x", what);
  const double cy = model(p.cy, s, "centre y", what);
  const double w = model(p.w, s, "width", what);
  const double h = model(p.h, s, "height", what);
  const double angle = model(p.angle, 1, "angle", what);
  const double apex = model(p.apex, 1, "apex", what);
  const bool sized = morph_end_ ? (w >= 0 && h >= 0) : (w > 0 && h > 0);
  if (!sized) throw InputError("cannot write .scad: " + what + " has a size <= 0");

  Tab tab{title, {}};
  const int d = decimals_;
  const std::string vx = dimension(tab, p, DimensionField::CentreX, prefix, cx, position_range(cx));
  const std::string vy = dimension(tab, p, DimensionField::CentreY, prefix, cy, position_range(cy));
  const std::string at = "translate([" + vx + ", " + vy + "]) ";
  // A zero angle is left out: a hand-written file would not rotate by 0 either.
  const bool rotated = (morph_end_ || number(angle, 4) != "0") && p.kind != PrimitiveKind::Circle;
  std::string rot;
  std::string code;
  switch (p.kind) {
    case PrimitiveKind::Rectangle: {
      const std::string vw = dimension(tab, p, DimensionField::Width, prefix, w, length_range(w));
      const std::string vh = dimension(tab, p, DimensionField::Height, prefix, h, length_range(h));
      if (rotated) rot = "rotate(" + add(tab, prefix, "angle", angle, angle_range(angle), 4) + ") ";
      code = at + rot + "square([" + vw + ", " + vh + "], center = true);";
      break;
    }
    case PrimitiveKind::Circle: {
      const std::string vr =
          dimension(tab, p, DimensionField::Radius, prefix, w / 2, length_range(w / 2));
      code = at + "circle(r = fn_r(" + vr + "));";
      break;
    }
    case PrimitiveKind::Ellipse: {
      const std::string vrx = add(tab, prefix, "rx", w / 2, length_range(w / 2), d);
      const std::string vry = add(tab, prefix, "ry", h / 2, length_range(h / 2), d);
      if (rotated) rot = "rotate(" + add(tab, prefix, "angle", angle, angle_range(angle), 4) + ") ";
      code = at + rot + "scale([" + vrx + ", " + vry + "]) circle(r = fn_r(1));";
      break;
    }
    case PrimitiveKind::Triangle: {
      const std::string vw = add(tab, prefix, "w", w, length_range(w), d);
      const std::string vh = add(tab, prefix, "h", h, length_range(h), d);
      if (rotated) rot = "rotate(" + add(tab, prefix, "angle", angle, angle_range(angle), 4) + ") ";
      // The apex offset is relative to the half width, so it needs more decimals than a
      // length to land within the same fraction of a pixel.
      const std::string va = add(tab, prefix, "apex", apex, "[-4:0.01:4]", 6);
      code = at + rot + "polygon([[-" + vw + " / 2, -" + vh + " / 2], [" + vw + " / 2, -" + vh +
             " / 2], [" + va + " * " + vw + " / 2, " + vh + " / 2]]);";
      break;
    }
  }
  if (!tab.vars.empty()) tabs_.push_back(std::move(tab));
  return code;
}


// The file for `tree`, or for the morph from `tree` to `*morph_b` (same structure).
std::string scad_text(const Node& tree, const ModelFrame& frame, const ScadOptions& options,
                      const FitStats* stats, const Node* morph_b, const std::string& source_b) {
  if (!std::isfinite(frame.pixel_size) || !(frame.pixel_size > 0) ||
      frame.pixel_size > kMaxMagnitude)
    throw InputError("cannot write .scad: pixel size must be a positive finite number");
  if (!std::isfinite(frame.thickness) || frame.thickness < 0 || frame.thickness > kMaxMagnitude)
    throw InputError("cannot write .scad: thickness must be a finite number >= 0");
  if (options.fn < 3 || options.fn > 10000)
    throw InputError("cannot write .scad: $fn must be between 3 and 10000");
  if (tree.primitive_count() == 0 || is_empty(tree))
    throw InputError("cannot write .scad: the tree has no primitives");

  // Enough decimals that rounding moves an edge by at most a thousandth of a pixel (so the
  // rendering agrees with the solver's raster at pixel centres), and at least 4.
  const int decimals =
      std::clamp(static_cast<int>(std::ceil(3.0 - std::log10(frame.pixel_size))), 4, 12);

  // Slider ranges cover the canvas the shape came from.
  double extent = 0;
  for (const Node* t : {&tree, morph_b})
    if (t)
      for (const Primitive* p : leaves(*t))
        extent = std::max({extent, std::fabs(p->cx) + p->w, std::fabs(p->cy) + p->h});
  extent = std::max({extent, static_cast<double>(options.width_px),
                     static_cast<double>(options.height_px)});
  extent *= frame.pixel_size;

  Writer writer(frame, decimals, extent, morph_b != nullptr);
  // A morph's two ends share only what both share; not worth the file's complexity.
  if (!morph_b) writer.share(tree);
  const std::string body = writer.geometry(tree, 1);
  std::vector<Tab> tabs_b;
  if (morph_b) {
    Writer other(frame, decimals, extent, true);
    if (other.geometry(*morph_b, 1) != body)
      throw InputError("cannot write .scad: the two trees of the morph differ in structure");
    tabs_b = other.tabs();
  }
  const std::string module = identifier(frame.source, "shape");

  std::ostringstream out;
  out << "// Generated by csgfit";
  if (!frame.source.empty()) {
    out << " from " << comment_safe(frame.source);
    if (morph_b) out << " (morph = 0) and " << comment_safe(source_b) << " (morph = 1)";
  }
  out << "\n";
  if (options.width_px > 0 && options.height_px > 0)
    out << "// Canvas: " << options.width_px << " x " << options.height_px << " px at "
        << number(frame.pixel_size, 9) << " mm per pixel = [0, "
        << number(options.width_px * frame.pixel_size, decimals) << "] x [0, "
        << number(options.height_px * frame.pixel_size, decimals) << "] mm, y up.\n";
  else
    out << "// Units: mm, y up; pixel size " << number(frame.pixel_size, 9) << " mm.\n";
  // Statistics without primitives were never filled in (a hand-written tree): leave them out.
  if (stats && stats->primitives > 0) {
    if (!std::isfinite(stats->iou) || !std::isfinite(stats->score))
      throw InputError("cannot write .scad: the fit statistics are not finite");
    out << "// Fit" << (morph_b ? " of A" : "") << ": IoU " << number(stats->iou, 4) << ", "
        << stats->primitives << " primitives, score " << number(stats->score, 2) << ".\n";
  }
  out << "// Every dimension below is a Customizer parameter (Window > Customizer).\n\n";

  if (morph_b) write_morph_slider(out, frame.source, source_b);
  write_resolution(out, options.fn);
  if (frame.thickness > 0) {
    out << "/* [Extrusion] */\n";
    out << "thickness = " << number(frame.thickness, decimals) << "; // [0:"
        << number(slider_step(std::max(frame.thickness, extent)), 12) << ":"
        << number(nice_ceiling(std::max(frame.thickness * 2, 1.0)), 6) << "]\n\n";
  }
  if (morph_b)
    write_morph_tabs(out, writer.tabs(), tabs_b);
  else {
    const Tab shared = writer.shared_tab(frame.pixel_size);
    if (!shared.vars.empty()) write_tabs(out, {shared});
    write_tabs(out, writer.tabs());
  }
  out << "/* [Hidden] */\n";
  out << "// Pixel size of the source image in mm; the dimensions above are already in mm.\n";
  out << "pixel_size = " << number(frame.pixel_size, 9) << ";\n";
  out << "$fn = segments;\n\n";
  if (morph_b) write_morph_values(out, writer.tabs(), tabs_b);
  write_circle_radius(out, options.circle_fit);
  out << "module " << module << "() {\n" << body << "}\n\n";
  if (frame.thickness > 0)
    out << "linear_extrude(height = thickness) " << module << "();\n";
  else
    out << module << "();\n";
  return out.str();
}

}  // namespace

std::string to_scad(const Node& tree, const ModelFrame& frame, const ScadOptions& options,
                    const FitStats* stats) {
  return scad_text(tree, frame, options, stats, nullptr, {});
}

std::string to_scad_morph(const Node& a, const Node& b, const ModelFrame& frame,
                          const std::string& source_b, const ScadOptions& options,
                          const FitStats* stats_a) {
  return scad_text(a, frame, options, stats_a, &b, source_b);
}

}  // namespace csgfit
