#include "io/mesh/ply_body.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "io/byte_order.h"
#include "io/input_file.h"
#include "io/text_tokens.h"

namespace csgfit::io_detail {

namespace {

// Reads typed values from the binary body; every read is bounds-checked by the caller through
// has().
class PlyBinary {
 public:
  PlyBinary(const unsigned char* p, const unsigned char* end, bool big)
      : p_(p), end_(end), big_(big) {}
  bool has(std::size_t n) const { return static_cast<std::size_t>(end_ - p_) >= n; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  void skip(std::size_t n) { p_ += n; }
  double read(PlyType t) {
    const unsigned char* p = p_;
    p_ += ply_size(t);
    switch (t) {
      case PlyType::kInt8:
        return load<std::int8_t>(p, big_);
      case PlyType::kUint8:
        return load<std::uint8_t>(p, big_);
      case PlyType::kInt16:
        return load<std::int16_t>(p, big_);
      case PlyType::kUint16:
        return load<std::uint16_t>(p, big_);
      case PlyType::kInt32:
        return load<std::int32_t>(p, big_);
      case PlyType::kUint32:
        return load<std::uint32_t>(p, big_);
      case PlyType::kFloat32:
        return load<float>(p, big_);
      case PlyType::kFloat64:
        return load<double>(p, big_);
    }
    return 0;
  }

 private:
  const unsigned char* p_;
  const unsigned char* end_;
  bool big_;
};

class PlyBodyReader {
 public:
  PlyBodyReader(const std::string& path, const std::string& d, PlyRowVisitor& visitor)
      : path_(path), d_(d), visitor_(visitor) {}

  void read_ascii(const std::vector<PlyElement>& elements, std::size_t body);
  void read_binary(const std::vector<PlyElement>& elements, std::size_t body, bool big);

 private:
  [[noreturn]] void truncated(const PlyElement& e, unsigned long long got) const {
    fail(quoted(path_) + " is truncated: it declares " + std::to_string(e.count) + " " + e.name +
         " elements but the data ends after " + std::to_string(got));
  }
  std::size_t list_count(double v, std::size_t item_size, std::size_t available) const;
  void begin_row(const PlyElement& e) {
    values_.assign(e.properties.size(), 0);
    list_.clear();
  }

  const std::string& path_;
  const std::string& d_;
  PlyRowVisitor& visitor_;
  std::vector<double> values_, list_;
};

// A list's item count; SIZE_MAX when the items cannot fit in the `available` bytes, each
// taking at least item_size (ASCII: 2).
std::size_t PlyBodyReader::list_count(double v, std::size_t item_size,
                                      std::size_t available) const {
  if (!(v >= 0) || v != std::floor(v)) fail(quoted(path_) + ": a PLY list has a negative count");
  if (v > static_cast<double>(available / item_size)) return SIZE_MAX;
  return static_cast<std::size_t>(v);
}

void PlyBodyReader::read_ascii(const std::vector<PlyElement>& elements, std::size_t body) {
  Cursor a{d_.data() + std::min(body, d_.size()), d_.data() + d_.size()};
  for (const PlyElement& e : elements) {
    // Rows without properties take no bytes: a hostile count of them would loop (fuzz/).
    if (e.properties.empty()) continue;
    const bool wanted = visitor_.wanted(e);
    for (unsigned long long r = 0; r < e.count; ++r) {
      begin_row(e);
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        double v;
        std::string_view tok = next_token(a);
        if (tok.empty()) truncated(e, r);
        if (!parse_double(tok, &v)) {
          fail(quoted(path_) + " line " + std::to_string(a.line) + ": bad PLY value '" +
               std::string(tok.substr(0, 20)) + "'");
        }
        values_[pi] = v;
        if (!e.properties[pi].is_list) continue;
        const std::size_t n = list_count(v, 2, static_cast<std::size_t>(a.end - a.p));
        if (n == SIZE_MAX) truncated(e, r);
        const bool keep = wanted && visitor_.keeps_list(e, pi);
        for (std::size_t k = 0; k < n; ++k) {
          tok = next_token(a);
          if (tok.empty()) truncated(e, r);
          if (!parse_double(tok, &v)) {
            fail(quoted(path_) + " line " + std::to_string(a.line) + ": bad PLY list value");
          }
          if (keep) list_.push_back(v);
        }
      }
      if (wanted) visitor_.row(e, r, values_, list_);
    }
  }
}

void PlyBodyReader::read_binary(const std::vector<PlyElement>& elements, std::size_t body,
                                bool big) {
  const unsigned char* base = bytes_of(d_);
  PlyBinary in(base + std::min(body, d_.size()), base + d_.size(), big);
  for (const PlyElement& e : elements) {
    const bool wanted = visitor_.wanted(e);
    std::size_t stride = 0;
    bool fixed = true;
    for (const PlyProperty& p : e.properties) {
      if (p.is_list) {
        fixed = false;
      } else {
        stride += ply_size(p.type);
      }
    }
    if (fixed && stride != 0 && e.count > in.remaining() / stride) {
      truncated(e, in.remaining() / stride);
    }
    if (!wanted && fixed) {  // skipped in O(1), and a huge count has failed above at once
      in.skip(static_cast<std::size_t>(e.count) * stride);
      continue;
    }
    for (unsigned long long r = 0; r < e.count; ++r) {
      begin_row(e);
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        const PlyProperty& p = e.properties[pi];
        if (!p.is_list) {
          if (!in.has(ply_size(p.type))) truncated(e, r);
          values_[pi] = in.read(p.type);
          continue;
        }
        if (!in.has(ply_size(p.count_type))) truncated(e, r);
        const std::size_t item = ply_size(p.type);
        const double declared = in.read(p.count_type);  // before remaining() is taken
        values_[pi] = declared;
        const std::size_t n = list_count(declared, item, in.remaining());
        if (n == SIZE_MAX) truncated(e, r);
        if (wanted && visitor_.keeps_list(e, pi)) {
          for (std::size_t k = 0; k < n; ++k) list_.push_back(in.read(p.type));
        } else {
          in.skip(n * item);
        }
      }
      if (wanted) visitor_.row(e, r, values_, list_);
    }
  }
}

}  // namespace

void read_ply_rows(const std::string& path, const std::string& d, const PlyHeader& h,
                   PlyRowVisitor& visitor) {
  PlyBodyReader reader(path, d, visitor);
  if (h.format == PlyFormat::kAscii) {
    reader.read_ascii(h.elements, h.body);
  } else {
    reader.read_binary(h.elements, h.body, h.format == PlyFormat::kBig);
  }
}

}  // namespace csgfit::io_detail
