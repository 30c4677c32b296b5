#include "csgfit/features/features2d.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace csgfit {

namespace {
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

// Felzenszwalb-Huttenlocher lower envelope of parabolas: squared distance transform of one line.
void edt_1d(const float* f, float* d, int n, std::vector<int>& v, std::vector<float>& z) {
  v.resize(static_cast<std::size_t>(n));
  z.resize(static_cast<std::size_t>(n) + 1);
  int k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<float>::infinity();
  z[1] = std::numeric_limits<float>::infinity();
  for (int q = 1; q < n; ++q) {
    float s;
    for (;;) {
      const int p = v[static_cast<std::size_t>(k)];
      s = ((f[q] + static_cast<float>(q * q)) - (f[p] + static_cast<float>(p * p))) /
          static_cast<float>(2 * q - 2 * p);
      if (s <= z[static_cast<std::size_t>(k)] && k > 0) {
        --k;
        continue;
      }
      break;
    }
    if (s <= z[static_cast<std::size_t>(k)]) {
      // k == 0 and the new parabola dominates everywhere.
      v[0] = q;
      z[0] = -std::numeric_limits<float>::infinity();
      z[1] = std::numeric_limits<float>::infinity();
      continue;
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k) + 1] = std::numeric_limits<float>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[static_cast<std::size_t>(k) + 1] < static_cast<float>(q)) ++k;
    const int p = v[static_cast<std::size_t>(k)];
    d[q] = static_cast<float>((q - p) * (q - p)) + f[p];
  }
}

}  // namespace

