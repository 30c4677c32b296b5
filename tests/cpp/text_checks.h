// Assertions on generated text (.scad, JSON) that print the whole text when they fail.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <string>

namespace csgfit::testing {

/// `text` holds `what`.
inline ::testing::AssertionResult contains(const std::string& text, const std::string& what) {
  if (text.find(what) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "no \"" << what << "\" in:\n" << text;
}

/// `text` does not hold `what`.
inline ::testing::AssertionResult lacks(const std::string& text, const std::string& what) {
  const std::size_t at = text.find(what);
  if (at == std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << what << "\" at " << at << " of:\n" << text;
}

/// How often `what` stands in `text`, not overlapping.
inline std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t pos = text.find(what); pos != std::string::npos;
       pos = text.find(what, pos + what.size()))
    ++n;
  return n;
}

}  // namespace csgfit::testing
