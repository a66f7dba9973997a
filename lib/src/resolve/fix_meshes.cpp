// fix_meshes: the repair on a canonical renumbering of the meshes, mapped back to their order,
// retried with a larger clearance when it ends unresolved (FixOptions::retries).
#include "resolve/canonical_order.h"
#include "resolve/repair_loop.h"
#include "untangle/fix.h"

namespace untangle {
namespace {

// Adds the times of `from` to those of `to` (the attempts of one run share its clock).
void add_times(const FixResult& from, FixResult& to) {
  to.detect_ms += from.detect_ms;
  to.contours_ms += from.contours_ms;
  to.resolve_ms += from.resolve_ms;
  to.regions_ms += from.regions_ms;
  to.displace_ms += from.displace_ms;
  to.relax_ms += from.relax_ms;
}

}  // namespace

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

  // Retries start from the input again: keep it while there may be one.
  const std::vector<Mesh> start = options.retries > 0 ? work : std::vector<Mesh>{};
  bool cancelled = false;
  const FixProgress watch = [&](const IterationRecord& record) {
    if (progress && !progress(record)) cancelled = true;
    return !cancelled;
  };
  FixResult result = run_repair(work, options, work_pins, round, watch);
  result.clearance = options.clearance;
  FixOptions retry = options;
  const auto illegal = [](const FixResult& r) {
    return r.after.crossings + r.after.inside_vertices;
  };
  for (int k = 0; k < options.retries && !result.clean && !cancelled; ++k) {
    retry.clearance *= 2.0;
    std::vector<Mesh> attempt = start;
    FixResult r = run_repair(attempt, retry, work_pins, round, watch);
    RetryRecord record{retry.clearance, r.clean, r.after.crossings, r.after.inside_vertices,
                       r.iterations, false};
    if (cancelled) break;
    if (r.clean || illegal(r) < illegal(result)) {
      for (RetryRecord& earlier : result.retries) earlier.kept = false;
      record.kept = true;
      r.retries = std::move(result.retries);
      r.before = result.before;
      add_times(result, r);
      r.clearance = retry.clearance;
      result = std::move(r);
      work = std::move(attempt);
    } else {
      add_times(r, result);
    }
    result.retries.push_back(record);
  }

  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const auto& order = renumbered[m].vertex_order;
    for (std::size_t k = 0; k < order.size(); ++k)
      meshes[m].positions[order[k]] = work[m].positions[k];
  }
  return result;
}

}  // namespace untangle
