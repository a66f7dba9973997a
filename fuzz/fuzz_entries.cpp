// The per-input logic of the fuzz targets (see fuzz_entries.h).
#include "fuzz_entries.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

#include "check/summarize.h"
#include "untangle/error.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"

namespace untangle::fuzz {
namespace {

// Fuzz code may print (the library never does): one line naming the broken invariant, then abort,
// which libFuzzer turns into a saved crash input and a test run into a failure.
#define FUZZ_CHECK(condition, what)                                                         \
  do {                                                                                      \
    if (!(condition)) {                                                                     \
      std::fprintf(stderr, "fuzz invariant violated: %s (%s) at %s:%d\n", what, #condition, \
                   __FILE__, __LINE__);                                                     \
      std::abort();                                                                         \
    }                                                                                       \
  } while (false)

// ----- loader -----

// Extensions of the formats assimp reads (and our own OBJ and OFF readers), and none at all
// (assimp then guesses from the content). The letters make seed files readable: "o" + OBJ text.
const char* extension_for(std::uint8_t selector) {
  switch (selector) {
    case 'o':
      return ".obj";
    case 'f':
      return ".off";
    case 'p':
      return ".ply";
    case 's':
      return ".stl";
    case 'g':
      return ".gltf";
    case 'b':
      return ".glb";
    case 'x':
      return ".fbx";
    default:
      break;
  }
  static const char* const kOthers[] = {".obj", ".off", ".ply", ".stl", ".gltf", ".glb",
                                        ".fbx", ".3ds", ".dae", ".x",   ".ms3d", ".lwo",
                                        ".ase", ".md2", ".smd", ".raw", ".ac",   ""};
  return kOthers[selector % (sizeof kOthers / sizeof kOthers[0])];
}

// One scratch directory per process: parallel fuzzing jobs (-jobs, -workers) must not share files.
// Removed at exit, so that test runs leave nothing behind.
class ScratchDirectory {
 public:
  ScratchDirectory()
      : path_(std::filesystem::temp_directory_path() /
              ("untangle-fuzz-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::filesystem::path scratch_directory() {
  static const ScratchDirectory dir;
  return dir.path();
}

// Loaded scenes larger than this skip detection: libFuzzer inputs are a few KB, but a small file
// may legitimately instance a mesh many times, and detection time is not what this target tests.
constexpr std::size_t kMaxDetectedTriangles = 20000;

// ----- contours -----

// Reads the fuzz input as a stream of small numbers; past the end it yields zeros, so every input
// describes a complete scene.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t next() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint32_t below(std::uint32_t n) { return n == 0 ? 0 : next() % n; }
  std::uint32_t below_wide(std::uint32_t n) {  // two bytes, for ids in larger ranges
    const std::uint32_t hi = next();
    return n == 0 ? 0 : ((hi << 8) | next()) % n;
  }
  // A coordinate on the grid {-r/2, ..., r/2} in half units: coarse, so degeneracies are common.
  double coordinate(int r) {
    return (static_cast<int>(below(static_cast<std::uint32_t>(r + 1))) - r / 2) * 0.5;
  }
  bool empty() const { return pos_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

Vec3 point_from(Bytes& in, int r) { return {in.coordinate(r), in.coordinate(r), in.coordinate(r)}; }

void add_triangle(Mesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  mesh.polygon.push_back(static_cast<std::uint32_t>(mesh.triangles.size()));
  mesh.triangles.push_back({a, b, c});
  mesh.source_faces = mesh.triangles.size();
}

// A sheet of nx x ny quads spanned by two grid vectors (possibly parallel or zero: degenerate
// sheets are wanted too), each quad split along the diagonal a bit chooses.
Mesh grid_sheet(Bytes& in) {
  Mesh mesh;
  const std::uint32_t nx = 1 + in.below(4), ny = 1 + in.below(4);
  const Vec3 origin = point_from(in, 8);
  const Vec3 u = point_from(in, 4), v = point_from(in, 4);
  for (std::uint32_t j = 0; j <= ny; ++j)
    for (std::uint32_t i = 0; i <= nx; ++i)
      mesh.positions.push_back({origin[0] + i * u[0] + j * v[0], origin[1] + i * u[1] + j * v[1],
                                origin[2] + i * u[2] + j * v[2]});
  const std::uint8_t diagonals = in.next();
  for (std::uint32_t j = 0; j < ny; ++j) {
    for (std::uint32_t i = 0; i < nx; ++i) {
      const std::uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      if ((diagonals >> ((i + j) % 8)) & 1) {
        add_triangle(mesh, a, b, d);
        add_triangle(mesh, a, d, c);
      } else {
        add_triangle(mesh, a, b, c);
        add_triangle(mesh, b, d, c);
      }
    }
  }
  return mesh;
}

// Arbitrary triangles over a few grid points: shared and non-manifold edges, repeated corners
// (dropped as degenerate by the topology), duplicated positions (welded).
Mesh triangle_soup(Bytes& in) {
  Mesh mesh;
  const std::uint32_t vertices = 3 + in.below(10);
  for (std::uint32_t v = 0; v < vertices; ++v) mesh.positions.push_back(point_from(in, 6));
  const std::uint32_t triangles = 1 + in.below(12);
  for (std::uint32_t t = 0; t < triangles; ++t) {
    const std::uint32_t a = in.below(vertices), b = in.below(vertices), c = in.below(vertices);
    add_triangle(mesh, a, b, c);
  }
  return mesh;
}

// A closed tetrahedron (contours through it close), possibly flat.
Mesh tetrahedron(Bytes& in) {
  Mesh mesh;
  for (int v = 0; v < 4; ++v) mesh.positions.push_back(point_from(in, 6));
  add_triangle(mesh, 0, 2, 1);
  add_triangle(mesh, 0, 1, 3);
  add_triangle(mesh, 1, 2, 3);
  add_triangle(mesh, 2, 0, 3);
  return mesh;
}

bool shares_vertex(const std::array<std::uint32_t, 3>& tri, std::uint32_t v) {
  return tri[0] == v || tri[1] == v || tri[2] == v;
}

// Detection against brute force: every edge against every face it shares no vertex with (pairs of
// one mesh only when `self_pairs`); the same set, in the same order.
void check_detection(const SceneTopology& topo, const CrossingSet& set, bool self_pairs) {
  std::vector<std::array<std::uint32_t, 2>> expected;
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
    const auto [p, q] = topo.edges[e];
    for (std::uint32_t f = 0; f < topo.tris.size(); ++f) {
      const auto& face = topo.tris[f];
      if (!self_pairs && topo.edge_mesh(e) == topo.tri_mesh[f]) continue;
      if (shares_vertex(face, p) || shares_vertex(face, q)) continue;
      if (edge_crosses_triangle(topo.points, p, q, face[0], face[1], face[2]))
        expected.push_back({e, f});
    }
  }
  FUZZ_CHECK(expected.size() == set.items.size(), "detect_crossings finds what brute force finds");
  for (std::size_t i = 0; i < expected.size(); ++i) {
    FUZZ_CHECK(set.items[i].edge == expected[i][0] && set.items[i].face == expected[i][1],
               "detect_crossings finds what brute force finds, sorted");
  }
  // The 0-or-2 property: two triangles sharing no vertex meet in a segment between two crossings
  // or not at all; sharing one vertex, in a segment from it to one crossing or not at all.
  std::vector<std::uint32_t> count(topo.tris.size() * topo.tris.size(), 0);
  for (const RawCrossing& c : set.items) {
    for (std::uint32_t i = topo.edge_face_begin[c.edge]; i < topo.edge_face_begin[c.edge + 1];
         ++i) {
      const std::uint32_t t = topo.edge_faces[i];
      ++count[std::min(t, c.face) * topo.tris.size() + std::max(t, c.face)];
    }
  }
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    for (std::uint32_t u = t + 1; u < topo.tris.size(); ++u) {
      if (!self_pairs && topo.tri_mesh[t] == topo.tri_mesh[u]) continue;
      int shared = 0;
      for (std::uint32_t v : topo.tris[t]) shared += shares_vertex(topo.tris[u], v);
      const std::uint32_t n = count[t * topo.tris.size() + u];
      if (shared == 0) FUZZ_CHECK(n == 0 || n == 2, "0 or 2 crossings per disjoint triangle pair");
      if (shared == 1) FUZZ_CHECK(n <= 1, "0 or 1 crossing per triangle pair sharing a vertex");
      if (shared >= 2) FUZZ_CHECK(n == 0, "no crossing between triangles sharing an edge");
    }
  }
}

// A crossing set chosen by the bytes, ids in range: a subset of the real crossings, invented
// (edge, face) pairs, or both; sorted and unique as CrossingSet requires.
CrossingSet raw_crossings(Bytes& in, const SceneTopology& topo, const CrossingSet& real) {
  std::vector<RawCrossing> items;
  const std::uint8_t mode = in.next();
  if ((mode & 1) != 0) {
    for (const RawCrossing& c : real.items)
      if (in.below(4) != 0) items.push_back(c);
  }
  if ((mode & 2) != 0 && !topo.edges.empty() && !topo.tris.empty()) {
    const std::uint32_t invented = in.below(24);
    for (std::uint32_t k = 0; k < invented; ++k) {
      RawCrossing c;
      c.edge = in.below_wide(static_cast<std::uint32_t>(topo.edges.size()));
      c.face = in.below_wide(static_cast<std::uint32_t>(topo.tris.size()));
      const Vec3& p = topo.points[topo.edges[c.edge][0]];
      const Vec3& q = topo.points[topo.edges[c.edge][1]];
      c.point = {0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])};
      items.push_back(c);
    }
  }
  return make_crossing_set(std::move(items));
}

}  // namespace

