// The keyword arguments of the module's functions as the solver's option structs, checked so
// that a bad value is one line naming the argument.
#pragma once

#include <cstdint>
#include <string>

#include "csgfit/io/image.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "csgfit/pipeline/fit_mesh.h"

namespace csgfit_python {

/// The search arguments the 2D and 3D fits share.
struct SearchArgs {
  double k = -1;                  // < 0: the solver's default for the input's size
  std::string primitives;         // comma-separated names
  double time = 10;               // seconds
  int threads = 0;                // 0 = all cores
  std::uint64_t seed = 1;
};

/// threshold -1 = Otsu; max_pixels 0 = the readers' limit; max_size 0 = no downsampling.
csgfit::ImageReadOptions image_read_options(int threshold, bool invert, long long max_pixels,
                                            int max_size);
csgfit::FitOptions fit_options(const SearchArgs& args, int alternatives,
                               const std::string& quality);
csgfit::FitOptions3D fit_options_3d(const SearchArgs& args);
/// resolution: voxels along the longest side (0 = auto); voxel_size: the search grid's edge
/// instead (0 = from the resolution).
csgfit::MeshFitOptions mesh_fit_options(int resolution, double voxel_size, bool construct = true);

/// Throws InputError unless v is a finite number > 0 (>= 0 when zero_ok).
void check_length(const char* name, double v, bool zero_ok = false);

}  // namespace csgfit_python
