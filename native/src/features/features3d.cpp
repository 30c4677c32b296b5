#include "csgfit/features/features3d.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace csgfit {

VoxelGrid crop(const VoxelGrid& grid, const int lo[3], const int hi[3], int pad) {
  const double s = grid.voxel_size();
  const int nx = hi[0] - lo[0] + 1 + 2 * pad, ny = hi[1] - lo[1] + 1 + 2 * pad,
            nz = hi[2] - lo[2] + 1 + 2 * pad;
  VoxelGrid out(std::max(nx, 0), std::max(ny, 0), std::max(nz, 0),
                grid.origin_x() + (lo[0] - pad) * s, grid.origin_y() + (lo[1] - pad) * s,
                grid.origin_z() + (lo[2] - pad) * s, s);
  for (int k = 0; k < out.nz(); ++k) {
    const int gk = k + lo[2] - pad;
    if (gk < 0 || gk >= grid.nz()) continue;
    for (int j = 0; j < out.ny(); ++j) {
      const int gj = j + lo[1] - pad;
      if (gj < 0 || gj >= grid.ny()) continue;
      const std::uint64_t* row = grid.row_words(gj, gk);
      const int i0 = std::max(0, pad - lo[0]), i1 = std::min(out.nx(), grid.nx() - lo[0] + pad);
      for (int i = i0; i < i1; ++i) {
        const int gi = i + lo[0] - pad;
        if ((row[gi >> 6] >> (gi & 63)) & 1u) out.set(i, j, k);
      }
    }
  }
  return out;
}

int dual_connectivity(int connectivity) { return connectivity == 6 ? 26 : 6; }

std::vector<Region3D> connected_regions3d(const VoxelGrid& mask, int connectivity) {
  if (connectivity != 6 && connectivity != 18 && connectivity != 26)
    throw std::invalid_argument("connectivity must be 6, 18 or 26");
  std::vector<Region3D> out;
  const int nx = mask.nx(), ny = mask.ny(), nz = mask.nz();
  if (mask.empty()) return out;
  // Neighbour offsets: faces first, then edges, then corners.
  std::vector<std::array<int, 3>> nb;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int n = std::abs(dx) + std::abs(dy) + std::abs(dz);
        if (n == 0) continue;
        if (n == 1 || (n == 2 && connectivity >= 18) || (n == 3 && connectivity == 26))
          nb.push_back({dx, dy, dz});
      }
  const std::size_t total = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<std::uint8_t> seen(total, 0);
  std::vector<std::uint32_t> stack, members;
  auto index = [&](int i, int j, int k) {
    return static_cast<std::uint32_t>((static_cast<std::size_t>(k) * ny + j) * nx + i);
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const std::uint64_t* row = mask.row_words(j, k);
      for (int wi = 0; wi < mask.words_per_row(); ++wi) {
        std::uint64_t w = row[wi];
        while (w) {
          const int i = wi * 64 + __builtin_ctzll(w);
          w &= w - 1;
          const std::uint32_t start = index(i, j, k);
          if (seen[start]) continue;
          seen[start] = 1;
          stack.assign(1, start);
          members.clear();
          int lo[3] = {i, j, k}, hi[3] = {i, j, k};
          while (!stack.empty()) {
            const std::uint32_t v = stack.back();
            stack.pop_back();
            members.push_back(v);
            const int vi = static_cast<int>(v % static_cast<std::uint32_t>(nx));
            const int vj = static_cast<int>((v / static_cast<std::uint32_t>(nx)) % static_cast<std::uint32_t>(ny));
            const int vk = static_cast<int>(v / (static_cast<std::uint32_t>(nx) * static_cast<std::uint32_t>(ny)));
            lo[0] = std::min(lo[0], vi), hi[0] = std::max(hi[0], vi);
            lo[1] = std::min(lo[1], vj), hi[1] = std::max(hi[1], vj);
            lo[2] = std::min(lo[2], vk), hi[2] = std::max(hi[2], vk);
            for (const auto& d : nb) {
              const int qi = vi + d[0], qj = vj + d[1], qk = vk + d[2];
              if (qi < 0 || qj < 0 || qk < 0 || qi >= nx || qj >= ny || qk >= nz) continue;
              const std::uint32_t q = index(qi, qj, qk);
              if (seen[q] || !mask.get(qi, qj, qk)) continue;
              seen[q] = 1;
              stack.push_back(q);
            }
          }
          Region3D reg;
          const double s = mask.voxel_size();
          reg.mask = VoxelGrid(hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1,
                               mask.origin_x() + lo[0] * s, mask.origin_y() + lo[1] * s,
                               mask.origin_z() + lo[2] * s, s);
          for (std::uint32_t v : members) {
            const int vi = static_cast<int>(v % static_cast<std::uint32_t>(nx));
            const int vj = static_cast<int>((v / static_cast<std::uint32_t>(nx)) % static_cast<std::uint32_t>(ny));
            const int vk = static_cast<int>(v / (static_cast<std::uint32_t>(nx) * static_cast<std::uint32_t>(ny)));
            reg.mask.set(vi - lo[0], vj - lo[1], vk - lo[2]);
          }
          for (int a = 0; a < 3; ++a) reg.lo[a] = lo[a], reg.hi[a] = hi[a];
          reg.volume = members.size();
          out.push_back(std::move(reg));
        }
      }
    }
  return out;
}


