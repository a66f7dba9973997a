// Measured moves (measured_move.h) and the choice among measured candidates.
#include "resolve/measured_move.h"

#include <algorithm>

#include "resolve/move_kinds.h"

namespace untangle {
namespace {

// Relaxations measure at most 1/kRelaxShare of the scene's triangles (and 5,000) per step: where
// they help, a few small ones do; on two whole garments the step's budget goes to the moves.
constexpr std::size_t kRelaxShare = 20;

}  // namespace

void MeasuredMoves::start_step(const CrossingSet& set, const SceneHierarchy& hierarchy,
                               std::size_t triangles) {
  hierarchy_ = &hierarchy;
  trial_.sync(set);
  wide_tried = false;
  for (std::uint32_t v : taken_list_) taken_[v] = 0;
  taken_list_.clear();
  trial_budget = 2 * triangles + 20000;
  relax_budget = triangles / kRelaxShare + 5000;
}

long long MeasuredMoves::gain(const DetectSettings& detect, const CrossingSet& set,
                              const std::vector<std::uint32_t>& part, const std::vector<Vec3>& at) {
  const TrialCount count = trial_.count(detect, *hierarchy_, set, part, at, true);
  return static_cast<long long>(count.before) - static_cast<long long>(count.after);
}

void MeasuredMoves::make(const Choice& chosen, std::vector<std::uint8_t>& in_moving_set,
                         Moves& moves) {
  for (std::uint32_t v : chosen.part) in_moving_set[v] = taken_[v] = 1;
  taken_list_.insert(taken_list_.end(), chosen.part.begin(), chosen.part.end());
  moves.add_region(chosen.part, chosen.delta);
  trial_.commit(chosen.part, chosen.at);
}

Choice measured_choice(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                       const std::vector<Candidate>& candidates) {
  MeasuredMoves& measured = tools.measured;
  Choice chosen;
  for (const Candidate& candidate : candidates) {
    // Sets larger than kMeasuredVertices (a side of a sheet rather than a flap) go unmeasured.
    if (candidate.vertices.size() > kMeasuredVertices ||
        3 * candidate.vertices.size() > measured.trial_budget)
      continue;
    for (PartMoves& p : part_moves(ctx, tools.scratch, candidate.mesh, candidate.orientation,
                                   candidate.vertices, *candidate.tree)) {
      // A vertex moves once per step: parts with a vertex a measured move already took wait.
      if (std::any_of(p.part.begin(), p.part.end(),
                      [&](std::uint32_t v) { return measured.taken(v); }))
        continue;
      for (std::size_t o = 0; o < p.options.size(); ++o) {
        if (3 * p.part.size() > measured.trial_budget) break;
        measured.trial_budget -= 3 * p.part.size();
        std::vector<Vec3> at(p.part.size());
        for (std::size_t i = 0; i < p.part.size(); ++i) {
          at[i] = add(ctx.topo.points[p.part[i]], p.options[o][i]);
          if (ctx.round) at[i] = ctx.round(at[i]);
        }
        const long long gain = measured.gain(ctx.detect, set, p.part, at);
        if (gain > chosen.gain || (gain == chosen.gain && p.strain[o] < chosen.strain)) {
          chosen.gain = gain;
          chosen.strain = p.strain[o];
          chosen.part = p.part;
          chosen.delta = p.options[o];
          chosen.at = at;
        }
      }
    }
  }
  return chosen;
}

}  // namespace untangle
