// read_mesh, read_voxels and read_input3d: the extension picks the format.

#include <algorithm>
#include <string>

#include "csgfit/error.h"
#include "csgfit/io/input3d.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/voxels_read.h"
#include "io/input_file.h"
#include "io/mesh/formats.h"
#include "io/voxels/formats.h"

namespace csgfit {

namespace {

using io_detail::fail;
using io_detail::lower_extension;
using io_detail::quoted;

[[noreturn]] void fail_unknown_format(const std::string& path, const char* what,
                                      const char* choices) {
  const std::string ext = lower_extension(path);
  fail(quoted(path) + ": unknown " + what + " format '" +
       (ext.empty() ? std::string("(no extension)") : "." + ext) + "' (use " + choices + ")");
}

}  // namespace

bool is_mesh_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == "stl" || ext == "obj" || ext == "off" || ext == "ply";
}

bool is_voxel_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == "npy" || ext == "binvox";
}

TriangleMesh read_mesh(const std::string& path, const MeshReadOptions& options,
                       MeshReadInfo* info) {
  if (!is_mesh_path(path)) fail_unknown_format(path, "mesh", ".stl, .obj, .off or .ply");
  const std::string ext = lower_extension(path);
  const bool text = ext == "obj" || ext == "off";
  const std::string data = io_detail::read_whole_file(
      path, options.max_file_bytes, "the input limit",
      text ? io_detail::FileContent::Text : io_detail::FileContent::Binary);
  if (ext == "stl") return io_detail::read_stl(path, data, options, info);
  if (ext == "obj") return io_detail::read_obj(path, data, options, info);
  if (ext == "off") return io_detail::read_off(path, data, options, info);
  return io_detail::read_ply(path, data, options, info);
}

VoxelGrid read_voxels(const std::string& path, const VoxelReadOptions& options) {
  if (!is_voxel_path(path)) fail_unknown_format(path, "voxel grid", ".npy or .binvox");
  const std::string ext = lower_extension(path);
  // Room for the largest grid allowed at 8 bytes a voxel, plus its header.
  const long long max_bytes =
      std::max<long long>(1LL << 20, static_cast<long long>(options.max_voxels) * 8 + (1 << 20));
  const std::string data = io_detail::read_whole_file(path, max_bytes, "the input limit");
  if (ext == "npy") return io_detail::read_npy(path, data, options);
  return io_detail::read_binvox(path, data, options);
}

Input3D read_input3d(const std::string& path) {
  if (is_voxel_path(path)) return Input3D::from_voxels(read_voxels(path));
  if (is_mesh_path(path)) return Input3D::from_mesh(read_mesh(path));
  throw InputError("unknown input format '" + path +
                   "' (expected .stl, .obj, .off, .ply, .npy or .binvox)");
}

}  // namespace csgfit