CrossingSet make_crossing_set(std::vector<RawCrossing> items) {
  auto key = [](const RawCrossing& c) { return std::make_pair(c.edge, c.face); };
  std::stable_sort(items.begin(), items.end(),
                   [&](const RawCrossing& a, const RawCrossing& b) { return key(a) < key(b); });
  items.erase(
      std::unique(items.begin(), items.end(),
                  [&](const RawCrossing& a, const RawCrossing& b) { return key(a) == key(b); }),
      items.end());
  CrossingSet set;
  set.items = std::move(items);
  return set;
}

void check_contours(const SceneTopology& topo, const CrossingSet& set,
                    const std::vector<TracedContour>& contours, bool from_detection) {
  const std::size_t n = set.items.size();
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  std::vector<std::uint32_t> seen(n, 0);
  for (const TracedContour& traced : contours) {
    const Contour& contour = traced.contour;
    FUZZ_CHECK(!contour.crossings.empty(), "a contour has crossings");
    FUZZ_CHECK(traced.edge_track.size() == contour.crossings.size(),
               "one track label per crossing");
    for (std::size_t k = 0; k < contour.crossings.size(); ++k) {
      FUZZ_CHECK(contour.crossings[k] < n, "contour crossings index into the set");
      FUZZ_CHECK(traced.edge_track[k] <= 1, "track labels are 0 or 1");
      ++seen[contour.crossings[k]];
    }
    FUZZ_CHECK(contour.loop_vertices == traced.loop_vertex_ids.size(), "loop vertex count");
    for (std::uint32_t v : traced.loop_vertex_ids)
      FUZZ_CHECK(v < topo.points.size(), "loop vertices are welded vertex ids");
    for (const Track& track : contour.tracks) {
      FUZZ_CHECK(track.mesh < meshes, "tracks lie on meshes of the scene");
      FUZZ_CHECK(track.cut_edges <= contour.crossings.size(), "cut edges are crossed edges");
      FUZZ_CHECK(std::isfinite(track.smaller_area) && track.smaller_area >= 0.0, "area");
      if (contour.closed)
        FUZZ_CHECK(track.type == TrackType::kCL, "closed contours have CL tracks");
    }
    FUZZ_CHECK(contour.polyline.size() >= contour.crossings.size(),
               "a polyline point per crossing");
    FUZZ_CHECK(std::isfinite(contour.length) && contour.length >= 0.0, "contour length");
    if (from_detection) FUZZ_CHECK(!traced.broken, "no broken contour from a real detection");
  }
  for (std::size_t c = 0; c < n; ++c)
    FUZZ_CHECK(seen[c] == 1, "every crossing on exactly one contour");

  const Intersections summary = summarize(topo, set, contours);
  FUZZ_CHECK(summary.counts.crossings == n, "summary counts every crossing");
  FUZZ_CHECK(summary.counts.contours == contours.size(), "summary counts every contour");
  if (from_detection) FUZZ_CHECK(summary.counts.broken == 0, "summary reports no broken contour");
}

