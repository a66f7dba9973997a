// fix_meshes: the repair on a canonical renumbering of the meshes, mapped back to their order.
#include "resolve/canonical_order.h"
#include "resolve/repair_loop.h"
#include "untangle/fix.h"

namespace untangle {

const char* to_string(FixMethod method) {
  return method == FixMethod::kRegion ? "region" : "paper";
}

FixResult fix_meshes(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
                     const std::function<Vec3(const Vec3&)>& round, const FixProgress& progress) {
  std::vector<CanonicalMesh> renumbered;
  renumbered.reserve(meshes.size());
  for (const Mesh& mesh : meshes) renumbered.push_back(canonical(mesh));
  std::vector<Mesh> work;
  work.reserve(meshes.size());
  PinMask work_pins(pins.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    work.push_back(std::move(renumbered[m].mesh));
    if (m < pins.size() && !pins[m].empty()) {
      const auto& order = renumbered[m].vertex_order;
      work_pins[m].assign(order.size(), 0);
      for (std::size_t k = 0; k < order.size(); ++k)
        if (order[k] < pins[m].size()) work_pins[m][k] = pins[m][order[k]];
    }
  }

  FixResult result = run_repair(work, options, work_pins, round, progress);

  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const auto& order = renumbered[m].vertex_order;
    for (std::size_t k = 0; k < order.size(); ++k)
      meshes[m].positions[order[k]] = work[m].positions[k];
  }
  return result;
}

}  // namespace untangle
