#include "option_checks.h"

#include <cstdlib>
#include <string>

#include "csgfit/error.h"
#include "csgfit/model/memory_budget.h"

namespace csgfit::cli {

namespace {

// A validator that runs `parse` (which throws InputError naming "" as the option) and returns its
// message without that empty name: CLI11 puts "--name: " before it.
template <class Parse>
CLI::Validator refusals_of(Parse parse) {
  return CLI::Validator(
      [parse](std::string& text) -> std::string {
        try {
          parse(text);
          return {};
        } catch (const InputError& e) {
          return std::string(e.what()).substr(1);
        }
      },
      "");
}

}  // namespace

CLI::Validator obeys(const NumberRule& rule) {
  return CLI::Validator(
      [rule](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0')
          return std::string("must be ") + rule.what + ", not '" + printable_message(text, 24) +
                 "'";
        return rule_violation(rule, value);
      },
      "");
}

CLI::Validator seed_check() {
  return refusals_of([](const std::string& text) { parse_seed("", text); });
}

void add_memory_option(CLI::App& command) {
  command
      .add_option_function<std::string>(
          "--max-memory",
          [](const std::string& text) {
            set_memory_budget(static_cast<std::size_t>(parse_memory_size("--max-memory", text)));
          },
          "refuse inputs and options whose buffers would need more than this (bytes, or with "
          "K, M, G, T; default: half of the machine's memory, " +
              byte_text(static_cast<double>(default_memory_budget())) + " here)")
      ->check(refusals_of([](const std::string& text) { parse_memory_size("", text); }));
}

}  // namespace csgfit::cli
