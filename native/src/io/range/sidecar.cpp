// The JSON sidecar of a range image (../shared/benchmarks/range/README.md), and intrinsics
// given on the command line over it or instead of it.

#include <sys/stat.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "csgfit/error.h"
#include "io/input_file.h"
#include "io/json/json_fields.h"
#include "io/range/range_formats.h"

namespace csgfit::io_detail {

namespace {

using Json = nlohmann::json;
using json_detail::member;

// A sidecar is a few hundred bytes; anything near this is not one.
constexpr long long kMaxSidecarBytes = 1 << 20;

bool file_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

class SidecarFields {
 public:
  SidecarFields(const std::string& path, const Json& j) : path_(path), j_(j) {}

  [[noreturn]] void bad(const std::string& what) const { fail(quoted(path_) + ": " + what); }

  bool has(const char* key) const { return member(j_, key) != nullptr; }

  double number(const Json& v, const std::string& name) const {
    if (!v.is_number()) bad("'" + name + "' must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) bad("'" + name + "' is not finite");
    return x;
  }
  double number(const char* key) const {
    const Json* v = member(j_, key);
    if (!v) bad(std::string("missing number '") + key + "'");
    return number(*v, key);
  }
  double number_or(const char* key, double fallback) const {
    return has(key) ? number(key) : fallback;
  }
  int size(const char* key) const {
    const double v = number(key);
    if (v != std::floor(v) || v < 1 || v > 1e9) bad(std::string("'") + key + "' is not a size");
    return static_cast<int>(v);
  }
  Projection projection() const;
  std::array<double, 16> pose() const;

 private:
  const std::string& path_;
  const Json& j_;
};

Projection SidecarFields::projection() const {
  const Json* p = member(j_, "projection");
  if (!p) {
    if (has("pixel_size")) return Projection::Orthographic;
    if (has("fx")) return Projection::Pinhole;
    bad("no 'projection' and neither 'pixel_size' nor 'fx'");
  }
  if (p->is_string() && p->get<std::string>() == "orthographic") return Projection::Orthographic;
  if (p->is_string() && p->get<std::string>() == "pinhole") return Projection::Pinhole;
  bad("'projection' must be \"orthographic\" or \"pinhole\"");
}

// 4 rows of 4 numbers, or 16 numbers, row-major.
std::array<double, 16> SidecarFields::pose() const {
  std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const Json* t = member(j_, "camera_to_world");
  if (!t) return m;
  const char* shape = "'camera_to_world' must be 4 rows of 4 numbers";
  if (!t->is_array()) bad(shape);
  if (t->size() == 16) {
    for (std::size_t i = 0; i < 16; ++i) m[i] = number((*t)[i], "camera_to_world");
    return m;
  }
  if (t->size() != 4) bad(shape);
  for (std::size_t r = 0; r < 4; ++r) {
    const Json& row = (*t)[r];
    if (!row.is_array() || row.size() != 4) bad(shape);
    for (std::size_t c = 0; c < 4; ++c) m[r * 4 + c] = number(row[c], "camera_to_world");
  }
  return m;
}

Json parse_sidecar(const std::string& path) {
  const std::string text =
      read_whole_file(path, kMaxSidecarBytes, "too large for a sidecar", FileContent::Text);
  try {
    Json j = Json::parse(text);
    if (!j.is_object()) fail(quoted(path) + " is not a JSON object (a range image sidecar)");
    return j;
  } catch (const Json::exception& e) {  // parse errors, and numbers beyond a double
    // Python's json.dump writes NaN and Infinity, which JSON does not have.
    const bool nan = text.find("NaN") != std::string::npos ||
                     text.find("Infinity") != std::string::npos;
    fail(quoted(path) + " is not valid JSON" +
         (nan ? " (it holds NaN or Infinity, which are not numbers in JSON)"
              : std::string(" (") + e.what() + ")"));
  }
}

SidecarCamera camera_from_sidecar(const std::string& path, int width, int height) {
  const Json j = parse_sidecar(path);
  const SidecarFields f(path, j);
  SidecarCamera s;
  RangeCamera& c = s.camera;
  c.projection = f.projection();
  c.width = f.has("width") ? f.size("width") : width;
  c.height = f.has("height") ? f.size("height") : height;
  if (c.width != width || c.height != height) {
    f.bad("it describes a " + std::to_string(c.width) + " x " + std::to_string(c.height) +
          " image, the image is " + std::to_string(width) + " x " + std::to_string(height));
  }
  if (c.projection == Projection::Orthographic) {
    c.pixel_size = f.number("pixel_size");
  } else {
    c.fx = f.number("fx");
    c.fy = f.number_or("fy", c.fx);
  }
  c.cx = f.number_or("cx", width / 2.0);
  c.cy = f.number_or("cy", height / 2.0);
  c.depth_unit = f.number_or("depth_unit", 1);
  c.camera_to_world = f.pose();
  s.no_return = f.number_or("no_return", 0);
  return s;
}

// The projection the options ask for, over `c`'s; false when they do not say.
bool apply_intrinsics(const std::string& image_path, const RangeIntrinsics& in,
                      RangeCamera& c) {
  if (in.pixel_size && (in.fx || in.fy)) {
    fail(quoted(image_path) + ": give either --pixel-size (orthographic) or --fx and --fy (pinhole), not both");
  }
  bool says = false;
  if (in.pixel_size) {
    c.projection = Projection::Orthographic;
    c.pixel_size = *in.pixel_size;
    says = true;
  } else if (in.fx || in.fy) {
    if (c.projection != Projection::Pinhole && !(in.fx && in.fy)) {
      fail(quoted(image_path) + ": a pinhole camera needs both --fx and --fy");
    }
    c.projection = Projection::Pinhole;
    if (in.fx) c.fx = *in.fx;
    if (in.fy) c.fy = *in.fy;
    says = true;
  }
  if (in.cx) c.cx = *in.cx;
  if (in.cy) c.cy = *in.cy;
  if (in.depth_unit) c.depth_unit = *in.depth_unit;
  return says;
}

}  // namespace

std::string sidecar_path(const std::string& image_path) {
  const std::string ext = lower_extension(image_path);
  if (ext.empty()) return image_path + ".json";
  return image_path.substr(0, image_path.size() - ext.size()) + "json";
}

std::optional<SidecarCamera> read_sidecar_camera(const std::string& image_path, int width,
                                                 int height, const RangeIntrinsics& intrinsics) {
  const std::string path = sidecar_path(image_path);
  std::optional<SidecarCamera> s;
  if (file_exists(path)) {
    s = camera_from_sidecar(path, width, height);
    apply_intrinsics(image_path, intrinsics, s->camera);
  } else {
    s.emplace();
    s->camera.width = width;
    s->camera.height = height;
    s->camera.cx = width / 2.0;
    s->camera.cy = height / 2.0;
    if (!apply_intrinsics(image_path, intrinsics, s->camera)) return std::nullopt;
  }
  try {
    s->camera.validate();
  } catch (const InputError& e) {
    fail((file_exists(path) ? quoted(path) : quoted(image_path) + " (with the given intrinsics)") +
         ": " + e.what());
  }
  return s;
}

SidecarCamera depth_camera(const std::string& image_path, int width, int height,
                           const RangeIntrinsics& intrinsics) {
  std::optional<SidecarCamera> s = read_sidecar_camera(image_path, width, height, intrinsics);
  if (!s) {
    fail(quoted(image_path) + " has no sidecar " + quoted(sidecar_path(image_path)) +
         " and no intrinsics: give --pixel-size (orthographic) or --fx and --fy (pinhole)");
  }
  return *s;
}

}  // namespace csgfit::io_detail

namespace csgfit {

std::optional<RangeCamera> read_range_camera(const std::string& image_path, int width,
                                             int height, const RangeIntrinsics& intrinsics) {
  const auto s = io_detail::read_sidecar_camera(image_path, width, height, intrinsics);
  if (!s) return std::nullopt;
  return s->camera;
}

}  // namespace csgfit
