// The voxeliser on two InverseCSG CAD meshes: 056 (808 triangles) and 168 (33,028, the largest
// but one), both about as deep as they are wide.
#include <benchmark/benchmark.h>

#include <cmath>
#include <exception>
#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include "csgfit/io/mesh_read.h"
#include "csgfit/model/mesh.h"
#include "csgfit/model/voxelize.h"

namespace {

using namespace csgfit;

struct Model {
  TriangleMesh mesh;
  double volume = 0;
  std::string error;
};

const Model& load(const std::string& name) {
  static std::map<std::string, Model> models;
  auto it = models.find(name);
  if (it != models.end()) return it->second;
  Model m;
  const std::string path =
      std::string(CSGFIT_BENCHMARKS_DIR) + "/3d/inversecsg/" + name + "/csg_high_res.off";
  if (!std::filesystem::exists(path)) {
    m.error = "benchmark mesh not found: " + path;
  } else {
    try {
      m.mesh = read_mesh(path);
      m.volume = std::abs(signed_volume(m.mesh));
    } catch (const std::exception& e) {
      m.error = e.what();
    }
  }
  return models.emplace(name, std::move(m)).first->second;
}

/// The voxels' volume must match the mesh's (divergence theorem) to within the slab of half a
/// voxel that a surface can shift by; a wrong inside/outside decision costs far more.
std::string check(const Model& m, const VoxelGrid& g) {
  const double voxel = g.voxel_size();
  const double volume = static_cast<double>(g.count()) * voxel * voxel * voxel;
  const double area = analyze_mesh(m.mesh).surface_area;
  const double tolerance = 0.5 * voxel * area;
  if (std::abs(volume - m.volume) > tolerance)
    return "voxel volume " + std::to_string(volume) + " vs mesh volume " +
           std::to_string(m.volume) + " (tolerance " + std::to_string(tolerance) + ")";
  return {};
}

/// One voxelisation at a given resolution, timed as wall time: the voxeliser hands the
/// winding-number queries to a second thread.
void Voxelize(benchmark::State& state, const std::string& name) {
  const Model& m = load(name);
  if (!m.error.empty()) {
    state.SkipWithError(m.error.c_str());
    return;
  }
  VoxelizeOptions options;
  options.resolution = static_cast<int>(state.range(0));
  VoxelizeStats stats;
  const VoxelGrid first = voxelize(m.mesh, options, &stats);
  const std::string error = check(m, first);
  if (!error.empty()) {
    state.SkipWithError(error.c_str());
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(voxelize(m.mesh, options));
  state.counters["triangles"] = static_cast<double>(m.mesh.triangles.size());
  state.counters["voxels"] = static_cast<double>(first.count());
  state.counters["winding_evaluations"] = static_cast<double>(stats.winding_evaluations);
}

}  // namespace

BENCHMARK_CAPTURE(Voxelize, 056, std::string("056"))
    ->ArgName("resolution")->Arg(64)->Arg(128)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Voxelize, 168, std::string("168"))
    ->ArgName("resolution")->Arg(64)->Arg(128)->UseRealTime()->Unit(benchmark::kMillisecond);
