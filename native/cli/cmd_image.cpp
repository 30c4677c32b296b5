#include <filesystem>

#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/image.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "fit_command.h"
#include "option_checks.h"
#include "output.h"
#include "progress_bar.h"

namespace fs = std::filesystem;

namespace csgfit::cli {

namespace {

struct ImageArgs {
  FitArgs fit;
  std::string preview, raster, quality = "default", preset = "default";
  double pixel_size = 1, thickness = 0;
  int threshold = -1, alternatives = 0, max_size = 0;
  long long max_pixels = 4096LL * 4096LL;
  bool invert = false;
};

void add_image_options(CLI::App& image, ImageArgs& a) {
  a.fit.primitives = "all";
  add_fit_args(image, a.fit,
               {"PNG, JPEG, BMP, PGM/PBM or TGA image", "output: .scad, .json, .FCStd or .step",
                "size weight per primitive (default: 11 at 128 x 128, scaled to the area)",
                "comma-separated: rectangle,circle,ellipse,triangle (or all)",
                "OpenSCAD $fn for circles and ellipses", "no progress bar and no summary"});
  image.add_option("--quality", a.quality, "fast, default or best")
      ->check(CLI::IsMember({"fast", "default", "best"}));
  image.add_option("--preset", a.preset, "search parameters: default or paper (seed 000, Table 2)")
      ->check(CLI::IsMember({"default", "paper"}));
  image
      .add_option("--alternatives", a.alternatives,
                  "also write up to N structurally different trees")
      ->check(obeys(option_rules::alternatives));
  image.add_option("--threshold", a.threshold, "grey level 0-255 (default: Otsu)")
      ->check(obeys(option_rules::threshold));
  image.add_flag("--invert", a.invert, "light pixels are the shape");
  image.add_option("--pixel-size", a.pixel_size, "millimetres per pixel")
      ->check(obeys(option_rules::scale));
  image.add_option("--thickness", a.thickness, "extrude the 2D result to this height (mm)")
      ->check(obeys(option_rules::thickness));
  image.add_option("--max-size", a.max_size, "downsample images larger than N pixels on a side")
      ->check(obeys(option_rules::image_side));
  image.add_option("--max-pixels", a.max_pixels, "refuse images with more pixels than this")
      ->check(obeys(option_rules::pixel_count));
  image.add_option("--preview", a.preview,
                   "PNG of input and result overlaid (excess red, uncovered blue)");
  image.add_option("--raster", a.raster, "PNG of the solver's own raster of the result");
}

Bitmap read_target(const ImageArgs& a) {
  ImageReadOptions read;
  read.threshold = a.threshold;
  read.invert = a.invert;
  read.max_size = a.max_size;
  read.max_pixels = a.max_pixels;
  Bitmap target = read_bitmap(a.fit.input, read);
  if (target.count() == 0)
    throw InputError("no shape found in '" + a.fit.input +
                     "' (all pixels are background; try --invert or --threshold)");
  return target;
}

void run_image(const ImageArgs& a) {
  ModelFrame frame;
  frame.pixel_size = a.pixel_size;
  frame.thickness = a.thickness;
  frame.source = fs::path(a.fit.input).filename().string();
  check_output(a.fit.output, &frame);
  if (!a.preview.empty()) check_png_output(a.preview, "--preview");
  if (!a.raster.empty()) check_png_output(a.raster, "--raster");
  FitOptions options = fit_options<FitOptions>(a.fit);
  options.alternatives = a.alternatives;
  options.search = SearchParams::for_quality(a.preset == "paper" ? a.preset : a.quality);

  const Bitmap target = read_target(a);
  ProgressBar bar(!a.fit.quiet);
  const FitResult result = fit_bitmap(target, options, bar.callback());
  bar.finish();

  write_output(a.fit.output, result, frame, a.fit.fn);
  const Bitmap fitted = render(result.tree, result.width, result.height);
  if (!a.preview.empty())
    write_preview_png(a.preview, target, fitted, target.width() < 256 ? 4 : 1);
  if (!a.raster.empty()) write_bitmap_png(a.raster, fitted);
  if (!a.fit.quiet) print_summary(result.stats);
}

}  // namespace

Command add_image_command(CLI::App& app) {
  return make_command(app, "image", "fit a CSG tree to a bitmap", add_image_options, run_image);
}

}  // namespace csgfit::cli
