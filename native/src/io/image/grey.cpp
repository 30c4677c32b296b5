#include "io/image/grey.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace csgfit::image_detail {

namespace {

// Area-average downsampling, streamed one source row at a time so that only the small output
// is held in floating point. Overlaps are exact integers: a source pixel is `dst` units wide,
// an output pixel `src` units. Grey is averaged weighted by alpha so that the colour hidden
// under transparent pixels (often black) does not bleed into the edge.
class AreaDownsampler {
 public:
  AreaDownsampler(int src_width, int src_height, int dst_width, int dst_height, bool has_alpha)
      : src_width_(src_width),
        src_height_(src_height),
        dst_width_(dst_width),
        dst_height_(dst_height),
        has_alpha_(has_alpha),
        col_spans_(spans(src_width, dst_width)),
        row_spans_(spans(src_height, dst_height)),
        acc_grey_(static_cast<std::size_t>(dst_width) * dst_height, 0.0),
        row_grey_(static_cast<std::size_t>(dst_width)),
        row_grey_alpha_(static_cast<std::size_t>(dst_width)),
        row_alpha_(static_cast<std::size_t>(dst_width)) {
    if (has_alpha_) {
      acc_grey_alpha_.assign(acc_grey_.size(), 0.0);
      acc_alpha_.assign(acc_grey_.size(), 0.0);
    }
  }

  void add_row(int row, const std::uint8_t* grey, const std::uint8_t* alpha) {
    std::fill(row_grey_.begin(), row_grey_.end(), 0.0);
    std::fill(row_grey_alpha_.begin(), row_grey_alpha_.end(), 0.0);
    std::fill(row_alpha_.begin(), row_alpha_.end(), 0.0);
    for (int c = 0; c < src_width_; ++c) {
      const Span& s = col_spans_[static_cast<std::size_t>(c)];
      const double g = grey[c];
      const double a = has_alpha_ ? alpha[c] : 255.0;
      add_horizontal(s.first, static_cast<double>(s.weight_first), g, a);
      if (s.weight_second > 0) {
        add_horizontal(s.first + 1, static_cast<double>(s.weight_second), g, a);
      }
    }
    const Span& s = row_spans_[static_cast<std::size_t>(row)];
    add_vertical(s.first, static_cast<double>(s.weight_first));
    if (s.weight_second > 0) add_vertical(s.first + 1, static_cast<double>(s.weight_second));
  }

  GreyImage finish() const {
    GreyImage out;
    out.width = dst_width_;
    out.height = dst_height_;
    const std::size_t n = acc_grey_.size();
    out.grey.resize(n);
    if (has_alpha_) out.alpha.resize(n);
    const double total = static_cast<double>(src_width_) * static_cast<double>(src_height_);
    auto to8 = [](double v) {
      return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    };
    for (std::size_t i = 0; i < n; ++i) {
      if (has_alpha_) {
        out.alpha[i] = to8(acc_alpha_[i] / total);
        out.grey[i] =
            acc_alpha_[i] > 0 ? to8(acc_grey_alpha_[i] / acc_alpha_[i]) : to8(acc_grey_[i] / total);
      } else {
        out.grey[i] = to8(acc_grey_[i] / total);
      }
    }
    return out;
  }

 private:
  // Source pixel i covers [i*dst, (i+1)*dst) and output pixel o covers [o*src, (o+1)*src);
  // with dst <= src a source pixel overlaps at most two output pixels.
  struct Span {
    int first = 0;
    long long weight_first = 0;
    long long weight_second = 0;
  };

  static std::vector<Span> spans(int src, int dst) {
    std::vector<Span> result(static_cast<std::size_t>(src));
    for (int i = 0; i < src; ++i) {
      const long long begin = static_cast<long long>(i) * dst;
      const long long end = begin + dst;
      const long long first = begin / src;
      const long long boundary = (first + 1) * src;
      Span& s = result[static_cast<std::size_t>(i)];
      s.first = static_cast<int>(first);
      if (end <= boundary) {
        s.weight_first = dst;
      } else {
        s.weight_first = boundary - begin;
        s.weight_second = end - boundary;
      }
    }
    return result;
  }

