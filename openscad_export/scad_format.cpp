#include "scad_format.h"

#include "scad_tree_writer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace csgfit::scad {

namespace {

// OpenSCAD keywords and built-ins, plus the helpers the writers define: a model's module must
// not shadow any of them (module circle() calling circle() would recurse).
const char* const kReserved[] = {
    "module", "function", "if", "else", "for", "let", "each", "true", "false", "undef",
    "include", "use", "assert", "echo", "intersection_for", "children", "cube", "sphere",
    "cylinder", "polyhedron", "square", "circle", "polygon", "text", "import", "surface",
    "projection", "linear_extrude", "rotate_extrude", "translate", "rotate", "scale", "mirror",
    "multmatrix", "color", "offset", "minkowski", "hull", "resize", "union", "difference",
    "intersection", "render", "group", "parent_module", "fn_r", "fn_sr", "fn_sphere_volume",
    "csg_torus", "csg_half_disc", "segments"};

}  // namespace

std::string number(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s(buf);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

double slider_step(double extent) {
  if (!(extent > 0)) return 0.01;
  return std::pow(10.0, std::floor(std::log10(extent)) - 3);
}

double nice_ceiling(double v) {
  if (!(v > 0)) return 1;
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= v) return m * p;
  return 10 * p;
}

std::string identifier(const std::string& source, const std::string& fallback) {
  std::string stem = source;
  const std::size_t slash = stem.find_last_of("/\\");
  if (slash != std::string::npos) stem = stem.substr(slash + 1);
  const std::size_t dot = stem.find('.');
  if (dot != std::string::npos) stem = stem.substr(0, dot);
  std::string id;
  for (char ch : stem) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (std::isalnum(c))
      id += static_cast<char>(std::tolower(c));
    else if (!id.empty() && id.back() != '_')
      id += '_';
  }
  while (!id.empty() && id.back() == '_') id.pop_back();
  if (id.empty()) return fallback;
  if (std::isdigit(static_cast<unsigned char>(id[0]))) id = fallback + "_" + id;
  for (const char* r : kReserved)
    if (id == r) return id + "_" + fallback;
  return id;
}

std::string comment_safe(std::string s) {
  for (char& ch : s)
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) ch = '?';
  return s;
}

void write_resolution(std::ostream& out, int fn) {
  out << "/* [Resolution] */\n";
  out << "// Segments per full circle\n";
  out << "segments = " << fn << "; // [12:1:360]\n\n";
}

std::string users_text(std::vector<int> numbers, const std::string& kinds) {
  std::sort(numbers.begin(), numbers.end());
  std::string out = kinds;
  for (std::size_t i = 0; i < numbers.size(); ++i)
    out += (i == 0 ? " " : i + 1 == numbers.size() ? " and " : ", ") + std::to_string(numbers[i]);
  return out;
}

std::string shared_title(DimensionField field, bool rectangles) {
  if (rectangles) return "side";
  switch (field) {
    case DimensionField::CentreX: return "centre x";
    case DimensionField::CentreY: return "centre y";
    case DimensionField::Width: return "width";
    case DimensionField::Height: return "height";
    case DimensionField::Radius: return "radius";
    case DimensionField::Length: return "height";
  }
  return "value";
}

void write_tabs(std::ostream& out, const std::vector<Tab>& tabs) {
  for (const Tab& tab : tabs) {
    out << "/* [" << tab.title << "] */\n";
    for (const Var& v : tab.vars) {
      if (!v.description.empty()) out << "// " << comment_safe(v.description) << "\n";
      out << v.name << " = " << v.value << "; // " << v.range << "\n";
    }
    out << "\n";
  }
}

void write_circle_radius(std::ostream& out, CircleFit fit) {
  switch (fit) {
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
}

void write_morph_slider(std::ostream& out, const std::string& source_a, const std::string& source_b) {
  out << "/* [Morph] */\n";
  out << "// 0 = " << comment_safe(source_a.empty() ? "shape A" : source_a) << ", 1 = "
      << comment_safe(source_b.empty() ? "shape B" : source_b)
      << "; -1 follows $t, so View > Animate plays the morph.\n";
  out << "morph = -1; // [-1:0.01:1]\n\n";
}

void write_morph_tabs(std::ostream& out, const std::vector<Tab>& a, const std::vector<Tab>& b) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    out << "/* [" << a[i].title << "] */\n";
    for (std::size_t j = 0; j < a[i].vars.size(); ++j) {
      const Var& va = a[i].vars[j];
      const Var& vb = b[i].vars[j];
      if (va.value == vb.value) {
        out << va.name << " = " << va.value << "; // " << va.range << "\n";
        continue;
      }
      out << va.name << "_a = " << va.value << "; // " << va.range << "\n";
      out << vb.name << "_b = " << vb.value << "; // " << vb.range << "\n";
    }
    out << "\n";
  }
}

void write_morph_values(std::ostream& out, const std::vector<Tab>& a, const std::vector<Tab>& b) {
  out << "m = morph < 0 ? $t : morph;\n";
  out << "function mix(at_a, at_b) = at_a + (at_b - at_a) * m;\n";
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < a[i].vars.size(); ++j)
      if (a[i].vars[j].value != b[i].vars[j].value)
        out << a[i].vars[j].name << " = mix(" << a[i].vars[j].name << "_a, " << a[i].vars[j].name
            << "_b);\n";
  out << "\n";
}

}  // namespace csgfit::scad