std::vector<Region> connected_regions(const Bitmap& mask, int connectivity, int col_min,
                                      int row_min, int col_max, int row_max) {
  std::vector<Region> out;
  const int w = mask.width(), h = mask.height();
  col_min = std::max(col_min, 0);
  row_min = std::max(row_min, 0);
  col_max = std::min(col_max, w - 1);
  row_max = std::min(row_max, h - 1);
  if (col_min > col_max || row_min > row_max) return out;
  Bitmap seen(w, h);
  std::vector<std::pair<int, int>> stack;
  static const int n4[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  static const int n8[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  const int (*nb)[2] = connectivity == 8 ? n8 : n4;
  const int nn = connectivity == 8 ? 8 : 4;
  for (int r = row_min; r <= row_max; ++r) {
    for (int c = col_min; c <= col_max; ++c) {
      if (!mask.get(c, r) || seen.get(c, r)) continue;
      Region reg;
      reg.mask = Bitmap(w, h);
      reg.col_min = reg.col_max = c;
      reg.row_min = reg.row_max = r;
      seen.set(c, r);
      stack.emplace_back(c, r);
      while (!stack.empty()) {
        auto [pc, pr] = stack.back();
        stack.pop_back();
        reg.mask.set(pc, pr);
        ++reg.area;
        reg.col_min = std::min(reg.col_min, pc);
        reg.col_max = std::max(reg.col_max, pc);
        reg.row_min = std::min(reg.row_min, pr);
        reg.row_max = std::max(reg.row_max, pr);
        for (int i = 0; i < nn; ++i) {
          const int qc = pc + nb[i][0], qr = pr + nb[i][1];
          if (qc < col_min || qc > col_max || qr < row_min || qr > row_max) continue;
          if (!mask.get(qc, qr) || seen.get(qc, qr)) continue;
          seen.set(qc, qr);
          stack.emplace_back(qc, qr);
        }
      }
      out.push_back(std::move(reg));
    }
  }
  return out;
}

std::vector<Region> connected_regions(const Bitmap& mask, int connectivity) {
  return connected_regions(mask, connectivity, 0, 0, mask.width() - 1, mask.height() - 1);
}

Moments compute_moments(const Bitmap& mask) {
  Moments m;
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  const int h = mask.height();
  for (int r = 0; r < h; ++r) {
    const std::uint64_t* words = mask.row_words(r);
    const double y = h - r - 0.5;
    for (int wi = 0; wi < mask.words_per_row(); ++wi) {
      std::uint64_t w = words[wi];
      while (w) {
        const int bit = __builtin_ctzll(w);
        w &= w - 1;
        const double x = wi * 64 + bit + 0.5;
        m.area += 1;
        sx += x;
        sy += y;
        sxx += x * x;
        syy += y * y;
        sxy += x * y;
      }
    }
  }
  if (m.area == 0) return m;
  m.cx = sx / m.area;
  m.cy = sy / m.area;
  // Each pixel is a unit square, not a point: it adds 1/12 to the variance along each axis.
  m.cxx = sxx / m.area - m.cx * m.cx + 1.0 / 12.0;
  m.cyy = syy / m.area - m.cy * m.cy + 1.0 / 12.0;
  m.cxy = sxy / m.area - m.cx * m.cy;
  const double tr = m.cxx + m.cyy;
  const double det = m.cxx * m.cyy - m.cxy * m.cxy;
  const double disc = std::sqrt(std::max(tr * tr / 4 - det, 0.0));
  m.lambda1 = tr / 2 + disc;
  m.lambda2 = std::max(tr / 2 - disc, 0.0);
  m.angle = 0.5 * std::atan2(2 * m.cxy, m.cxx - m.cyy) * kRadToDeg;
  return m;
}

std::vector<float> distance_map(const Bitmap& mask, bool outside_is_background) {
  const int w = mask.width(), h = mask.height();
  // Pad by one pixel of background so that the canvas edge counts as background.
  const int pad = outside_is_background ? 1 : 0;
  const int pw = w + 2 * pad, ph = h + 2 * pad;
  const float inf = 1e20f;
  std::vector<float> grid(static_cast<std::size_t>(pw) * static_cast<std::size_t>(ph), 0.0f);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c)
      if (mask.get(c, r)) grid[static_cast<std::size_t>(r + pad) * pw + (c + pad)] = inf;
  std::vector<int> v;
  std::vector<float> z, f(static_cast<std::size_t>(std::max(pw, ph))),
      d(static_cast<std::size_t>(std::max(pw, ph)));
  for (int c = 0; c < pw; ++c) {
    for (int r = 0; r < ph; ++r) f[static_cast<std::size_t>(r)] = grid[static_cast<std::size_t>(r) * pw + c];
    edt_1d(f.data(), d.data(), ph, v, z);
    for (int r = 0; r < ph; ++r) grid[static_cast<std::size_t>(r) * pw + c] = d[static_cast<std::size_t>(r)];
  }
  for (int r = 0; r < ph; ++r) {
    float* row = grid.data() + static_cast<std::size_t>(r) * pw;
    std::copy(row, row + pw, f.begin());
    edt_1d(f.data(), row, pw, v, z);
  }
  std::vector<float> out(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c)
      out[static_cast<std::size_t>(r) * w + c] = grid[static_cast<std::size_t>(r + pad) * pw + (c + pad)];
  return out;
}

std::vector<DistancePeak> distance_peaks(const Bitmap& mask, double min_distance,
                                         std::size_t limit) {
  const int w = mask.width(), h = mask.height();
  const std::vector<float> d2 = distance_map(mask);
  std::vector<DistancePeak> peaks;
  const float min2 = static_cast<float>(min_distance * min_distance);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const float v = d2[static_cast<std::size_t>(r) * w + c];
      if (v <= 0 || v < min2) continue;
      bool is_max = true;
      for (int dr = -1; dr <= 1 && is_max; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          if (!dr && !dc) continue;
          const int qr = r + dr, qc = c + dc;
          if (qr < 0 || qr >= h || qc < 0 || qc >= w) continue;
          const float u = d2[static_cast<std::size_t>(qr) * w + qc];
          // Plateaus: keep only the first pixel in scan order.
          if (u > v || (u == v && (dr < 0 || (dr == 0 && dc < 0)))) {
            is_max = false;
            break;
          }
        }
      if (is_max) peaks.push_back({c + 0.5, h - r - 0.5, std::sqrt(static_cast<double>(v))});
    }
  }
  std::stable_sort(peaks.begin(), peaks.end(),
                   [](const DistancePeak& a, const DistancePeak& b) { return a.distance > b.distance; });
  if (peaks.size() > limit) peaks.resize(limit);
  return peaks;
}

std::vector<std::pair<int, int>> boundary_pixels(const Bitmap& mask) {
  std::vector<std::pair<int, int>> out;
  const int w = mask.width(), h = mask.height();
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      if (!mask.get(c, r)) continue;
      if (c == 0 || r == 0 || c == w - 1 || r == h - 1 || !mask.get(c - 1, r) ||
          !mask.get(c + 1, r) || !mask.get(c, r - 1) || !mask.get(c, r + 1))
        out.emplace_back(c, r);
    }
  return out;
}

}  // namespace csgfit