  void add_horizontal(int col, double weight, double grey, double alpha) {
    const std::size_t c = static_cast<std::size_t>(col);
    row_grey_[c] += weight * grey;
    row_grey_alpha_[c] += weight * grey * alpha;
    row_alpha_[c] += weight * alpha;
  }

  void add_vertical(int row, double weight) {
    const std::size_t base = static_cast<std::size_t>(row) * static_cast<std::size_t>(dst_width_);
    for (std::size_t c = 0; c < row_grey_.size(); ++c) {
      acc_grey_[base + c] += weight * row_grey_[c];
      if (has_alpha_) {
        acc_grey_alpha_[base + c] += weight * row_grey_alpha_[c];
        acc_alpha_[base + c] += weight * row_alpha_[c];
      }
    }
  }

  int src_width_;
  int src_height_;
  int dst_width_;
  int dst_height_;
  bool has_alpha_;
  std::vector<Span> col_spans_;
  std::vector<Span> row_spans_;
  std::vector<double> acc_grey_;
  std::vector<double> acc_grey_alpha_;
  std::vector<double> acc_alpha_;
  std::vector<double> row_grey_;
  std::vector<double> row_grey_alpha_;
  std::vector<double> row_alpha_;
};

}  // namespace

template <typename T, typename To8>
void DecodedPixels::convert(const T* in, std::uint8_t* grey, std::uint8_t* alpha, To8 to8) const {
  // Rec. 601 luma; exact for grey pixels (r = g = b).
  auto luma = [](unsigned r, unsigned g, unsigned b) {
    return static_cast<std::uint8_t>((299u * r + 587u * g + 114u * b + 500u) / 1000u);
  };
  for (int c = 0; c < width; ++c, in += channels) {
    std::uint8_t a = 255;
    switch (channels) {
      case 1:
        grey[c] = static_cast<std::uint8_t>(to8(in[0]));
        break;
      case 2:
        grey[c] = static_cast<std::uint8_t>(to8(in[0]));
        a = static_cast<std::uint8_t>(to8(in[1]));
        break;
      case 3:
        grey[c] = luma(to8(in[0]), to8(in[1]), to8(in[2]));
        break;
      default:
        grey[c] = luma(to8(in[0]), to8(in[1]), to8(in[2]));
        a = static_cast<std::uint8_t>(to8(in[3]));
        break;
    }
    if (alpha != nullptr) alpha[c] = a;
  }
}

void DecodedPixels::convert_row(int row, std::uint8_t* grey, std::uint8_t* alpha) const {
  const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(width) *
                            static_cast<std::size_t>(channels);
  if (sixteen_bit) {
    convert(static_cast<const std::uint16_t*>(data) + first, grey, alpha,
            [](std::uint16_t v) { return static_cast<unsigned>((v * 255u + 32767u) / 65535u); });
  } else {
    convert(static_cast<const std::uint8_t*>(data) + first, grey, alpha,
            [](std::uint8_t v) { return static_cast<unsigned>(v); });
  }
}

GreyImage to_grey_image(const DecodedPixels& pixels, int out_width, int out_height) {
  std::vector<std::uint8_t> grey_row(static_cast<std::size_t>(pixels.width));
  std::vector<std::uint8_t> alpha_row(static_cast<std::size_t>(pixels.width));
  if (out_width == pixels.width && out_height == pixels.height) {
    GreyImage out;
    out.width = pixels.width;
    out.height = pixels.height;
    const std::size_t n =
        static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height);
    out.grey.resize(n);
    if (pixels.has_alpha()) out.alpha.resize(n);
    for (int r = 0; r < pixels.height; ++r) {
      const std::size_t first = static_cast<std::size_t>(r) * static_cast<std::size_t>(out.width);
      pixels.convert_row(r, out.grey.data() + first,
                         pixels.has_alpha() ? out.alpha.data() + first : nullptr);
    }
    return out;
  }
  AreaDownsampler sampler(pixels.width, pixels.height, out_width, out_height, pixels.has_alpha());
  for (int r = 0; r < pixels.height; ++r) {
    pixels.convert_row(r, grey_row.data(), pixels.has_alpha() ? alpha_row.data() : nullptr);
    sampler.add_row(r, grey_row.data(), alpha_row.data());
  }
  return sampler.finish();
}

}  // namespace csgfit::image_detail
