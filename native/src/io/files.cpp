#include "csgfit/io/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "io/input_file.h"

namespace csgfit {

using io_detail::fail;
using io_detail::quoted;

void write_file_atomic(const std::string& path, const std::string& contents) {
  // Unique per process and call, so that concurrent writers never share a temporary file.
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
  const std::string temp = path + suffix;

  auto failure = [&](int error) {
    ::unlink(temp.c_str());
    fail("cannot write " + quoted(path) + ": " + std::strerror(error));
  };
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) fail("cannot write " + quoted(path) + ": " + std::strerror(errno));
  const char* data = contents.data();
  std::size_t left = contents.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      failure(error);
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) failure(errno);
  if (::rename(temp.c_str(), path.c_str()) != 0) failure(errno);
}

}  // namespace csgfit
