// fix_meshes: the repair on the canonical scene (canonical_order.h), mapped back to the order of the
// meshes and their vertices, retried with a larger clearance when it ends unresolved
// (FixOptions::retries).
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
  // The repair runs on the canonical scene (canonical_order.h): every mesh renumbered, the meshes
  // in an order of their own, so that neither the file's order nor the listing order matters.
  CanonicalScene scene = canonical_scene(meshes, pins);
  std::vector<Mesh>& work = scene.meshes;
  const PinMask& work_pins = scene.pins;

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

  counts_in_input_order(scene, result.before);
  counts_in_input_order(scene, result.after);
  result.quality = in_input_order(scene, result.quality);
  std::vector<std::vector<Vec3>> positions;
  for (Mesh& m : work) positions.push_back(std::move(m.positions));
  positions = vertices_in_input_order(scene, positions);
  for (std::size_t m = 0; m < meshes.size(); ++m) meshes[m].positions = std::move(positions[m]);
  return result;
}

}  // namespace untangle
