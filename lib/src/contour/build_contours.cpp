// Contours: walk crossings through intersecting triangle pairs; classify tracks; flood fills.
#include "contour/build_contours.h"

#include <algorithm>
#include <numeric>

#include <tbb/enumerable_thread_specific.h>

#include "detect/run_parallel.h"
#include "geometry/vec3.h"

namespace untangle {
namespace {

enum class LinkKind : std::uint8_t { kCrossing, kBoundary, kLoop, kBroken };

// One way out of a crossing: through one triangle t incident to its edge, the segment t ∩ f leads
// to another crossing, a loop vertex, or (boundary edge) nowhere.
struct Link {
  LinkKind kind = LinkKind::kBroken;
  std::uint32_t target = kNone;  // crossing index, or loop vertex id
  std::array<std::uint32_t, 2> pair{kNone, kNone};  // the triangle pair, ordered
  bool swap = false;  // the next crossing's edge lies on the other track
};

bool has_vertex(const std::array<std::uint32_t, 3>& tri, std::uint32_t v) {
  return tri[0] == v || tri[1] == v || tri[2] == v;
}

// Crossings grouped by triangle pair: crossing (e, f) lies in the pair {t, f} for each triangle t
// incident to e, and is entered once per such t (an entry) under that pair's key in an
// open-addressing table, which chains the entries of one pair.
class PairTable {
 public:
  explicit PairTable(std::size_t entries) {
    std::size_t size = 16;
    while (size < 2 * entries) {
      size *= 2;
      --shift_;
    }
    mask_ = size - 1;
    keys_.assign(size, kEmpty);
    first_.resize(size);
    crossing_.reserve(entries);
    next_.reserve(entries);
  }
  // Enters crossing c under the pair {t, f}; returns the entry's slot.
  std::uint32_t add(std::uint32_t c, std::uint32_t t, std::uint32_t f) {
    const std::uint64_t key = std::uint64_t{std::min(t, f)} << 32 | std::max(t, f);
    std::size_t h = static_cast<std::size_t>((key ^ key >> 29) * 0x9e3779b97f4a7c15ull >> shift_);
    while (keys_[h] != kEmpty && keys_[h] != key) h = (h + 1) & mask_;
    next_.push_back(keys_[h] == key ? first_[h] : kNone);
    keys_[h] = key;
    first_[h] = static_cast<std::uint32_t>(crossing_.size());
    crossing_.push_back(c);
    return static_cast<std::uint32_t>(h);
  }
  // The entries of the pair in `slot`: first(slot), then next(entry) until kNone.
  std::uint32_t first(std::uint32_t slot) const { return first_[slot]; }
  std::uint32_t next(std::uint32_t entry) const { return next_[entry]; }
  std::uint32_t crossing(std::uint32_t entry) const { return crossing_[entry]; }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::size_t mask_ = 0;
  int shift_ = 60;  // Fibonacci hashing: the top bits of the product
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> first_, crossing_, next_;
};

// The links of every crossing: one per triangle t incident to its edge (in edge_faces order),
// then an end for a boundary edge; crossing ci's are links[link_begin[ci], link_begin[ci + 1]).
// Crossing (e, f) meets crossing (e', f') through t when both lie in the triangle pair {t, f}: e'
// an edge of t and f' = f (same roles), or e' an edge of f and f' = t (the roles swap). So its
// partner through t is the one other crossing entered under {t, f} whose edge shares no vertex
// with its own face (every crossing of a real detection; an arbitrary set may hold others, which
// never link). No other: t ∩ f runs to a vertex the two share (a loop vertex) or nowhere
// (broken); two or more: broken. Two passes over the crossings in edge order and one table probe
// per entry, not a lookup of every edge of t and f in a table by edge (six per link): that takes
// few instructions but many scattered reads of t's and f's corners and edges, and is slower.
std::vector<Link> link_crossings(const SceneTopology& topo, const CrossingSet& set,
                                 std::vector<std::uint32_t>& link_begin) {
  const std::size_t n = set.items.size();
  std::size_t entries = 0;
  for (const RawCrossing& c : set.items) entries += topo.edge_face_count(c.edge);
  PairTable table(entries);
  std::vector<std::uint32_t> slot(entries);  // per entry, in the order entered
  std::vector<std::uint8_t> linkable(n);
  // Corners as detection sees them: a position shared across meshes is one point (DESIGN §2), so a
  // segment t ∩ f can run to it as to a vertex t and f share.
  const auto& tris = topo.detect_tris();
  for (std::uint32_t ci = 0, entry = 0; ci < n; ++ci) {
    const RawCrossing& c = set.items[ci];
    const auto& face = tris[c.face];
    linkable[ci] = !has_vertex(face, topo.detect_point(topo.edges[c.edge][0])) &&
                   !has_vertex(face, topo.detect_point(topo.edges[c.edge][1]));
    for (std::uint32_t i = topo.edge_face_begin[c.edge]; i < topo.edge_face_begin[c.edge + 1]; ++i)
      slot[entry++] = table.add(ci, topo.edge_faces[i], c.face);
  }
  std::vector<Link> links;
  links.reserve(entries + n);
  link_begin.assign(n + 1, 0);
  for (std::uint32_t ci = 0, entry = 0; ci < n; ++ci) {
    link_begin[ci] = static_cast<std::uint32_t>(links.size());
    const RawCrossing& c = set.items[ci];
    const std::uint32_t f = c.face;
    for (std::uint32_t i = topo.edge_face_begin[c.edge]; i < topo.edge_face_begin[c.edge + 1];
         ++i, ++entry) {
      const std::uint32_t t = topo.edge_faces[i];
      Link link;
      link.pair = {std::min(t, f), std::max(t, f)};
      std::size_t found = 0;
      for (std::uint32_t o = table.first(slot[entry]); o != kNone; o = table.next(o)) {
        const std::uint32_t other = table.crossing(o);
        if (o == entry || !linkable[other]) continue;
        link.kind = LinkKind::kCrossing;
        link.target = other;
        link.swap = set.items[other].face != f;
        ++found;
      }
      if (found != 1) {
        link.kind = LinkKind::kBroken;
        link.target = kNone;
      }
      if (found == 0) {
        const auto &tt = tris[t], &ff = tris[f];
        for (std::uint32_t v : tt) {
          if (has_vertex(ff, v)) {  // t ∩ f runs from the crossing to the shared vertex
            link.kind = LinkKind::kLoop;
            link.target = v;
            break;
          }
        }
      }
      links.push_back(link);
    }
    if (topo.is_boundary(c.edge)) {
      Link end;
      end.kind = LinkKind::kBoundary;
      end.target = c.edge;
      links.push_back(end);
    }
  }
  link_begin[n] = static_cast<std::uint32_t>(links.size());
  return links;
}

}  // namespace

std::vector<std::uint32_t> odd_edges(std::vector<std::uint32_t>& crossed) {
  std::sort(crossed.begin(), crossed.end());
  std::vector<std::uint32_t> odd;
  for (std::size_t i = 0; i < crossed.size();) {
    std::size_t j = i;
    while (j < crossed.size() && crossed[j] == crossed[i]) ++j;
    if ((j - i) % 2 == 1) odd.push_back(crossed[i]);
    i = j;
  }
  return odd;
}

std::size_t flood_regions(const SceneTopology& topo, std::uint32_t mesh,
                          const std::vector<std::uint8_t>& edge_is_cut,
                          std::vector<std::uint32_t>& region) {
  const std::uint32_t begin = topo.mesh_vertex_begin[mesh];
  const std::uint32_t end = topo.mesh_vertex_begin[mesh + 1];
  region.assign(end - begin, kNone);
  std::size_t count = 0;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = begin; seed < end; ++seed) {
    if (region[seed - begin] != kNone) continue;
    const std::uint32_t id = static_cast<std::uint32_t>(count++);
    region[seed - begin] = id;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::uint32_t v = stack.back();
      stack.pop_back();
      for (std::uint32_t i = topo.vertex_edge_begin[v]; i < topo.vertex_edge_begin[v + 1]; ++i) {
        if (edge_is_cut[topo.vertex_edges[i]]) continue;
        const std::uint32_t w = topo.vertex_neighbors[i];
        if (region[w - begin] == kNone) {
          region[w - begin] = id;
          stack.push_back(w);
        }
      }
    }
  }
  return count;
}

