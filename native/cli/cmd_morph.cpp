// csgfit morph: two bitmaps (or two meshes / voxel grids) -> two trees of one structure, written
// as one animated model (seed 000's morphing).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "csgfit/io/image.h"
#include "csgfit/io/input3d.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/voxels_read.h"
#include "csgfit/io/json.h"
#include "csgfit/pipeline/fit_morph.h"
#include "fcstd_writer.h"
#include "fit_command.h"
#include "option_checks.h"
#include "progress_bar.h"
#include "scad_writer.h"
#include "scad_writer3d.h"

namespace fs = std::filesystem;

namespace csgfit::cli {

namespace {

enum class MorphFormat { Scad, Json, Gif, FCStd };

struct MorphArgs {
  std::string a, b, output, frames_dir, primitives, preset = "default", rotate = "shortest";
  double time_limit = 10, k = -1, pixel_size = 1, thickness = 0;
  std::uint64_t seed = 1;
  int threads = 0, fn = 96, frames = 24, threshold = -1, max_size = 0, resolution = 64;
  bool quiet = false, invert = false;
};

void add_morph_options(CLI::App& cmd, MorphArgs& a) {
  cmd.add_option("a", a.a, "shape A (morph = 0): an image, or a mesh / voxel grid")->required();
  cmd.add_option("b", a.b, "shape B (morph = 1), of A's kind (and size, for images)")->required();
  cmd.add_option("-o,--output", a.output, "output: .scad (animated), .json, .gif or .FCStd")->required();
  cmd.add_option("--time", a.time_limit, "time budget in seconds")->check(obeys(option_rules::time));
  cmd.add_option("--seed", a.seed, "random seed: same seed and threads, same pair")->check(seed_check());
  cmd.add_option("--threads", a.threads, "worker threads (0 = all cores)")->check(obeys(option_rules::threads));
  cmd.add_option("--k", a.k, "price of one primitive of the pair, half of it in each tree (default as csgfit image / mesh)")
      ->check(obeys(option_rules::k));
  cmd.add_option("--primitives", a.primitives, "comma-separated primitive kinds (default: every 2D kind; 3D: csgfit mesh's)");
  cmd.add_option("--fn", a.fn, "OpenSCAD $fn for round primitives")->check(obeys(option_rules::fn));
  cmd.add_flag("-q,--quiet", a.quiet, "no progress bar and no summary");
  cmd.add_option("--preset", a.preset, "search: default, or paper (seed 000's Table 2, a = 5)")
      ->check(CLI::IsMember({"default", "paper"}));
  cmd.add_option("--rotate", a.rotate, "how 2D primitives turn: shortest, cw or ccw")
      ->check(CLI::IsMember({"shortest", "cw", "ccw"}));
  cmd.add_option("--frames", a.frames, "frames of a .gif and of --frames-dir")->check(obeys(option_rules::frames));
  cmd.add_option("--frames-dir", a.frames_dir, "also write the frames as PNGs (the solver's raster) here");
  cmd.add_option("--threshold", a.threshold, "grey level 0-255 (default: Otsu)")->check(obeys(option_rules::threshold));
  cmd.add_flag("--invert", a.invert, "light pixels are the shape");
  cmd.add_option("--pixel-size", a.pixel_size, "millimetres per pixel")->check(obeys(option_rules::scale));
  cmd.add_option("--thickness", a.thickness, "extrude the 2D morph to this height (mm)")
      ->check(obeys(option_rules::thickness));
  cmd.add_option("--max-size", a.max_size, "downsample images larger than N pixels on a side")
      ->check(obeys(option_rules::image_side));
  cmd.add_option("--resolution", a.resolution, "3D: voxels along the longest side of the common grid")
      ->check(obeys(option_rules::resolution));
  add_memory_option(cmd);
}

MorphFormat morph_format(const std::string& out) {
  std::string ext = fs::path(out).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".scad") return MorphFormat::Scad;
  if (ext == ".json") return MorphFormat::Json;
  if (ext == ".gif") return MorphFormat::Gif;
  if (ext == ".fcstd") return MorphFormat::FCStd;
  throw InputError("a morph is written as .scad, .json, .gif or .FCStd, not '" +
                   (ext.empty() ? out : ext) + "'");
}

// A mesh or voxel grid by its extension, as read_input3d picks its reader; anything else is an
// image, whose reader recognises the format by its content.
bool is_3d_input(const std::string& path) { return is_mesh_path(path) || is_voxel_path(path); }

std::string file_name(const std::string& path) { return fs::path(path).filename().string(); }

// The frames' directory: made if missing, and writable.
void check_frames_dir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw InputError("--frames-dir: cannot make the folder '" + dir + "'");
  check_writable((fs::path(dir) / "frame_000.png").string());
}

std::vector<Bitmap> frames_of(const MorphResult& r, int count) {
  std::vector<Bitmap> frames;
  for (int i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) / (count - 1);
    frames.push_back(render(interpolate(r.a, r.b, t), r.width, r.height));
  }
  return frames;
}

void print_morph_summary(const FitStats& a, const FitStats& b, std::size_t one_sided) {
  std::fprintf(stderr,
               "csgfit: morph IoU %.4f (A) and %.4f (B), %zu primitives (%zu seen in one shape "
               "only), %zu trees, %zu evaluations, %.2f s (%s)\n",
               a.iou, b.iou, a.primitives, one_sided, a.trees, a.evaluations, a.seconds,
               a.stop_reason.c_str());
}

