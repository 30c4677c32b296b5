#include "csgfit/io/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "io/input_file.h"

namespace fs = std::filesystem;

namespace csgfit {

using io_detail::fail;
using io_detail::quoted;

namespace {

struct PendingFile {
  std::string temp, path;
};

// The open batch's waiting files; `open` is false outside a batch.
struct Batch {
  std::mutex mutex;
  bool open = false;
  std::vector<PendingFile> files;
};

Batch& batch() {
  static Batch b;
  return b;
}

// Unique per process and call, so that concurrent writers never share a temporary file.
std::string temp_suffix() {
  static std::atomic<unsigned long long> counter{0};
  unsigned long long random = 0;
  try {
    std::random_device device;
    random = (static_cast<unsigned long long>(device()) << 32) ^ device();
  } catch (const std::exception&) {
    random = static_cast<unsigned long long>(
        std::chrono::steady_clock::now().time_since_epoch().count());
  }
  random ^= counter.fetch_add(1) * 0x9E3779B97F4A7C15ULL;
  char suffix[64];
  std::snprintf(suffix, sizeof suffix, ".tmp-%ld-%016llx", static_cast<long>(::getpid()), random);
  return suffix;
}

// A hidden name beside `path` that keeps its extension (FreeCAD picks the format by it).
std::string temp_name(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / ("." + p.stem().string() + temp_suffix() + p.extension().string()))
      .string();
}

int create_temp(const std::string& path, std::string* temp) {
  int fd = -1;
  for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
    *temp = temp_name(path);
    fd = ::open(temp->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) fail("cannot write " + quoted(path) + ": " + std::strerror(errno));
  return fd;
}

void write_all(int fd, const std::string& contents, const std::string& path,
               const std::string& temp) {
  auto failure = [&](int error) {
    ::close(fd);
    ::unlink(temp.c_str());
    fail("cannot write " + quoted(path) + ": " + std::strerror(error));
  };
  const char* data = contents.data();
  std::size_t left = contents.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      failure(errno);
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    fail("cannot write " + quoted(path) + ": " + std::strerror(error));
  }
}

void rename_now(const std::string& temp, const std::string& path) {
  if (::rename(temp.c_str(), path.c_str()) == 0) return;
  const int error = errno;
  ::unlink(temp.c_str());
  fail("cannot write " + quoted(path) + ": " + std::strerror(error));
}

}  // namespace

std::string make_temp_beside(const std::string& path) {
  std::string temp;
  ::close(create_temp(path, &temp));
  return temp;
}

void publish_file(const std::string& temp, const std::string& path) {
  Batch& b = batch();
  {
    std::lock_guard<std::mutex> lock(b.mutex);
    if (b.open) {
      b.files.push_back({temp, path});
      return;
    }
  }
  rename_now(temp, path);
}

void write_file_atomic(const std::string& path, const std::string& contents) {
  std::error_code ec;
  if (fs::is_directory(fs::path(path), ec)) fail("cannot write " + quoted(path) + ": it is a folder");
  std::string temp;
  const int fd = create_temp(path, &temp);
  write_all(fd, contents, path, temp);
  publish_file(temp, path);
}

void check_writable(const std::string& path) {
  const fs::path parent = fs::absolute(fs::path(path)).parent_path();
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    fail("cannot write " + quoted(path) + ": folder '" + parent.string() + "' does not exist");
  if (fs::is_directory(fs::path(path), ec)) fail("cannot write " + quoted(path) + ": it is a folder");
  // access(W_OK) says yes to root everywhere, /proc included: only a real file tells.
  ::unlink(make_temp_beside(path).c_str());
}

OutputBatch::OutputBatch() {
  Batch& b = batch();
  std::lock_guard<std::mutex> lock(b.mutex);
  b.open = true;
  b.files.clear();
}

OutputBatch::~OutputBatch() {
  Batch& b = batch();
  std::lock_guard<std::mutex> lock(b.mutex);
  for (const PendingFile& f : b.files) ::unlink(f.temp.c_str());
  b.files.clear();
  b.open = false;
}

void OutputBatch::commit() {
  Batch& b = batch();
  std::lock_guard<std::mutex> lock(b.mutex);
  for (std::size_t i = 0; i < b.files.size(); ++i) {
    if (::rename(b.files[i].temp.c_str(), b.files[i].path.c_str()) == 0) continue;
    const int error = errno;
    for (std::size_t j = 0; j < i; ++j) ::unlink(b.files[j].path.c_str());
    const std::string path = b.files[i].path;
    // The destructor removes the temporary files still waiting (this one and the rest).
    b.files.erase(b.files.begin(), b.files.begin() + static_cast<std::ptrdiff_t>(i));
    fail("cannot write " + quoted(path) + ": " + std::strerror(error));
  }
  b.files.clear();
  b.open = false;
}

}  // namespace csgfit
