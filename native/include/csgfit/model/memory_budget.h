// One memory budget for the whole process: every large allocation (rasters, voxel grids, image
// and mesh buffers, the search's islands) asks it first, so an absurd size is refused with one
// line instead of swapping, crashing or being killed.
#pragma once

#include <cstddef>
#include <string>

namespace csgfit {

/// The budget when none is set: half of the machine's physical memory (4 GiB if unknown).
std::size_t default_memory_budget();

/// Sets the budget in bytes; 0 restores the default. Applies to every later allocation check.
void set_memory_budget(std::size_t bytes);

/// The budget in force, in bytes.
std::size_t memory_budget();

/// Throws InputError("WHAT needs N GB, more than the memory budget of M GB (--max-memory)")
/// when `bytes` (a double, so that a product of corrupt sizes cannot wrap) is over the budget.
void check_allocation(double bytes, const std::string& what);

/// A byte count as people read it: "512 MB", "9.3 GB".
std::string byte_text(double bytes);

}  // namespace csgfit
