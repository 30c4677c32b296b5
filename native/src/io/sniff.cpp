#include "io/sniff.h"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "io/input_file.h"

namespace csgfit::io_detail {

namespace {

// The text formats, recognised after leading white space.
std::string sniff_text(const std::string& d) {
  std::size_t i = 0;
  while (i < d.size() && std::isspace(static_cast<unsigned char>(d[i]))) ++i;
  const char* p = d.data() + i;
  const char* end = d.data() + d.size();
  if (starts_with_ci(p, end, "solid") && !has_binary_bytes(d, 4096) &&
      d.find("facet", i) != std::string::npos) {
    return "an ASCII STL mesh";
  }
  // OFF headers may carry prefixes (COFF, NOFF, STOFF...).
  std::size_t j = i;
  while (j < d.size() && j < i + 6 && std::strchr("STCN4n", d[j]) != nullptr && d[j] != 0) ++j;
  if (d.compare(j, 3, "OFF") == 0 &&
      (j + 3 == d.size() || std::isspace(static_cast<unsigned char>(d[j + 3])))) {
    return "an OFF mesh";
  }
  return "";
}

}  // namespace

bool starts_with(const std::string& d, const char* prefix) {
  return d.compare(0, std::strlen(prefix), prefix) == 0;
}

bool starts_with_ci(const char* p, const char* end, const char* word) {
  for (; *word; ++word, ++p) {
    if (p >= end || std::tolower(static_cast<unsigned char>(*p)) != *word) return false;
  }
  return true;
}

bool has_binary_bytes(const std::string& d, std::size_t limit) {
  const std::size_t n = std::min(d.size(), limit);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(d[i]);
    if (c == 0 || (c < 32 && c != '\n' && c != '\r' && c != '\t' && c != '\f' && c != '\v')) {
      return true;
    }
  }
  return false;
}

std::string sniff(const std::string& d) {
  if (starts_with(d, "\x89PNG")) return "a PNG image";
  if (d.size() >= 3 && static_cast<unsigned char>(d[0]) == 0xFF &&
      static_cast<unsigned char>(d[1]) == 0xD8 && static_cast<unsigned char>(d[2]) == 0xFF) {
    return "a JPEG image";
  }
  if (starts_with(d, "GIF8")) return "a GIF image";
  if (starts_with(d, "%PDF")) return "a PDF document";
  if (starts_with(d, "PK\x03\x04")) return "a ZIP archive (3MF or a compressed mesh?)";
  if (d.size() >= 2 && static_cast<unsigned char>(d[0]) == 0x1F &&
      static_cast<unsigned char>(d[1]) == 0x8B) {
    return "gzip-compressed data";
  }
  if (starts_with(d, "\x93NUMPY")) return "a NumPy array (.npy)";
  if (starts_with(d, "#binvox")) return "a binvox voxel grid";
  if (starts_with(d, "ply\n") || starts_with(d, "ply\r")) return "a PLY mesh";
  if (starts_with(d, "glTF")) return "a binary glTF (.glb)";
  if (starts_with(d, "ISO-10303-21")) return "a STEP file";
  if (starts_with(d, "<?xml")) return "an XML document";
  return sniff_text(d);
}

void fail_mislabelled(const std::string& path, const std::string& what,
                      const std::string& expected) {
  fail(quoted(path) + " looks like " + what + ", not " + expected + " (wrong file extension?)");
}

}  // namespace csgfit::io_detail
