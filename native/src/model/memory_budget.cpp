#include "csgfit/model/memory_budget.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>

#include "csgfit/error.h"

namespace csgfit {

namespace {

std::atomic<std::size_t> budget{0};  // 0: the default

}  // namespace

std::size_t default_memory_budget() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return std::size_t{4} << 30;
  return static_cast<std::size_t>(pages) / 2 * static_cast<std::size_t>(page_size);
}

void set_memory_budget(std::size_t bytes) { budget.store(bytes); }

std::size_t memory_budget() {
  const std::size_t set = budget.load();
  return set != 0 ? set : default_memory_budget();
}

std::string byte_text(double bytes) {
  static const char* const units[] = {"bytes", "KB", "MB", "GB", "TB", "PB", "EB"};
  int unit = 0;
  while (bytes >= 1000 && unit < 6) {
    bytes /= 1000;
    ++unit;
  }
  char text[48];
  std::snprintf(text, sizeof text, unit == 0 || bytes >= 100 ? "%.0f %s" : "%.1f %s", bytes,
                units[unit]);
  return text;
}

void check_allocation(double bytes, const std::string& what) {
  const double limit = static_cast<double>(memory_budget());
  if (bytes <= limit) return;  // NaN is refused too
  throw InputError(what + " needs " + (bytes < 1e30 ? byte_text(bytes) : std::string("more than 1e30 bytes")) +
                   ", more than the memory budget of " + byte_text(limit) + " (--max-memory)");
}

}  // namespace csgfit
