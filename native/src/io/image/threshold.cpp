// Grey to shape: Otsu's threshold when none is given, alpha < 128 always background.

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include "csgfit/io/image.h"
#include "io/input_file.h"

namespace csgfit {

int otsu_threshold(const GreyImage& image) {
  // With a single grey level (or nothing opaque) there is nothing to separate; the middle of
  // the range makes a uniform dark image all shape and a uniform light one all background.
  constexpr int kUniformThreshold = 127;
  std::array<long long, 256> histogram{};
  const bool has_alpha = !image.alpha.empty();
  for (std::size_t i = 0; i < image.grey.size(); ++i) {
    if (has_alpha && image.alpha[i] < 128) continue;
    ++histogram[image.grey[i]];
  }
  long long total = 0;
  double total_sum = 0;
  for (int i = 0; i < 256; ++i) {
    total += histogram[static_cast<std::size_t>(i)];
    total_sum +=
        static_cast<double>(i) * static_cast<double>(histogram[static_cast<std::size_t>(i)]);
  }
  if (total == 0) return kUniformThreshold;

  // Class 0 is "grey <= t". Maximise the between-class variance w0 * w1 * (mu0 - mu1)^2.
  double best = -1;
  int best_t = -1;
  long long n0 = 0;
  double sum0 = 0;
  for (int t = 0; t < 255; ++t) {
    n0 += histogram[static_cast<std::size_t>(t)];
    sum0 += static_cast<double>(t) * static_cast<double>(histogram[static_cast<std::size_t>(t)]);
    const long long n1 = total - n0;
    if (n0 == 0 || n1 == 0) continue;
    const double w0 = static_cast<double>(n0) / static_cast<double>(total);
    const double w1 = 1.0 - w0;
    const double mu0 = sum0 / static_cast<double>(n0);
    const double mu1 = (total_sum - sum0) / static_cast<double>(n1);
    const double variance = w0 * w1 * (mu0 - mu1) * (mu0 - mu1);
    if (variance > best * (1 + 1e-12)) {
      best = variance;
      best_t = t;
    }
  }
  if (best_t < 0) return kUniformThreshold;
  // Every t across the empty bins after best_t gives the same split; take the middle of that
  // gap, which is the most robust cut for clean two-level images (0/255 gives 127).
  int gap_end = best_t;
  while (gap_end + 1 < 255 && histogram[static_cast<std::size_t>(gap_end + 1)] == 0) ++gap_end;
  return (best_t + gap_end) / 2;
}

Bitmap threshold_image(const GreyImage& image, const ImageReadOptions& options) {
  const std::size_t n = static_cast<std::size_t>(std::max(image.width, 0)) *
                        static_cast<std::size_t>(std::max(image.height, 0));
  if (image.width < 0 || image.height < 0 || image.grey.size() != n ||
      (!image.alpha.empty() && image.alpha.size() != n)) {
    throw std::invalid_argument("threshold_image: grey/alpha sizes do not match the image size");
  }
  if (options.threshold > 255) {
    io_detail::fail("threshold " + std::to_string(options.threshold) + " is outside 0..255");
  }
  const int threshold = options.threshold >= 0 ? options.threshold : otsu_threshold(image);
  Bitmap bitmap(image.width, image.height);
  const bool has_alpha = !image.alpha.empty();
  std::size_t i = 0;
  for (int r = 0; r < image.height; ++r) {
    for (int c = 0; c < image.width; ++c, ++i) {
      if (has_alpha && image.alpha[i] < 128) continue;
      const bool dark = image.grey[i] <= threshold;
      if (dark != options.invert) bitmap.set(c, r);
    }
  }
  return bitmap;
}

Bitmap read_bitmap(const std::string& path, const ImageReadOptions& options) {
  return threshold_image(read_image(path, options), options);
}

}  // namespace csgfit
