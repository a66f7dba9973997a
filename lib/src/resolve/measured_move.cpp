// Measured moves (measured_move.h): exact counts of candidate moves, and the choice among them.
#include "resolve/measured_move.h"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

#include "detect/triangle_bvh.h"
#include "geometry/box3.h"
#include "resolve/move_kinds.h"

namespace untangle {
namespace {

// Relaxations measure at most 1/kRelaxShare of the scene's triangles (and 5,000) per step: where
// they help, a few small ones do; on two whole garments the step's budget goes to the moves.
constexpr std::size_t kRelaxShare = 20;

bool has(const std::array<std::uint32_t, 3>& tri, std::uint32_t v) {
  return tri[0] == v || tri[1] == v || tri[2] == v;
}

}  // namespace

MeasuredMoves::MeasuredMoves(const SceneTopology& topology)
    : topology_(topology),
      points_(topology.points),
      affected_(topology.tris.size(), 0),
      committed_(topology.tris.size(), 0),
      faces_(topology.tris.size(), 0),
      taken_(topology.points.size(), 0) {}

void MeasuredMoves::commit(const std::vector<std::uint32_t>& vertices,
                           const std::vector<Vec3>& at) {
  for (std::size_t i = 0; i < vertices.size(); ++i) points_[vertices[i]] = at[i];
  for (std::uint32_t t : topology_.triangles_at(vertices))
    if (!committed_[t]) {
      committed_[t] = 1;
      committed_list_.push_back(t);
    }
}

MoveCount MeasuredMoves::count(const DetectSettings& settings, const CrossingSet& set,
                               const std::vector<std::uint32_t>& vertices,
                               const std::vector<Vec3>& at, bool stop_above_before) {
  const SceneTopology& topo = topology_;
  const std::vector<std::uint32_t> touched = topology_.triangles_at(vertices);
  for (std::uint32_t t : touched) affected_[t] = 1;

  MoveCount result;
  result.triangles = touched.size();
  if (committed_list_.empty()) {
    // Nothing committed yet: the crossings now are the set's. Through a touched face, or along an
    // edge of a touched triangle through an untouched face (the set is sorted by edge: each
    // edge's crossings are one range).
    std::vector<std::uint32_t> edges;
    for (std::uint32_t t : touched) {
      result.before += faces_[t];
      for (std::uint32_t e : topo.tri_edges[t]) edges.push_back(e);
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (std::uint32_t e : edges) {
      auto it =
          std::lower_bound(set.items.begin(), set.items.end(), e,
                           [](const RawCrossing& x, std::uint32_t edge) { return x.edge < edge; });
      for (; it != set.items.end() && it->edge == e; ++it)
        if (!affected_[it->face]) ++result.before;
    }
  } else {
    result.before = crossings_of(settings, touched, std::numeric_limits<std::size_t>::max());
  }

  std::vector<Vec3> was(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    was[i] = points_[vertices[i]];
    points_[vertices[i]] = at[i];
  }
  result.after =
      crossings_of(settings, touched,
                   stop_above_before ? result.before : std::numeric_limits<std::size_t>::max());
  for (std::size_t i = 0; i < vertices.size(); ++i) points_[vertices[i]] = was[i];
  for (std::uint32_t t : touched) affected_[t] = 0;
  return result;
}

std::size_t MeasuredMoves::crossings_of(const DetectSettings& settings,
                                        const std::vector<std::uint32_t>& touched,
                                        std::size_t limit) {
  const SceneTopology& topo = topology_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> found;  // (edge, face)
  // A crossing is found once from each triangle at its edge: the finds are made unique now and
  // then, and counting stops once more than `limit` distinct ones are in.
  std::size_t next_check = limit == std::numeric_limits<std::size_t>::max() ? limit : 2 * limit + 8;
  bool gave_up = false;
  auto check = [&] {
    if (found.size() <= next_check) return;
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    gave_up = found.size() > limit;
    next_check = 2 * found.size() + 8;
  };
  const auto& tris = topo.detect_tris();  // shared positions are one point, as in detection
  auto test_edges = [&](std::uint32_t t, std::uint32_t f) {
    const auto& tri = tris[t];
    const auto& face = tris[f];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = tri[k], q = tri[(k + 1) % 3];
      if (has(face, p) || has(face, q)) continue;
      if (edge_crosses_triangle(points_, p, q, face[0], face[1], face[2]))
        found.push_back({topo.tri_edges[t][k], f});
    }
  };
  auto test_pair = [&](std::uint32_t t, std::uint32_t u) {
    int shared = 0;
    for (std::uint32_t v : tris[t]) shared += has(tris[u], v) ? 1 : 0;
    if (gave_up || shared >= 2 || triangles_surely_apart(points_, tris[t], tris[u]))
      return;
    test_edges(t, u);
    test_edges(u, t);
    check();
  };
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  auto skipped = [&](std::size_t m) {
    return m < settings.skip_among.size() && settings.skip_among[m];
  };
  auto paired = [&](std::uint32_t t, std::uint32_t u) {
    const std::size_t tm = topo.tri_mesh[t], um = topo.tri_mesh[u];
    if (tm == um && !settings.self_pairs) return false;
    return !(skipped(tm) && skipped(um));
  };

  // Triangles whose boxes in the hierarchy are stale (the touched ones, the committed ones), at
  // their current boxes: a sweep along x, pairs with a touched triangle in them.
  std::vector<std::uint32_t> current = touched;
  for (std::uint32_t t : committed_list_)
    if (!affected_[t]) current.push_back(t);
  std::vector<Box3> boxes(current.size());
  for (std::size_t i = 0; i < current.size(); ++i)
    boxes[i] = triangle_box(points_, topo.tris[current[i]]);
  std::vector<std::uint32_t> by_x(current.size());
  for (std::uint32_t i = 0; i < by_x.size(); ++i) by_x[i] = i;
  std::sort(by_x.begin(), by_x.end(), [&](std::uint32_t a, std::uint32_t b) {
    return boxes[a].lo[0] != boxes[b].lo[0] ? boxes[a].lo[0] < boxes[b].lo[0] : a < b;
  });
  // The pairs (i, j), i before j in x order, j's box starting before i's ends, with a touched
  // triangle in them, in that order. From a touched i every such j; from a committed one only
  // the touched j, found among the touched positions alone: a sweep over every pair of
  // committed triangles, to skip them, was 44% of a stalled continuation on the sheet over the
  // cow's rump (a step commits moves over much of the sheet; issue 21).
  std::vector<std::uint32_t> touched_at;  // positions in by_x of the touched triangles, ascending
  for (std::uint32_t i = 0; i < by_x.size(); ++i)
    if (affected_[current[by_x[i]]]) touched_at.push_back(i);
  std::size_t after_i = 0;  // the first of touched_at beyond i
  for (std::size_t i = 0; i < by_x.size() && !gave_up; ++i) {
    while (after_i < touched_at.size() && touched_at[after_i] <= i) ++after_i;
    const Box3& box = boxes[by_x[i]];
    const std::uint32_t t = current[by_x[i]];
    if (affected_[t]) {
      for (std::size_t j = i + 1; j < by_x.size() && boxes[by_x[j]].lo[0] <= box.hi[0]; ++j) {
        const std::uint32_t u = current[by_x[j]];
        if (paired(t, u) && box.overlaps(boxes[by_x[j]])) test_pair(t, u);
      }
      continue;
    }
    for (std::size_t x = after_i; x < touched_at.size(); ++x) {
      const std::size_t j = touched_at[x];
      if (boxes[by_x[j]].lo[0] > box.hi[0]) break;
      const std::uint32_t u = current[by_x[j]];
      if (paired(t, u) && box.overlaps(boxes[by_x[j]])) test_pair(t, u);
    }
  }
  // The rest through the hierarchy.
  std::vector<std::uint32_t> near;
  for (std::size_t i = 0; i < touched.size() && !gave_up; ++i) {
    const std::uint32_t t = touched[i];
    const std::uint32_t tm = topo.tri_mesh[t];
    near.clear();
    for (std::size_t m = 0; m < meshes; ++m) {
      if (m == tm && !settings.self_pairs) continue;
      if (skipped(m) && skipped(tm)) continue;
      if (const TriangleBvh* tree = hierarchy_->mesh(m)) tree->query(boxes[i], near);
    }
    if (!skipped(tm) && settings.skipped_bvh != nullptr)
      settings.skipped_bvh->query(boxes[i], near);
    for (std::uint32_t u : near)
      if (!affected_[u] && !committed_[u]) test_pair(t, u);
  }
  std::sort(found.begin(), found.end());
  return static_cast<std::size_t>(std::unique(found.begin(), found.end()) - found.begin());
}

void MeasuredMoves::start_step(const CrossingSet& set, const SceneHierarchy& hierarchy,
                               std::size_t triangles) {
  hierarchy_ = &hierarchy;
  points_ = topology_.points;
  for (std::uint32_t t : committed_list_) committed_[t] = 0;
  committed_list_.clear();
  std::fill(faces_.begin(), faces_.end(), 0);
  for (const RawCrossing& x : set.items) ++faces_[x.face];
  wide_tried = false;
  for (std::uint32_t v : taken_list_) taken_[v] = 0;
  taken_list_.clear();
  trial_budget = 2 * triangles + 20000;
  relax_budget = triangles / kRelaxShare + 5000;
}

long long MeasuredMoves::gain(const DetectSettings& detect, const CrossingSet& set,
                              const std::vector<std::uint32_t>& part, const std::vector<Vec3>& at) {
  const MoveCount c = count(detect, set, part, at, true);
  return static_cast<long long>(c.before) - static_cast<long long>(c.after);
}

void MeasuredMoves::make(const Choice& chosen, std::vector<std::uint8_t>& in_moving_set,
                         Moves& moves) {
  for (std::uint32_t v : chosen.part) in_moving_set[v] = taken_[v] = 1;
  taken_list_.insert(taken_list_.end(), chosen.part.begin(), chosen.part.end());
  moves.add_region(chosen.part, chosen.delta);
  commit(chosen.part, chosen.at);
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
