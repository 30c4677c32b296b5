// Flattening a .scad to .csg by running OpenSCAD itself: only OpenSCAD evaluates its language
// (modules, loops, includes), and its .csg output is the small grammar csg_parse.cpp reads.

#include <fcntl.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/io/openscad_csg.h"
#include "io/input_file.h"

extern char** environ;

namespace csgfit {

namespace {

std::string quoted(const std::string& path) { return "'" + path + "'"; }

// The executable `name` in a folder of $PATH; empty when there is none.
std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/" + name;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        ::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
  }
  return {};
}

// A fresh private folder, removed with everything in it when this goes out of scope.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "csgfit-scad-XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) {
      throw InputError("cannot create a temporary folder for OpenSCAD's output: " +
                       std::string(std::strerror(errno)));
    }
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

constexpr int kFlattenSeconds = 120;

// Runs argv[0] with stdin from /dev/null and stdout and stderr into `log`; the exit status,
// or -1 when it did not exit normally.
int run(const std::vector<std::string>& args, const std::string& log) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int err = ::posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) throw InputError("cannot run " + args[0] + ": " + std::strerror(err));
  // A .scad can loop forever; flattening is quick for any real program, so a run past the
  // limit is stopped and reported, not waited for.
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kFlattenSeconds);
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) return -1;
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      throw InputError(args.back() + ": OpenSCAD did not finish flattening it within " +
                       std::to_string(kFlattenSeconds) + " s");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The log's first megabyte: where OpenSCAD's reason is (a program can echo without end).
std::string read_log(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::string text(1 << 20, '\0');
  f.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(f.gcount()));
  return text;
}

// OpenSCAD's reason in its log: the first ERROR line, else the first warning about parsing,
// else its first line.
std::string reason(const std::string& log) {
  std::istringstream lines(log);
  std::string line, parse_warning, first;
  while (std::getline(lines, line)) {
    if (line.rfind("ERROR", 0) == 0) return line;
    if (parse_warning.empty() && line.rfind("WARNING", 0) == 0 &&
        (line.find("arse") != std::string::npos || line.find("syntax") != std::string::npos)) {
      parse_warning = line;
    }
    if (first.empty() && line.find_first_not_of(" \t\r") != std::string::npos) first = line;
  }
  return !parse_warning.empty() ? parse_warning : first;
}

}  // namespace

std::string flatten_scad_with_openscad(const std::string& scad_path) {
  struct stat st {};
  if (::stat(scad_path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    throw InputError(quoted(scad_path) + " does not exist or is not a file");
  }
  const std::string openscad = find_on_path("openscad");
  if (openscad.empty()) {
    throw InputError("cannot flatten " + quoted(scad_path) +
                     ": 'openscad' is not on PATH (install OpenSCAD, or give a .csg)");
  }
  const TempDir tmp;
  const std::string out = tmp.path() + "/flat.csg";
  const std::string log = tmp.path() + "/openscad.log";
  // "./" keeps a path starting with '-' from being read as an option.
  const std::string in = scad_path.front() == '-' ? "./" + scad_path : scad_path;
  const int status = run({openscad, "-o", out, in}, log);
  struct stat out_st {};
  if (status != 0 || ::stat(out.c_str(), &out_st) != 0) {
    std::string why = reason(read_log(log));
    if (why.empty()) why = "it exited with status " + std::to_string(status);
    throw InputError("OpenSCAD cannot flatten " + quoted(scad_path) + ": " + why);
  }
  return io_detail::read_whole_file(out, 512LL << 20, "too large a flattened program",
                                    io_detail::FileContent::Text);
}

}  // namespace csgfit
