// The solver's voxels as a NumPy .npy file (uint8, shape (nz, ny, nx)), for the OpenSCAD
// round trips that compare them with OpenSCAD's rendering (scripts/stl_voxelize.py).
#pragma once

#include <fstream>
#include <string>

#include "csgfit/model/voxel_grid.h"

namespace csgfit::testing {

inline void write_npy(const VoxelGrid& g, const std::string& path) {
  std::string header = "{'descr': '|u1', 'fortran_order': False, 'shape': (" +
                       std::to_string(g.nz()) + ", " + std::to_string(g.ny()) + ", " +
                       std::to_string(g.nx()) + "), }";
  // Magic (6) + version (2) + length (2) + header + '\n', padded to a multiple of 64.
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream out(path, std::ios::binary);
  out.write("\x93NUMPY\x01\x00", 8);
  const unsigned short len = static_cast<unsigned short>(header.size());
  const char len_bytes[2] = {static_cast<char>(len & 0xff), static_cast<char>(len >> 8)};
  out.write(len_bytes, 2);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  std::string bytes(static_cast<std::size_t>(g.nx()) * g.ny() * g.nz(), '\0');
  std::size_t idx = 0;
  for (int k = 0; k < g.nz(); ++k)
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i) bytes[idx++] = g.get(i, j, k) ? 1 : 0;
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace csgfit::testing