namespace {

// A list of ids of which callers track the used prefix; grown geometrically, keeping its entries,
// so that its size follows the sides actually grown rather than the mesh (memory that is
// allocated and cleared on every call costs page faults).
struct IdBuffer {
  std::vector<std::uint32_t> ids;
  std::uint32_t* room(std::size_t n) {
    if (ids.size() < n) ids.resize(std::max(n, 2 * ids.size()));
    return ids.data();
  }
};

// Per-thread flags of a separation test, all zero between tests (sized on first use), and lists
// kept for their capacity.
struct SeparationScratch {
  std::vector<std::uint64_t> blocked;  // a bit per entry of vertex_edges: the edge is cut
  std::vector<std::uint8_t> side_of;  // per welded vertex: 0, or 1 + the side that reached it
  std::vector<std::uint8_t> seen;     // per triangle
  IdBuffer triangles;
  std::vector<std::uint32_t> edges;  // the track's crossed edges
  IdBuffer queue[2];                 // the vertices each side reached, in order
  std::size_t reached[2] = {0, 0};   // how many of queue[s] are set
};

// Grows the two sides of a cut edge in lock step, one vertex of each in turn, never crossing a
// cut edge. Returns the side (0 or 1) that runs out first, or -1 when the fronts meet. Each side's
// vertices are the first scratch.reached[side] of scratch.queue[side], marked 1 + side in
// scratch.side_of. The neighbours of a vertex are taken without data-dependent branches (whether
// one is new or cut is not predictable): each is written at the end of the queue, which grows by
// one only when the neighbour is new.
int grow_sides(const SceneTopology& topo, std::uint32_t seed0, std::uint32_t seed1,
               SeparationScratch& scratch) {
  const std::uint32_t* edge_begin = topo.vertex_edge_begin.data();
  const std::uint32_t* neighbors = topo.vertex_neighbors.data();
  const std::uint64_t* blocked = scratch.blocked.data();
  std::uint8_t* side_of = scratch.side_of.data();
  std::uint32_t* queue[2];
  std::size_t head[2] = {0, 0}, size[2] = {1, 1}, room[2];
  for (int s = 0; s < 2; ++s) {
    queue[s] = scratch.queue[s].room(64);
    room[s] = scratch.queue[s].ids.size();
  }
  queue[0][0] = seed0;
  queue[1][0] = seed1;
  side_of[seed0] = 1;
  side_of[seed1] = 2;
  int finished = -1;
  bool met = false;
  while (!met) {
    for (int s = 0; s < 2 && !met; ++s) {
      if (head[s] == size[s]) {
        finished = s;
        break;
      }
      const std::uint32_t v = queue[s][head[s]++];
      const unsigned mark = static_cast<unsigned>(s + 1), other_mark = 3 - mark;
      std::size_t n = size[s];
      if (n + (edge_begin[v + 1] - edge_begin[v]) + 1 > room[s]) {  // each neighbour is written
        queue[s] = scratch.queue[s].room(n + (edge_begin[v + 1] - edge_begin[v]) + 1);
        room[s] = scratch.queue[s].ids.size();
      }
      std::uint32_t* q = queue[s];
      unsigned other = 0;
      for (std::uint32_t i = edge_begin[v]; i < edge_begin[v + 1]; ++i) {
        const std::uint32_t w = neighbors[i];
        const unsigned open = static_cast<unsigned>(~blocked[i >> 6] >> (i & 63)) & 1u;
        const unsigned was = side_of[w];
        const unsigned fresh = open & static_cast<unsigned>(was == 0);
        other |= open & static_cast<unsigned>(was == other_mark);
        q[n] = w;
        n += fresh;
        side_of[w] = static_cast<std::uint8_t>(was | (mark & (0u - fresh)));
      }
      size[s] = n;
      met = other != 0;
    }
    if (finished >= 0) break;
  }
  for (int s = 0; s < 2; ++s) scratch.reached[s] = size[s];
  return met ? -1 : finished;
}

// The area of a side: a third of each triangle per corner in the side (`mark` in side_of). The
// triangles around the side's vertices are listed once each, then weighted; written without
// data-dependent branches (which side a corner lies on is not predictable), so this costs little
// more than reading the fans.
double side_area(const SceneTopology& topo, const std::uint32_t* side, std::size_t side_count,
                 std::uint8_t mark, SeparationScratch& scratch) {
  std::vector<std::uint8_t>& seen = scratch.seen;
  if (seen.empty()) seen.assign(topo.tris.size(), 0);
  std::uint32_t* list = scratch.triangles.room(64);
  std::size_t room = scratch.triangles.ids.size();
  std::size_t count = 0;
  for (std::size_t s = 0; s < side_count; ++s) {
    const std::uint32_t v = side[s];
    for (std::uint32_t i = topo.vertex_edge_begin[v]; i < topo.vertex_edge_begin[v + 1]; ++i) {
      const std::uint32_t e = topo.vertex_edges[i];
      const std::uint32_t first = topo.edge_face_begin[e], last = topo.edge_face_begin[e + 1];
      if (count + (last - first) + 1 > room) {  // each face is written, the new ones kept
        list = scratch.triangles.room(count + (last - first) + 1);
        room = scratch.triangles.ids.size();
      }
      for (std::uint32_t k = first; k < last; ++k) {
        const std::uint32_t t = topo.edge_faces[k];
        list[count] = t;
        count += seen[t] ^ 1u;
        seen[t] = 1;
      }
    }
  }
  double area = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const auto& tri = topo.tris[list[i]];
    seen[list[i]] = 0;
    const int corners = (scratch.side_of[tri[0]] == mark) + (scratch.side_of[tri[1]] == mark) +
                        (scratch.side_of[tri[2]] == mark);
    area += triangle_area(topo.points[tri[0]], topo.points[tri[1]], topo.points[tri[2]]) * corners / 3.0;
  }
  return area;
}