Moments3D compute_moments3d(const VoxelGrid& mask) {
  Moments3D m;
  // Accumulate in voxel-index units about the grid's middle (keeps the sums well conditioned),
  // then convert.
  const double mx = 0.5 * mask.nx(), my = 0.5 * mask.ny(), mz = 0.5 * mask.nz();
  double n = 0, sx = 0, sy = 0, sz = 0, sxx = 0, syy = 0, szz = 0, sxy = 0, sxz = 0, syz = 0;
  for (int k = 0; k < mask.nz(); ++k)
    for (int j = 0; j < mask.ny(); ++j) {
      const std::uint64_t* row = mask.row_words(j, k);
      const double y = j + 0.5 - my, z = k + 0.5 - mz;
      double rn = 0, rx = 0, rxx = 0;
      for (int wi = 0; wi < mask.words_per_row(); ++wi) {
        std::uint64_t w = row[wi];
        while (w) {
          const double x = wi * 64 + __builtin_ctzll(w) + 0.5 - mx;
          w &= w - 1;
          rn += 1, rx += x, rxx += x * x;
        }
      }
      if (rn == 0) continue;
      n += rn, sx += rx, sxx += rxx;
      sy += rn * y, sz += rn * z, syy += rn * y * y, szz += rn * z * z;
      sxy += rx * y, sxz += rx * z, syz += rn * y * z;
    }
  if (n == 0) return m;
  const double s = mask.voxel_size();
  m.voxels = static_cast<std::size_t>(n);
  m.volume = n * s * s * s;
  const double cx = sx / n, cy = sy / n, cz = sz / n;
  m.centroid = {mask.origin_x() + (cx + mx) * s, mask.origin_y() + (cy + my) * s,
                mask.origin_z() + (cz + mz) * s};
  const double s2 = s * s;
  m.covariance[0][0] = (sxx / n - cx * cx + 1.0 / 12) * s2;
  m.covariance[1][1] = (syy / n - cy * cy + 1.0 / 12) * s2;
  m.covariance[2][2] = (szz / n - cz * cz + 1.0 / 12) * s2;
  m.covariance[0][1] = m.covariance[1][0] = (sxy / n - cx * cy) * s2;
  m.covariance[0][2] = m.covariance[2][0] = (sxz / n - cx * cz) * s2;
  m.covariance[1][2] = m.covariance[2][1] = (syz / n - cy * cz) * s2;
  symmetric_eigen3(m.covariance, m.variances, m.axes);
  return m;
}

VoxelGrid erode6(const VoxelGrid& mask) {
  VoxelGrid out(mask.nx(), mask.ny(), mask.nz(), mask.origin_x(), mask.origin_y(),
                mask.origin_z(), mask.voxel_size());
  const int wpr = mask.words_per_row();
  for (int k = 1; k + 1 < mask.nz(); ++k)
    for (int j = 1; j + 1 < mask.ny(); ++j) {
      const std::uint64_t* c = mask.row_words(j, k);
      const std::uint64_t* a = mask.row_words(j - 1, k);
      const std::uint64_t* b = mask.row_words(j + 1, k);
      const std::uint64_t* d = mask.row_words(j, k - 1);
      const std::uint64_t* e = mask.row_words(j, k + 1);
      std::uint64_t* o = out.row_words(j, k);
      for (int wi = 0; wi < wpr; ++wi) {
        // x neighbours by shifting across word boundaries; bits past nx are zero and nothing
        // shifts in below voxel 0, so the first and last voxel of a row never survive.
        const std::uint64_t left = (c[wi] << 1) | (wi > 0 ? c[wi - 1] >> 63 : 0);
        const std::uint64_t right = (c[wi] >> 1) | (wi + 1 < wpr ? c[wi + 1] << 63 : 0);
        o[wi] = c[wi] & a[wi] & b[wi] & d[wi] & e[wi] & left & right;
      }
    }
  return out;
}

}  // namespace csgfit
