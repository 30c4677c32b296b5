// The range fit's picture: the first view segmented, one colour per surface patch, beside the
// depth error of the result as that sensor sees it.
#pragma once

#include <string>
#include <vector>

#include "csgfit/model/range_scan.h"
#include "csgfit/pipeline/fit_range.h"

namespace csgfit {

/// Writes the preview PNG of `result` for `scan` (which must have a camera; its points are the
/// first of the merged points, so `patch_of_point` starts with them). Left: patches (grey =
/// no patch, black = no return); right: |depth error| from white (none) to red (1 % of the
/// part's diagonal or more), blue where only the tree is seen, black where neither is.
void write_range_preview(const std::string& path, const RangeScan& scan,
                         const RangeFitResult& result);

}  // namespace csgfit
