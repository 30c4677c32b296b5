// The range of every numeric option, written once: the CLI's validators, the Python module's
// argument checks and the fits themselves all check against these rules, and the README's table
// lists them. A value outside its rule is refused before any work, with one line.
#pragma once

#include <string>

namespace csgfit {

/// The values an option takes: [lo, hi] (lo excluded when lo_open), integers only when integer.
struct NumberRule {
  const char* what;  ///< what the value is, for messages: "a time in seconds"
  double lo, hi;
  bool lo_open;
  bool integer;
};

namespace option_rules {
inline constexpr NumberRule time{"a time in seconds", 0, 1e6, true, false};
inline constexpr NumberRule threads{"a thread count (0 = all cores)", 0, 256, false, true};
inline constexpr NumberRule k{"a size weight", 0, 1e15, false, false};
inline constexpr NumberRule fn{"an OpenSCAD $fn", 3, 1000, false, true};
/// Pixel size, depth unit, voxel size: model units per pixel, step or voxel.
inline constexpr NumberRule scale{"a length in model units", 1e-9, 1e9, false, false};
inline constexpr NumberRule thickness{"a thickness in model units (0 = flat)", 0, 1e9, false, false};
inline constexpr NumberRule resolution{"a voxel count (0 = auto)", 0, 512, false, true};
inline constexpr NumberRule image_side{"a side in pixels", 1, 65536, false, true};
inline constexpr NumberRule pixel_count{"a pixel count", 1, 1LL << 30, false, true};
inline constexpr NumberRule alternatives{"a count of alternatives", 0, 20, false, true};
inline constexpr NumberRule threshold{"a grey level", 0, 255, false, true};
inline constexpr NumberRule focal_length{"a focal length in pixels", 1e-3, 1e7, false, false};
inline constexpr NumberRule principal_point{"a pixel coordinate", -1e7, 1e7, false, false};
/// The optimiser's GA weights (seed 001: geometry 20, size 2, proximity 2).
inline constexpr NumberRule weight{"a score weight", 0, 1000, false, false};
/// csgfit inflate's steps (seed 001's generator: 10).
inline constexpr NumberRule inflate_steps{"a step count", 0, 1000, false, true};
inline constexpr NumberRule frames{"a frame count", 2, 500, false, true};
/// csgfit points: seed 004's islands (1 = one population) and the table's height.
inline constexpr NumberRule islands{"an island count", 1, 64, false, true};
inline constexpr NumberRule height{"a height in model units", -1e9, 1e9, false, false};
/// --max-memory, in bytes: 16 MiB up to 1 PiB.
inline constexpr NumberRule memory{"a memory size", 16.0 * (1 << 20), 1125899906842624.0, false, true};
}  // namespace option_rules

/// Empty when `value` obeys `rule`, else why not: "must be a time in seconds in (0, 1e+06],
/// not -1". NaN and infinities never obey.
std::string rule_violation(const NumberRule& rule, double value);

/// Throws InputError("NAME must be ...") when `value` does not obey `rule`.
void check_option(const std::string& name, double value, const NumberRule& rule);

/// A --max-memory value: bytes, or a number with K, M, G or T (powers of 1024). Throws
/// InputError naming `name` for anything else or outside option_rules::memory.
double parse_memory_size(const std::string& name, const std::string& text);

/// A seed: decimal digits only, 0 .. 2^64 - 1. Throws InputError naming `name` otherwise.
unsigned long long parse_seed(const std::string& name, const std::string& text);

}  // namespace csgfit
