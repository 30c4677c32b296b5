#include "csgfit/pipeline/option_limits.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "csgfit/error.h"

namespace csgfit {

namespace {

// Whole numbers of an integer rule in full (2147483647, not 2.14748e+09).
std::string number_text(double v, bool whole = false) {
  char text[48];
  const bool full = whole && std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e18;
  std::snprintf(text, sizeof text, full ? "%.0f" : "%g", v);
  return text;
}

std::string range_text(const NumberRule& rule) {
  if (rule.integer) return number_text(rule.lo, true) + " .. " + number_text(rule.hi, true);
  return (rule.lo_open ? "(" : "[") + number_text(rule.lo) + ", " + number_text(rule.hi) + "]";
}

}  // namespace

std::string rule_violation(const NumberRule& rule, double value) {
  const bool inside = std::isfinite(value) && value <= rule.hi &&
                      (rule.lo_open ? value > rule.lo : value >= rule.lo) &&
                      (!rule.integer || value == std::floor(value));
  if (inside) return {};
  return std::string("must be ") + rule.what + (rule.integer ? ", an integer " : " ") + "in " +
         range_text(rule) + ", not " + number_text(value, rule.integer);
}

void check_option(const std::string& name, double value, const NumberRule& rule) {
  const std::string why = rule_violation(rule, value);
  if (!why.empty()) throw InputError(name + " " + why);
}

double parse_memory_size(const std::string& name, const std::string& text) {
  const std::string quoted = "'" + printable_message(text, 24) + "'";
  errno = 0;
  char* end = nullptr;
  double value = std::strtod(text.c_str(), &end);
  const std::string unit = end;
  const char* const units[] = {"", "K", "M", "G", "T"};
  int power = -1;
  for (int i = 0; i < 5 && power < 0; ++i)
    if (unit == units[i] || (i > 0 && unit == std::string(units[i]) + "B")) power = i;
  if (end == text.c_str() || errno == ERANGE || power < 0)
    throw InputError(name + " must be a size such as 4G or 512M, not " + quoted);
  value = std::floor(value * std::pow(1024.0, power));
  if (!rule_violation(option_rules::memory, value).empty())
    throw InputError(name + " must be a size from 16M to 1024T, not " + quoted);
  return value;
}

unsigned long long parse_seed(const std::string& name, const std::string& text) {
  const bool digits = !text.empty() && text.size() <= 20 &&
                      text.find_first_not_of("0123456789") == std::string::npos;
  errno = 0;
  const unsigned long long seed = digits ? std::strtoull(text.c_str(), nullptr, 10) : 0;
  if (!digits || errno == ERANGE)
    throw InputError(name + " must be a seed, an integer in 0 .. 18446744073709551615, not '" +
                     printable_message(text, 24) + "'");
  return seed;
}

}  // namespace csgfit
