// The coordinate rules of 2D results: how solver coordinates become model units.
#pragma once

#include <string>

namespace csgfit {

/// How solver coordinates (pixel units, y up) map to model units.
struct ModelFrame {
  double pixel_size = 1.0;   ///< model units (mm) per pixel
  double thickness = 0.0;    ///< > 0: the 2D result is extruded to this height
  std::string source;        ///< input file name, for the record
};

}  // namespace csgfit