template <typename Pair>
std::size_t one_sided(const Pair& r) {
  return static_cast<std::size_t>(std::count_if(r.leaves.begin(), r.leaves.end(),
                                                [](const MorphLeaf& l) { return !l.in_a || !l.in_b; }));
}

Bitmap read_image(const MorphArgs& a, const std::string& path) {
  ImageReadOptions read;
  read.threshold = a.threshold;
  read.invert = a.invert;
  read.max_size = a.max_size;
  Bitmap target = read_bitmap(path, read);
  if (target.count() == 0)
    throw InputError("no shape found in '" + path + "' (all pixels are background; try --invert or --threshold)");
  return target;
}

void run_morph2d(const MorphArgs& a, MorphFormat format) {
  const Bitmap ba = read_image(a, a.a), bb = read_image(a, a.b);
  if (ba.width() != bb.width() || ba.height() != bb.height())
    throw InputError("the images differ in size: '" + a.a + "' is " + std::to_string(ba.width()) +
                     " x " + std::to_string(ba.height()) + " pixels, '" + a.b + "' " +
                     std::to_string(bb.width()) + " x " + std::to_string(bb.height()) +
                     " (scale one to the other's size first)");
  MorphOptions options;
  if (!a.primitives.empty()) options.fit.primitives = primitive_set<PrimitiveSet>(a.primitives);
  options.fit.k = a.k;
  options.fit.time_limit = a.time_limit;
  options.fit.threads = a.threads;
  options.fit.seed = a.seed;
  options.fit.search = SearchParams::for_morph(a.preset);
  options.rotate = turn_direction_from_string(a.rotate);

  ProgressBar bar(!a.quiet);
  const MorphResult r = morph_bitmaps(ba, bb, options, bar.callback());
  bar.finish();

  ModelFrame frame;
  frame.pixel_size = a.pixel_size;
  frame.thickness = a.thickness;
  frame.source = file_name(a.a);
  ScadOptions scad;
  scad.fn = a.fn;
  scad.width_px = r.width;
  scad.height_px = r.height;
  // The frames are drawn once, for the .gif and for --frames-dir alike.
  std::vector<Bitmap> frames;
  if (format == MorphFormat::Gif || !a.frames_dir.empty()) frames = frames_of(r, a.frames);
  switch (format) {
    case MorphFormat::Scad:
      write_file_atomic(a.output, to_scad_morph(r.a, r.b, frame, file_name(a.b), scad, &r.stats_a));
      break;
    case MorphFormat::Json:
      write_file_atomic(a.output, to_json_morph(r, frame, file_name(a.b), options.rotate));
      break;
    case MorphFormat::FCStd: write_fcstd(to_json_morph(r, frame, file_name(a.b), options.rotate), a.output); break;
    case MorphFormat::Gif:
      write_bitmaps_gif(a.output, frames, r.width < 256 ? 2 : 1, std::max(2, 200 / a.frames));
      break;
  }
  if (!a.frames_dir.empty())
    for (std::size_t i = 0; i < frames.size(); ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%03zu.png", i);
      write_bitmap_png((fs::path(a.frames_dir) / name).string(), frames[i]);
    }
  if (!a.quiet) print_morph_summary(r.stats_a, r.stats_b, one_sided(r));
}

void run_morph3d(const MorphArgs& a, MorphFormat format) {
  if (format == MorphFormat::Gif || !a.frames_dir.empty())
    throw InputError("frames (.gif, --frames-dir) are drawn for 2D morphs only; write .scad and animate it in OpenSCAD");
  const auto [ga, gb] = morph_grids(read_input3d(a.a), read_input3d(a.b), a.resolution);
  FitOptions3D options;
  if (!a.primitives.empty()) options.primitives = primitive_set<PrimitiveSet3D>(a.primitives);
  options.k = a.k;
  options.time_limit = a.time_limit;
  options.threads = a.threads;
  options.seed = a.seed;

  ProgressBar bar(!a.quiet);
  const MorphResult3D r = morph_voxels(ga, gb, options, bar.callback());
  bar.finish();
  ScadOptions3D scad;
  scad.fn = std::min(a.fn, 64);
  scad.source = file_name(a.a);
  switch (format) {
    case MorphFormat::Scad: write_file_atomic(a.output, to_scad_morph(r.a, r.b, file_name(a.b), scad)); break;
    case MorphFormat::Json:
      write_file_atomic(a.output, to_json_morph3d(r, ga, file_name(a.a), file_name(a.b)));
      break;
    case MorphFormat::FCStd: write_fcstd(to_json_morph3d(r, ga, file_name(a.a), file_name(a.b)), a.output); break;
    case MorphFormat::Gif: break;  // refused above
  }
  if (!a.quiet) print_morph_summary(r.stats_a, r.stats_b, one_sided(r));
}

void run_morph(const MorphArgs& a) {
  const MorphFormat format = morph_format(a.output);
  check_writable(a.output);
  if (!a.frames_dir.empty()) check_frames_dir(a.frames_dir);
  const bool solid_a = is_3d_input(a.a), solid_b = is_3d_input(a.b);
  if (solid_a != solid_b)
    throw InputError("give two images or two meshes / voxel grids, not '" + a.a + "' and '" + a.b + "'");
  if (solid_a)
    run_morph3d(a, format);
  else
    run_morph2d(a, format);
}

}  // namespace

Command add_morph_command(CLI::App& app) {
  return make_command(app, "morph", "two shapes to two trees of one structure, as one animated model",
                      add_morph_options, run_morph);
}

}  // namespace csgfit::cli
