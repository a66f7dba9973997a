// PairList (pair_list.h): the relaxation's candidate pairs, listed once and kept while the part
// moves little, and the update of the crossings over them.
#include "detect/pair_list.h"

#include <algorithm>
#include <cmath>

#include "detect/run_parallel.h"
#include "detect/update_steps.h"

namespace untangle {

PairList::PairList(std::vector<std::uint32_t> triangles, double reach)
    : triangles_(std::move(triangles)), reach_(reach) {}

bool PairList::beyond(const Vec3& p, const Vec3& reference) const {
  bool out = false;
  for (int k = 0; k < 3; ++k) out = out || !(std::abs(p[k] - reference[k]) <= reach_);
  return out;
}

bool PairList::holds(const SceneTopology& topo) const {
  if (!made_) return false;
  for (std::size_t i = 0; i < corners_.size(); ++i)
    if (beyond(topo.points[corners_[i]], at_[i])) return false;
  return true;
}

namespace {

// A box grown by `grow` on every side, and by one more unit in the last place outward, so that
// the rounding of the sums never shrinks it.
Box3 grown_box(Box3 b, double grow) {
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = std::nextafter(b.lo[k] - grow, -INFINITY);
    b.hi[k] = std::nextafter(b.hi[k] + grow, INFINITY);
  }
  return b;
}

}  // namespace

// Whether the pair (t listed, u) is one update_crossings would test, by the meshes' filters of
// `settings` and the shared corners; `from_shared`: u came from the skipped meshes' shared tree.
bool PairList::wanted(const SceneTopology& topo, const DetectSettings& settings, std::uint32_t t,
                      std::uint32_t u, bool from_shared) const {
  auto skipped = [&](std::size_t m) {
    return m < settings.skip_among.size() && settings.skip_among[m];
  };
  const std::uint32_t tm = topo.tri_mesh[t], um = topo.tri_mesh[u];
  if (from_shared) {
    if (skipped(tm)) return false;
  } else {
    if (um == tm && !settings.self_pairs) return false;
    if (skipped(um) && skipped(tm)) return false;
  }
  return u != t && shared_vertices(topo.detect_tris()[t], topo.detect_tris()[u]) < 2;
}

void PairList::prepare(const SceneTopology& topo, const DetectSettings& settings,
                       const SceneHierarchy& hierarchy) {
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  std::vector<std::pair<const TriangleBvh*, bool>> trees;  // (tree, the skipped meshes' shared one)
  for (std::size_t m = 0; m < meshes; ++m)
    if (hierarchy.mesh(m) != nullptr) trees.push_back({hierarchy.mesh(m), false});
  if (settings.skipped_bvh != nullptr) trees.push_back({settings.skipped_bvh, true});
  if (!made_) {
    make(topo, settings, trees);
    index();
    return;
  }
  // The corners that went beyond the reach take their position now as their new reference; the
  // listed triangles at them are listed again, grown by 4.5 reaches: every corner of theirs, and of
  // any listed triangle, lies within the reach of its reference, so within twice the reach of
  // where it is now, from now until the next refresh.
  std::vector<std::uint8_t>& stale = scratch_;
  stale.assign(topo.points.size(), 0);
  bool any = false;
  for (std::size_t i = 0; i < corners_.size(); ++i) {
    const Vec3& p = topo.points[corners_[i]];
    if (!beyond(p, at_[i])) continue;
    at_[i] = p;
    stale[corners_[i]] = 1;
    any = true;
  }
  if (!any) return;
  std::vector<std::uint32_t> again;
  for (const std::uint32_t t : triangles_) {
    const auto& tri = topo.tris[t];
    if (stale[tri[0]] || stale[tri[1]] || stale[tri[2]]) again.push_back(t);
  }
  std::vector<std::uint8_t> listing(topo.tris.size(), 0);
  for (const std::uint32_t t : again) listing[t] = 1;
  pairs_.erase(std::remove_if(pairs_.begin(), pairs_.end(),
                              [&](const std::array<std::uint32_t, 2>& p) {
                                return listing[p[0]] || listing[p[1]];
                              }),
               pairs_.end());
  std::vector<std::uint32_t> near;
  for (const std::uint32_t t : again) {
    const Box3 box = grown_box(triangle_box(topo, t), 4.5 * reach_);
    for (const auto& [tree, from_shared] : trees) {
      near.clear();
      tree->query(box, near);
      std::sort(near.begin(), near.end());
      for (const std::uint32_t u : near) {
        // Two triangles listed again: once, from the lower.
        if ((listing[u] && u < t) || !wanted(topo, settings, t, u, from_shared)) continue;
        pairs_.push_back({t, u});
      }
    }
  }
  index();
}