// Type, cut edges and (when `separation`) separation of track k of a traced contour.
void classify_track(const SceneTopology& topo, const CrossingSet& set, TracedContour& traced, int k,
                    bool separation, SeparationScratch& scratch) {
  Contour& contour = traced.contour;
  Track& track = contour.tracks[k];
  if (contour.closed) track.type = TrackType::kCL;
  else if (track.boundary_ends >= 2) track.type = TrackType::kBB;
  else if (track.boundary_ends == 1) track.type = TrackType::kBI;
  else track.type = TrackType::kII;

  std::vector<std::uint32_t>& edges = scratch.edges;
  edges.clear();
  for (std::size_t i = 0; i < contour.crossings.size(); ++i)
    if (traced.edge_track[i] == k) edges.push_back(set.items[contour.crossings[i]].edge);
  const std::vector<std::uint32_t> odd = odd_edges(edges);
  track.cut_edges = odd.size();
  if (!separation || (track.type != TrackType::kCL && track.type != TrackType::kBB)) return;
  if (odd.empty()) {  // cuts off no vertex: a disk inside faces, or a sliver at the boundary
    track.separates = true;
    return;
  }
  if (scratch.blocked.empty()) {
    scratch.blocked.assign((topo.vertex_edges.size() + 63) / 64, 0);
    scratch.side_of.assign(topo.points.size(), 0);
  }
  // Cut flags by entry of the vertices' edge lists, read in step with the neighbours.
  auto block = [&](bool value) {
    for (std::uint32_t e : odd) {
      for (std::uint32_t v : topo.edges[e]) {
        const auto first = topo.vertex_edges.begin() + topo.vertex_edge_begin[v];
        const auto last = topo.vertex_edges.begin() + topo.vertex_edge_begin[v + 1];
        const auto i = static_cast<std::size_t>(std::lower_bound(first, last, e) - topo.vertex_edges.begin());
        const std::uint64_t bit = std::uint64_t{1} << (i & 63);
        scratch.blocked[i >> 6] = value ? scratch.blocked[i >> 6] | bit : scratch.blocked[i >> 6] & ~bit;
      }
    }
  };
  block(true);
  // Grow the two sides of the first cut edge in lock step: if one side runs out first it is a
  // separate region (the smaller side by vertex count); if the two fronts meet, the track
  // separates nothing. Cost: the smaller side, not the mesh.
  const int finished = grow_sides(topo, topo.edges[odd.front()][0], topo.edges[odd.front()][1], scratch);
  if (finished >= 0) {
    track.separates = true;
    const auto mark = static_cast<std::uint8_t>(finished + 1);
    track.smaller_area = side_area(topo, scratch.queue[finished].ids.data(), scratch.reached[finished], mark, scratch);
  }
  for (int s = 0; s < 2; ++s)
    for (std::size_t i = 0; i < scratch.reached[s]; ++i) scratch.side_of[scratch.queue[s].ids[i]] = 0;
  block(false);
}

}  // namespace