int fuzz_load_one(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string path =
      (scratch_directory() / ("input" + std::string(extension_for(data[0])))).string();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  std::vector<Mesh> meshes;
  try {
    meshes = read_meshes(path, Role::kMovable);
  } catch (const Error& e) {
    FUZZ_CHECK(e.code() == ExitCode::kUnreadableInput, "bad files are unreadable input");
  }
  std::filesystem::remove(path);
  std::size_t triangles = 0;
  for (const Mesh& mesh : meshes) {
    FUZZ_CHECK(mesh.polygon.size() == mesh.triangles.size(), "a source face per triangle");
    for (const Triangle& t : mesh.triangles)
      for (std::uint32_t v : t) FUZZ_CHECK(v < mesh.positions.size(), "triangle corners in range");
    for (const Vec3& p : mesh.positions)
      for (double c : p) FUZZ_CHECK(std::isfinite(c), "finite coordinates");
    triangles += mesh.triangles.size();
  }
  if (meshes.empty() || triangles > kMaxDetectedTriangles) return 0;
  DetectOptions options;
  options.threads = 1;
  const Intersections found = find_intersections(meshes, options);
  FUZZ_CHECK(found.counts.broken == 0, "no broken contour in a loaded file");
  FUZZ_CHECK(found.counts.contours == found.contours.size(), "contour count");
  return 0;
}

int fuzz_contours_one(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  const std::uint8_t flags = in.next();
  const bool self_pairs = (flags & 1) != 0;
  const std::uint32_t mesh_count = 1 + (flags >> 1) % 3;
  std::vector<Mesh> meshes;
  for (std::uint32_t m = 0; m < mesh_count; ++m) {
    switch (in.below(3)) {
      case 0:
        meshes.push_back(grid_sheet(in));
        break;
      case 1:
        meshes.push_back(triangle_soup(in));
        break;
      default:
        meshes.push_back(tetrahedron(in));
        break;
    }
    meshes.back().path = "fuzz";
  }

  const SceneTopology topo = build_topology(meshes);
  DetectSettings settings;
  settings.threads = 1;
  settings.self_pairs = self_pairs;
  const CrossingSet real = detect_crossings(topo, settings);
  check_detection(topo, real, self_pairs);
  check_contours(topo, real, build_contours(topo, real), /*from_detection=*/true);

  // Contour building from raw crossings: whatever the set, it must terminate and stay in range.
  const CrossingSet raw = raw_crossings(in, topo, real);
  check_contours(topo, raw, build_contours(topo, raw), /*from_detection=*/false);
  return 0;
}

}  // namespace untangle::fuzz
