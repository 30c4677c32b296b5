#include "option_checks.h"

#include <cerrno>
#include <cstdlib>
#include <string>

#include "csgfit/error.h"
#include "csgfit/model/memory_budget.h"

namespace csgfit::cli {

namespace {

// The validators see the text as typed; what they return is the whole message after "--name: ".
std::string shown(const std::string& text) {
  std::string out;
  for (char c : text.substr(0, 24)) out += (c >= 0x20 && c < 0x7f) ? c : '?';
  return text.size() > 24 ? out + "..." : out;
}

}  // namespace

CLI::Validator obeys(const NumberRule& rule) {
  return CLI::Validator(
      [rule](std::string& text) -> std::string {
        errno = 0;
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0')
          return std::string("must be ") + rule.what + ", not '" + shown(text) + "'";
        return rule_violation(rule, value);
      },
      "");
}

CLI::Validator seed_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          parse_seed("", text);
          return {};
        } catch (const InputError& e) {
          return std::string(e.what()).substr(1);  // after the empty name's space
        }
      },
      "");
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
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            try {
              parse_memory_size("", text);
              return {};
            } catch (const InputError& e) {
              return std::string(e.what()).substr(1);
            }
          },
          ""));
}

}  // namespace csgfit::cli