std::vector<TracedContour> build_contours(const SceneTopology& topo, const CrossingSet& set,
                                          int threads, bool separation) {
  const std::size_t n = set.items.size();
  // Links of every crossing, one per triangle incident to its edge (boundary edges add an end).
  std::vector<std::uint32_t> link_begin;
  const std::vector<Link> links = link_crossings(topo, set, link_begin);

  // Components through crossing links, in order of their lowest crossing.
  std::vector<std::uint32_t> component(n, kNone);
  std::vector<std::vector<std::uint32_t>> members;
  for (std::uint32_t s = 0; s < n; ++s) {
    if (component[s] != kNone) continue;
    const std::uint32_t id = static_cast<std::uint32_t>(members.size());
    members.emplace_back();
    std::vector<std::uint32_t> stack{s};
    component[s] = id;
    while (!stack.empty()) {
      const std::uint32_t c = stack.back();
      stack.pop_back();
      members[id].push_back(c);
      for (std::uint32_t i = link_begin[c]; i < link_begin[c + 1]; ++i) {
        if (links[i].kind != LinkKind::kCrossing || component[links[i].target] != kNone) continue;
        component[links[i].target] = id;
        stack.push_back(links[i].target);
      }
    }
    std::sort(members[id].begin(), members[id].end());
  }

  std::vector<TracedContour> out;
  out.reserve(members.size());
  std::vector<std::uint8_t> label(n, 0);
  std::vector<std::uint8_t> placed(n, 0);  // already in the current contour's order
  for (const std::vector<std::uint32_t>& nodes : members) {
    TracedContour traced;
    Contour& contour = traced.contour;
    const std::uint32_t id = component[nodes.front()];
    // Links are symmetric for a real detection (the 0-or-2 property). In an arbitrary set a
    // crossing may link to one of an earlier contour that does not link back; such a link is not
    // followed, so that every crossing lies on exactly one contour, and the contour is broken.
    auto inside = [&](const Link& link) {
      return link.kind == LinkKind::kCrossing && component[link.target] == id;
    };
    bool branched = false;
    std::uint32_t start = nodes.front();
    bool start_found = false;
    for (std::uint32_t c : nodes) {
      bool end = false;
      for (std::uint32_t i = link_begin[c]; i < link_begin[c + 1]; ++i) {
        if (!inside(links[i])) end = true;
        const bool leaves = links[i].kind == LinkKind::kCrossing && !inside(links[i]);
        if (links[i].kind == LinkKind::kBroken || leaves) traced.broken = true;
      }
      if (topo.edge_face_count(set.items[c].edge) >= 3) {
        branched = true;
        ++contour.branch_points;
      }
      if (end && !start_found) {
        start = c;
        start_found = true;
      }
    }

    std::vector<std::uint32_t> order;
    std::vector<std::uint8_t> track;
    bool walked = false;
    if (!branched) {
      // Walk the chain (or cycle) from an end, never leaving through the pair we came in by.
      order.push_back(start);
      track.push_back(0);
      placed[start] = 1;
      std::array<std::uint32_t, 2> arrival{kNone, kNone};
      std::uint32_t cur = start;
      walked = true;
      for (;;) {
        const Link* next = nullptr;
        for (std::uint32_t i = link_begin[cur]; i < link_begin[cur + 1]; ++i) {
          if (inside(links[i]) && links[i].pair != arrival) {
            next = &links[i];
            break;
          }
        }
        if (next == nullptr) break;
        const std::uint8_t lab = static_cast<std::uint8_t>(track.back() ^ (next->swap ? 1 : 0));
        if (next->target == start) {
          contour.closed = true;
          break;
        }
        if (placed[next->target]) {  // runs into itself: not a simple chain (arbitrary sets only)
          walked = false;
          break;
        }
        order.push_back(next->target);
        track.push_back(lab);
        placed[next->target] = 1;
        arrival = next->pair;
        cur = next->target;
      }
      if (order.size() != nodes.size()) walked = false;
      if (!walked) traced.broken = true;
    }
    if (!walked) {
      // Non-manifold edges branch the curve, and a walk that failed left crossings out: keep every
      // crossing of the component once, labels by breadth-first search from the start (and from
      // any crossing not reached, which only an arbitrary set can leave).
      for (std::uint32_t c : order) placed[c] = 0;
      order.clear();
      track.clear();
      contour.closed = false;
      auto grow = [&](std::uint32_t root) {
        if (placed[root]) return;
        placed[root] = 1;
        order.push_back(root);
        track.push_back(0);
        for (std::size_t k = order.size() - 1; k < order.size(); ++k) {
          const std::uint32_t c = order[k];
          for (std::uint32_t i = link_begin[c]; i < link_begin[c + 1]; ++i) {
            if (!inside(links[i]) || placed[links[i].target]) continue;
            placed[links[i].target] = 1;
            order.push_back(links[i].target);
            track.push_back(static_cast<std::uint8_t>(track[k] ^ (links[i].swap ? 1 : 0)));
          }
        }
      };
      grow(start);
      for (std::uint32_t c : nodes) grow(c);
    }
    for (std::uint32_t c : order) placed[c] = 0;
    for (std::size_t k = 0; k < order.size(); ++k) label[order[k]] = track[k];

    const RawCrossing& first = set.items[order.front()];
    contour.tracks[0].mesh = topo.edge_mesh(first.edge);
    contour.tracks[1].mesh = topo.tri_mesh[first.face];
    contour.self = contour.tracks[0].mesh == contour.tracks[1].mesh;

    // Ends: boundary edges count for the track holding the edge; loop vertices for neither.
    std::vector<std::uint32_t> loop_ends;
    for (std::uint32_t c : order) {
      for (std::uint32_t i = link_begin[c]; i < link_begin[c + 1]; ++i) {
        if (links[i].kind == LinkKind::kBoundary) ++contour.tracks[label[c]].boundary_ends;
        if (links[i].kind == LinkKind::kLoop) loop_ends.push_back(links[i].target);
      }
    }
    contour.loop_vertices = loop_ends.size();
    traced.loop_vertex_ids = loop_ends;

    // Polyline: loop vertex, crossing points, loop vertex.
    auto loop_of = [&](std::uint32_t c) -> std::uint32_t {
      for (std::uint32_t i = link_begin[c]; i < link_begin[c + 1]; ++i)
        if (links[i].kind == LinkKind::kLoop) return links[i].target;
      return kNone;
    };
    if (!contour.closed && !branched) {
      const std::uint32_t lv = loop_of(order.front());
      if (lv != kNone) contour.polyline.push_back(topo.points[lv]);
    }
    for (std::uint32_t c : order) contour.polyline.push_back(set.items[c].point);
    if (!contour.closed && !branched && order.size() > 1) {
      const std::uint32_t lv = loop_of(order.back());
      if (lv != kNone) contour.polyline.push_back(topo.points[lv]);
    }
    for (std::size_t k = 1; k < contour.polyline.size(); ++k)
      contour.length += norm(sub(contour.polyline[k - 1], contour.polyline[k]));
    if (contour.closed && contour.polyline.size() > 2)
      contour.length += norm(sub(contour.polyline.back(), contour.polyline.front()));

    contour.crossings = order;
    traced.edge_track = track;
    out.push_back(std::move(traced));
  }

  // Track types, cut edges and separation: each track on its own (in parallel, with its own
  // scratch), written into its own slot.
  std::vector<std::array<std::uint32_t, 2>> jobs;  // (contour, track)
  for (std::uint32_t c = 0; c < out.size(); ++c) jobs.push_back({c, 0}), jobs.push_back({c, 1});
  if (threads == 1 || jobs.size() < 2) {
    // On this thread alone: one scratch, without the thread-local storage, whose first use loads
    // and starts TBB's allocator (2.4% of a one-thread `check` of the shipped MakeHuman pair,
    // issue 24).
    SeparationScratch scratch;
    for (std::size_t j = 0; j < jobs.size(); ++j)
      classify_track(topo, set, out[jobs[j][0]], jobs[j][1], separation, scratch);
    return out;
  }
  tbb::enumerable_thread_specific<SeparationScratch> scratches;
  run_parallel(threads, jobs.size(), 1, [&](std::size_t begin, std::size_t end) {
    SeparationScratch& scratch = scratches.local();
    for (std::size_t j = begin; j < end; ++j)
      classify_track(topo, set, out[jobs[j][0]], jobs[j][1], separation, scratch);
  });
  return out;
}

}  // namespace untangle