void PairList::make(const SceneTopology& topo, const DetectSettings& settings,
                    const std::vector<std::pair<const TriangleBvh*, bool>>& trees) {
  made_ = true;
  pairs_.clear();
  corners_.clear();
  for (const std::uint32_t t : triangles_)
    for (const std::uint32_t v : topo.tris[t]) corners_.push_back(v);
  std::sort(corners_.begin(), corners_.end());
  corners_.erase(std::unique(corners_.begin(), corners_.end()), corners_.end());
  at_.resize(corners_.size());
  for (std::size_t i = 0; i < corners_.size(); ++i) at_[i] = topo.points[corners_[i]];
  slot_.assign(topo.tris.size(), kNone);
  for (std::size_t i = 0; i < triangles_.size(); ++i)
    slot_[triangles_[i]] = static_cast<std::uint32_t>(i);
  if (triangles_.empty()) return;
  // Each listed box grown by 2.5 reaches: every corner stays within the reach of where it is now
  // (as holds() computes it: within the reach and a rounding) until it is listed again, so two
  // boxes that overlap later come within twice the reach of each other now.
  std::vector<Box3> boxes(triangles_.size());
  for (std::size_t i = 0; i < triangles_.size(); ++i)
    boxes[i] = grown_box(triangle_box(topo, triangles_[i]), 2.5 * reach_);
  const TriangleBvh grown(std::move(boxes));
  struct Job {
    std::uint32_t tree;
    TriangleBvh::Part part;
  };
  std::vector<Job> jobs;
  for (std::size_t k = 0; k < trees.size(); ++k)
    for (const TriangleBvh::Part& part : grown.split(*trees[k].first, false, kParts))
      jobs.push_back({static_cast<std::uint32_t>(k), part});
  std::vector<std::vector<std::array<std::uint32_t, 2>>> found(jobs.size());
  run_parallel(settings.threads, jobs.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end; ++j) {
      const auto& [tree, from_shared] = trees[jobs[j].tree];
      grown.each_pair_in(*tree, jobs[j].part, false, [&](std::uint32_t x, std::uint32_t u) {
        const std::uint32_t t = triangles_[x];
        // Two listed triangles: once, from the lower (the higher meets the lower's tree too).
        if ((slot_[u] != kNone && u < t) || !wanted(topo, settings, t, u, from_shared)) return;
        found[j].push_back({t, u});
      });
    }
  });
  for (const auto& block : found) pairs_.insert(pairs_.end(), block.begin(), block.end());
}

void PairList::index() {
  // Each pair under both of its listed triangles, in the order of pairs_ (a counting sort).
  adjacent_begin_.assign(triangles_.size() + 1, 0);
  for (const auto& [t, u] : pairs_) {
    ++adjacent_begin_[slot_[t] + 1];
    if (slot_[u] != kNone) ++adjacent_begin_[slot_[u] + 1];
  }
  for (std::size_t i = 0; i < triangles_.size(); ++i) adjacent_begin_[i + 1] += adjacent_begin_[i];
  adjacent_.resize(adjacent_begin_.back());
  std::vector<std::uint32_t> next(adjacent_begin_.begin(), adjacent_begin_.end() - 1);
  for (const auto& [t, u] : pairs_) {
    adjacent_[next[slot_[t]]++] = u;
    if (slot_[u] != kNone) adjacent_[next[slot_[u]]++] = t;
  }
}

CrossingSet update_crossings(const SceneTopology& topo, const DetectSettings& settings,
                             const PairList& list, const CrossingSet& previous,
                             const std::vector<std::uint8_t>& moved) {
  // The listed triangles with a moved corner (only they can have one), their boxes now and planes.
  const std::vector<std::uint32_t>& listed = list.triangles();
  const auto& tris = topo.detect_tris();
  std::vector<std::uint8_t> affected(listed.size(), 0);
  std::vector<std::uint32_t> retest;  // listed indices, ascending
  for (std::size_t i = 0; i < listed.size(); ++i) {
    for (const std::uint32_t v : topo.tris[listed[i]]) affected[i] |= moved[v];
    if (affected[i]) retest.push_back(static_cast<std::uint32_t>(i));
  }
  std::vector<Box3> box(listed.size());
  std::vector<TriPlane> planes(listed.size());
  run_parallel(settings.threads, retest.size(), 1024, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t t = listed[retest[k]];
      box[retest[k]] = triangle_box(topo, t);
      planes[retest[k]] = triangle_plane(topo.points, tris[t]);
    }
  });
  auto skipped = [&](std::size_t m) {
    return m < settings.skip_among.size() && settings.skip_among[m];
  };
  // The pairs of each retested triangle whose boxes overlap now: the pairs the descents of
  // update_crossings would test, tested as it tests them (the retested triangle first, the lower
  // of two retested ones).
  constexpr std::size_t kBlock = 256;
  const std::size_t blocks = (retest.size() + kBlock - 1) / kBlock;
  std::vector<std::vector<RawCrossing>> found(blocks);
  run_parallel(settings.threads, blocks, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      const std::size_t last = std::min(retest.size(), (b + 1) * kBlock);
      for (std::size_t k = b * kBlock; k < last; ++k) {
        const std::uint32_t i = retest[k], t = listed[i];
        for (const std::uint32_t u : list.adjacent(i)) {
          const std::uint32_t j = list.slot(u);
          const bool retested = j != kNone && affected[j];
          if (retested && u < t) continue;  // tested from u, the lower
          if (!box[i].overlaps(retested ? box[j] : triangle_box(topo, u))) continue;
          TriPlane plane_u;
          if (retested)
            plane_u = planes[j];
          else if (settings.skipped_planes && settings.skipped_bvh && skipped(topo.tri_mesh[u]))
            plane_u = (*settings.skipped_planes)[u];
          else
            plane_u = triangle_plane(topo.points, tris[u]);
          test_pair(topo, t, u, planes[i], plane_u, found[b]);
        }
      }
    }
  });
  return merge_update(topo, previous, moved, found);
}

}  // namespace untangle
