#include "fcstd_writer.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "csgfit/error.h"
#include "csgfit/io/files.h"

namespace fs = std::filesystem;

namespace csgfit::cli {

namespace {

std::string writer_script() {
  const char* env = std::getenv("CSGFIT_FCSTD_WRITER");
  const std::string writer = env ? std::string(env)
                                 : (fs::path(CSGFIT_SOURCE_DIR) / "freecad_workbench" /
                                    "csgfit_freecad" / "fcstd_writer.py")
                                       .string();
  if (!fs::exists(writer))
    throw InputError("cannot write .FCStd: the FreeCAD writer '" + writer +
                     "' was not found (set CSGFIT_FCSTD_WRITER)");
  return writer;
}

// freecadcmd keeps argv to itself, so the script takes its arguments from the environment; its
// stderr goes to `log_path`, from which only its one-line reason reaches the user.
pid_t start_writer(const std::string& writer, const std::string& json_path,
                   const std::string& temp_abs, const std::string& out, const std::string& log_path) {
  const std::string doc_name = fs::path(out).stem().string();
  const pid_t pid = fork();
  if (pid == 0) {
    setenv("CSGFIT_JSON", json_path.c_str(), 1);
    setenv("CSGFIT_FCSTD", temp_abs.c_str(), 1);
    setenv("CSGFIT_DOC_NAME", doc_name.c_str(), 1);
    const int log = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int null = open("/dev/null", O_WRONLY);
    if (log >= 0) dup2(log, STDERR_FILENO);
    if (null >= 0) dup2(null, STDOUT_FILENO);
    execlp("freecadcmd", "freecadcmd", writer.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

std::string writer_reason(const std::string& log_path) {
  std::string reason;
  std::ifstream log(log_path);
  for (std::string line; std::getline(log, line);)
    if (line.rfind("csgfit: error:", 0) == 0) reason = line.substr(14);
  return reason;
}

}  // namespace

void write_fcstd(const std::string& json_text, const std::string& out) {
  const std::string writer = writer_script();
  const std::string stem =
      (fs::temp_directory_path() / ("csgfit-" + std::to_string(getpid()))).string();
  const std::string json_path = stem + ".json", log_path = stem + ".log";
  // Not through the command's batch: the document is the writer's input, not an output.
  {
    std::ofstream json_file(json_path, std::ios::binary | std::ios::trunc);
    json_file << json_text;
    if (!json_file.flush())
      throw InputError("cannot write '" + out + "': no room for its document in " +
                       fs::temp_directory_path().string());
  }
  // FreeCAD saves to a temporary file beside OUT, which then lands with the command's other
  // outputs, so that a failed save or a later failure leaves no document behind.
  const std::string temp = make_temp_beside(out);
  const pid_t pid = start_writer(writer, json_path, fs::absolute(temp).string(), out, log_path);
  int status = -1;
  if (pid > 0) waitpid(pid, &status, 0);
  const std::string reason = writer_reason(log_path);
  fs::remove(json_path);
  fs::remove(log_path);
  std::error_code ec;
  if (pid < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0 || fs::file_size(temp, ec) == 0) {
    fs::remove(temp, ec);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
      throw InputError("cannot write '" + out + "': freecadcmd is not installed");
    throw InputError("cannot write '" + out + "':" + (reason.empty() ? " FreeCAD failed" : reason));
  }
  publish_file(temp, out);
}

}  // namespace csgfit::cli
