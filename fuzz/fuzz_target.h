// What every fuzz target shares (docs/FUZZING.md): the input as the readers' in-memory form, a
// per-process scratch file for the readers that only take a path, and the one exception a
// reader may throw for bad input. Anything else (another exception, a crash, a leak, undefined
// behaviour, a huge allocation) is a finding.
#pragma once

#include <sys/stat.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "csgfit/error.h"

namespace csgfit_fuzz {

/// The input as the readers hold a whole file: a std::string (with a NUL after the last byte,
/// as io_detail::read_whole_file gives it).
inline std::string as_text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// A folder of this process's own under /dev/shm (or $TMPDIR, or /tmp), removed at exit.
inline const std::string& scratch_dir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    const std::string base = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : tmp ? tmp : "/tmp";
    std::string d = base + "/csgfit-fuzz-" + std::to_string(::getpid());
    ::mkdir(d.c_str(), 0700);
    return d;
  }();
  return dir;
}

/// The path of `name` in the scratch folder (the file need not exist).
inline std::string scratch_path(const std::string& name) { return scratch_dir() + "/" + name; }

/// Writes the input to the scratch file `name` (its extension picks the reader's format) and
/// returns its path; the file is removed when the process exits.
inline std::string write_scratch(const std::string& name, const std::uint8_t* data,
                                 std::size_t size) {
  static std::string last;
  const std::string path = scratch_path(name);
  if (last.empty()) {
    last = path;
    std::atexit([] {
      std::remove(last.c_str());
      ::rmdir(scratch_dir().c_str());
    });
  }
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();  // the harness, not the reader, is broken
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

/// Runs one parse: bad input must end in InputError (the readers' contract); any other
/// exception escapes to libFuzzer, which reports it as a crash. With CSGFIT_FUZZ_VERBOSE set,
/// each refusal is printed (to check that the seeds are read, or what an input is refused for).
template <typename Parse>
int run(Parse&& parse) {
  static const bool verbose = std::getenv("CSGFIT_FUZZ_VERBOSE") != nullptr;
  try {
    parse();
    if (verbose) std::fprintf(stderr, "read\n");
  } catch (const csgfit::InputError& e) {
    if (verbose) std::fprintf(stderr, "InputError: %s\n", e.what());
  }
  return 0;
}

}  // namespace csgfit_fuzz
