#include "io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>

#include "csgfit/error.h"
#include "csgfit/model/memory_budget.h"
#include "io/sniff.h"

namespace csgfit::io_detail {

namespace {

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

// A NUL in a text format is another format, corruption or a sparse file: said where it is met,
// before the rest is read (a 1 GiB file of zeros is refused after 64 KiB).
void refuse_binary(const std::string& path, const std::string& read, const char* chunk,
                   std::size_t n) {
  const void* nul = std::memchr(chunk, 0, n);
  if (!nul) return;
  const std::string what = sniff(read.empty() ? std::string(chunk, n) : read);
  if (!what.empty()) fail_mislabelled(path, what, "a text file");
  fail(quoted(path) + " contains binary data (a NUL byte at offset " +
       std::to_string(read.size() + static_cast<std::size_t>(static_cast<const char*>(nul) - chunk)) +
       "), not text");
}

}  // namespace

void fail(const std::string& message) { throw InputError(message); }

std::string count_text(std::size_t n, const char* noun) {
  const std::string word = noun;
  if (n == 1) return "1 " + word;
  // The one irregular plural the readers count.
  return std::to_string(n) + " " + (word == "vertex" ? std::string("vertices") : word + "s");
}

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string read_whole_file(const std::string& path, long long max_bytes,
                            const char* limit_reason, FileContent content) {
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) fail("cannot open " + quoted(path) + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) {
    fail("cannot open " + quoted(path) + ": " + std::strerror(errno));
  }
  if (S_ISDIR(st.st_mode)) fail("cannot open " + quoted(path) + ": " + std::strerror(EISDIR));
  // Devices such as /dev/zero would never end; pipes are fine (reading from a shell pipeline).
  if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
    fail("cannot open " + quoted(path) + ": not a regular file");
  }
  const std::string too_big =
      quoted(path) + " is larger than " + std::to_string(max_bytes) + " bytes, " + limit_reason;
  if (S_ISREG(st.st_mode) && st.st_size > max_bytes) fail(too_big);
  if (S_ISREG(st.st_mode)) check_allocation(static_cast<double>(st.st_size), "reading " + quoted(path));
  std::string data;
  if (S_ISREG(st.st_mode)) data.reserve(static_cast<std::size_t>(st.st_size));
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd.get(), chunk, sizeof chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("cannot read " + quoted(path) + ": " + std::strerror(errno));
    }
    if (n == 0) break;
    if (static_cast<long long>(data.size()) + n > max_bytes) fail(too_big);
    if (content == FileContent::Text) refuse_binary(path, data, chunk, static_cast<std::size_t>(n));
    data.append(chunk, static_cast<std::size_t>(n));
  }
  if (data.empty()) fail(quoted(path) + " is empty (0 bytes)");
  return data;
}

}  // namespace csgfit::io_detail
