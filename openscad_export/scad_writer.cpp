#include "scad_format.h"
#include "scad_writer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "csgfit/error.h"

namespace csgfit {

namespace {

using scad::collect_flat;
using scad::comment_safe;
using scad::is_empty;
using scad::kMaxMagnitude;
using scad::nice_ceiling;
using scad::slider_step;

std::string fmt(double v, int decimals) { return scad::number(v, decimals); }
std::string sanitize_identifier(const std::string& source) {
  return scad::identifier(source, "shape");
}

struct Var {
  std::string name;
  std::string value;
  std::string range;  // Customizer comment, e.g. "[0:0.01:100]"
};

struct Tab {
  std::string title;
  std::vector<Var> vars;
};

class Writer {
 public:
  Writer(const ModelFrame& frame, int decimals, double extent)
      : frame_(frame), decimals_(decimals), extent_(extent) {}

  std::string geometry(const Node& n, int indent) {
    const std::string pad(static_cast<std::size_t>(indent) * 2, ' ');
    switch (n.kind) {
      case NodeKind::Primitive: return pad + primitive(n.primitive) + "\n";
      case NodeKind::Union:
      case NodeKind::Intersection: {
        std::vector<const Node*> kids;
        collect_flat(n, n.kind, kids);
        if (kids.size() == 1) return geometry(*kids.front(), indent);
        return block(n.kind == NodeKind::Union ? "union()" : "intersection()", kids, indent);
      }
      case NodeKind::Difference: {
        std::vector<const Node*> kids{&n.children.front()};
        // a - (b + c) = a - b - c: the subtracted unions read better inlined.
        for (std::size_t i = 1; i < n.children.size(); ++i) {
          const Node& c = n.children[i];
          if (is_empty(c)) continue;
          if (c.kind == NodeKind::Union)
            collect_flat(c, NodeKind::Union, kids);
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

 private:
  std::string block(const std::string& head, const std::vector<const Node*>& kids, int indent) {
    const std::string pad(static_cast<std::size_t>(indent) * 2, ' ');
    std::string out = pad + head + " {\n";
    for (const Node* k : kids) out += geometry(*k, indent + 1);
    out += pad + "}\n";
    return out;
  }

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
    return "[0:" + fmt(step(), 12) + ":" + fmt(hi, 12) + "]";
  }
  std::string position_range(double v) const {
    const double hi = nice_ceiling(std::max(extent_, std::fabs(v)));
    const double lo = v < 0 ? -hi : 0;
    return "[" + fmt(lo, 12) + ":" + fmt(step(), 12) + ":" + fmt(hi, 12) + "]";
  }
  static std::string angle_range(double a) {
    return a < 0 ? "[-360:0.1:360]" : "[0:0.1:360]";
  }
  // About a thousandth of the drawing's size, so a slider has ~1000 useful positions.
  double step() const { return slider_step(extent_); }

  std::string add(Tab& tab, const std::string& prefix, const char* field, double v,
                  const std::string& range, int decimals) {
    const std::string name = prefix + "_" + field;
    tab.vars.push_back({name, fmt(v, decimals), range});
    return name;
  }

  std::string primitive(const Primitive& p) {
    ++count_;
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
    if (!(w > 0) || !(h > 0)) throw InputError("cannot write .scad: " + what + " has a size <= 0");

    Tab tab{title, {}};
    const int d = decimals_;
    const std::string vx = add(tab, prefix, "cx", cx, position_range(cx), d);
    const std::string vy = add(tab, prefix, "cy", cy, position_range(cy), d);
    const std::string at = "translate([" + vx + ", " + vy + "]) ";
    // A zero angle is left out: a hand-written file would not rotate by 0 either.
    const bool rotated = fmt(angle, 4) != "0" && p.kind != PrimitiveKind::Circle;
    std::string rot;
    std::string code;
    switch (p.kind) {
      case PrimitiveKind::Rectangle: {
        const std::string vw = add(tab, prefix, "w", w, length_range(w), d);
        const std::string vh = add(tab, prefix, "h", h, length_range(h), d);
        if (rotated) rot = "rotate(" + add(tab, prefix, "angle", angle, angle_range(angle), 4) + ") ";
        code = at + rot + "square([" + vw + ", " + vh + "], center = true);";
        break;
      }
      case PrimitiveKind::Circle: {
        const std::string vr = add(tab, prefix, "r", w / 2, length_range(w / 2), d);
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
    tabs_.push_back(std::move(tab));
    return code;
  }

  const ModelFrame& frame_;
  int decimals_;
  double extent_;
  int count_ = 0;
  std::vector<Tab> tabs_;
};

}  // namespace

std::string to_scad(const Node& tree, const ModelFrame& frame, const ScadOptions& options,
                    const FitStats* stats) {
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
  for (const Primitive* p : leaves(tree))
    extent = std::max({extent, std::fabs(p->cx) + p->w, std::fabs(p->cy) + p->h});
  extent = std::max({extent, static_cast<double>(options.width_px),
                     static_cast<double>(options.height_px)});
  extent *= frame.pixel_size;

  Writer writer(frame, decimals, extent);
  const std::string body = writer.geometry(tree, 1);
  const std::string module = sanitize_identifier(frame.source);

  std::ostringstream out;
  out << "// Generated by csgfit";
  if (!frame.source.empty()) {
    out << " from " << comment_safe(frame.source);
  }
  out << "\n";
  if (options.width_px > 0 && options.height_px > 0)
    out << "// Canvas: " << options.width_px << " x " << options.height_px << " px at "
        << fmt(frame.pixel_size, 9) << " mm per pixel = [0, "
        << fmt(options.width_px * frame.pixel_size, decimals) << "] x [0, "
        << fmt(options.height_px * frame.pixel_size, decimals) << "] mm, y up.\n";
  else
    out << "// Units: mm, y up; pixel size " << fmt(frame.pixel_size, 9) << " mm.\n";
  // Statistics without primitives were never filled in (a hand-written tree): leave them out.
  if (stats && stats->primitives > 0) {
    if (!std::isfinite(stats->iou) || !std::isfinite(stats->score))
      throw InputError("cannot write .scad: the fit statistics are not finite");
    out << "// Fit: IoU " << fmt(stats->iou, 4) << ", " << stats->primitives << " primitives, score "
        << fmt(stats->score, 2) << ".\n";
  }
  out << "// Every dimension below is a Customizer parameter (Window > Customizer).\n\n";

  out << "/* [Resolution] */\n";
  out << "// Segments per full circle\n";
  out << "segments = " << options.fn << "; // [12:1:360]\n\n";
  if (frame.thickness > 0) {
    out << "/* [Extrusion] */\n";
    out << "thickness = " << fmt(frame.thickness, decimals) << "; // [0:"
        << fmt(slider_step(std::max(frame.thickness, extent)), 12) << ":"
        << fmt(nice_ceiling(std::max(frame.thickness * 2, 1.0)), 6) << "]\n\n";
  }
  for (const Tab& tab : writer.tabs()) {
    out << "/* [" << tab.title << "] */\n";
    for (const Var& v : tab.vars) out << v.name << " = " << v.value << "; // " << v.range << "\n";
    out << "\n";
  }
  out << "/* [Hidden] */\n";
  out << "// Pixel size of the source image in mm; the dimensions above are already in mm.\n";
  out << "pixel_size = " << fmt(frame.pixel_size, 9) << ";\n";
  out << "$fn = segments;\n\n";
  switch (options.circle_fit) {
    case CircleFit::Inscribed:
      out << "// Circles are $fn-gons with their vertices on the fitted circle.\n";
      out << "function fn_r(r) = r;\n\n";
      break;
    case CircleFit::Circumscribed:
      out << "// OpenSCAD puts a circle's $fn vertices on the circle, so the polygon lies inside "
             "it;\n// enlarging the radius by 1/cos(180/$fn) makes the polygon's edges touch the "
             "fitted\n// circle instead, which halves the area between the two.\n";
      out << "function fn_r(r) = r / cos(180 / $fn);\n\n";
      break;
    case CircleFit::EqualArea:
      out << "// OpenSCAD puts a circle's $fn vertices on the circle, so the polygon lies inside "
             "it;\n// this radius gives the polygon the fitted circle's area instead.\n";
      out << "function fn_r(r) = r * sqrt(2 * PI / ($fn * sin(360 / $fn)));\n\n";
      break;
  }
  out << "module " << module << "() {\n" << body << "}\n\n";
  if (frame.thickness > 0)
    out << "linear_extrude(height = thickness) " << module << "();\n";
  else
    out << module << "();\n";
  return out.str();
}

}  // namespace csgfit
