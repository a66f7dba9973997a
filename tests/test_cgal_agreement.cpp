// Detection agrees with CGAL: on every generated scene and on random scenes, the intersecting
// triangle pairs of untangle::find_intersections equal those of CGAL's Polygon_mesh_processing.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cgal_reference.h"
#include "scenes/scenes.h"
#include "untangle/intersections.h"
#include "untangle/mesh.h"

namespace untangle {
namespace {

using cgal_reference::TrianglePair;

std::vector<Mesh> all_meshes(const scenes::Scene& scene) {
  std::vector<Mesh> meshes = scene.movable;
  meshes.insert(meshes.end(), scene.obstacles.begin(), scene.obstacles.end());
  return meshes;
}

// Corners of triangle a and triangle b (same mesh) at identical positions: 0 (disjoint), 1
// (sharing a vertex) or 2 (sharing an edge), on welded topology as both sides see it.
int shared_corners(const Mesh& ma, std::uint32_t ta, const Mesh& mb, std::uint32_t tb) {
  if (&ma != &mb) return 0;
  int shared = 0;
  for (std::uint32_t va : ma.triangles[ta]) {
    for (std::uint32_t vb : mb.triangles[tb]) {
      if (ma.positions[va] == mb.positions[vb]) {
        ++shared;
        break;
      }
    }
  }
  return shared;
}

std::string describe(const std::vector<Mesh>& meshes, const TrianglePair& pair) {
  std::ostringstream out;
  out.precision(17);
  const Mesh& ma = meshes[pair[0]];
  const Mesh& mb = meshes[pair[2]];
  out << "  (mesh " << pair[0] << " tri " << pair[1] << ", mesh " << pair[2] << " tri " << pair[3]
      << "): shared corners " << shared_corners(ma, pair[1], mb, pair[3])
      << ", CGAL do_intersect(Triangle_3, Triangle_3) = "
      << (cgal_reference::do_triangles_intersect(ma, pair[1], mb, pair[3]) ? "true" : "false")
      << ", degenerate contact "
      << (cgal_reference::degenerate_contact(ma, pair[1], mb, pair[3]) ? "yes" : "no") << "\n";
  for (int side = 0; side < 2; ++side) {
    const Mesh& m = side == 0 ? ma : mb;
    const std::uint32_t t = pair[side == 0 ? 1 : 3];
    out << "    " << (side == 0 ? "A" : "B") << ":";
    for (std::uint32_t v : m.triangles[t]) {
      const Vec3& p = m.positions[v];
      out << " v" << v << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
    }
    out << "\n";
  }
  return out.str();
}

// Requires find_intersections(meshes).triangle_pairs == CGAL's pairs; prints the first
// differences (with coordinates) otherwise. `expect_some` additionally requires a non-empty answer.
void expect_agreement(const std::vector<Mesh>& meshes, const std::string& label, bool expect_some) {
  SCOPED_TRACE(label);
  const std::vector<cgal_reference::ReferenceMesh> reference =
      cgal_reference::to_reference_meshes(meshes);
  for (std::size_t i = 0; i < reference.size(); ++i) {
    ASSERT_TRUE(reference[i].degenerate.empty())
        << "mesh " << i << " has " << reference[i].degenerate.size()
        << " degenerate triangles (first: " << reference[i].degenerate.front()
        << "); this comparison is for non-degenerate scenes";
  }
  const std::vector<TrianglePair> expected = cgal_reference::triangle_pairs(reference);
  const Intersections ours = find_intersections(meshes);
  const std::vector<TrianglePair>& actual = ours.triangle_pairs;

  EXPECT_TRUE(std::is_sorted(actual.begin(), actual.end())) << "our triangle_pairs are not sorted";
  for (const TrianglePair& p : actual) {
    EXPECT_LT(std::make_pair(p[0], p[1]), std::make_pair(p[2], p[3]))
        << "our pair is not ordered: " << p[0] << " " << p[1] << " " << p[2] << " " << p[3];
  }
  EXPECT_EQ(ours.counts.triangle_pairs, actual.size());
  if (expect_some) {
    EXPECT_FALSE(expected.empty()) << "CGAL finds no intersection in this scene";
  }
  // The comparison is meant for scenes in general position: there CGAL's closed-set answer and
  // our symbolic perturbation must coincide. Say so when the scene is not.
  std::vector<TrianglePair> degenerate;
  for (const TrianglePair& p : expected) {
    if (cgal_reference::degenerate_contact(meshes[p[0]], p[1], meshes[p[2]], p[3])) {
      degenerate.push_back(p);
    }
  }
  EXPECT_TRUE(degenerate.empty())
      << "the scene is not in general position: " << degenerate.size()
      << " intersecting pairs touch degenerately (vertex on triangle, edge on edge or coplanar), "
         "where CGAL and a symbolic perturbation may differ; first:\n"
      << describe(meshes, degenerate.front());

  if (actual == expected) return;
  std::vector<TrianglePair> only_ours, only_cgal;
  std::set_difference(actual.begin(), actual.end(), expected.begin(), expected.end(),
                      std::back_inserter(only_ours));
  std::set_difference(expected.begin(), expected.end(), actual.begin(), actual.end(),
                      std::back_inserter(only_cgal));
  constexpr std::size_t kShown = 8;
  std::ostringstream message;
  message << "triangle pairs differ: ours " << actual.size() << ", CGAL " << expected.size()
          << "; only ours " << only_ours.size() << ", only CGAL " << only_cgal.size() << "\n";
  message << "first pairs only in ours:\n";
  for (std::size_t i = 0; i < std::min(kShown, only_ours.size()); ++i) {
    message << describe(meshes, only_ours[i]);
  }
  message << "first pairs only in CGAL's:\n";
  for (std::size_t i = 0; i < std::min(kShown, only_cgal.size()); ++i) {
    message << describe(meshes, only_cgal[i]);
  }
  ADD_FAILURE() << message.str();
}

// ---- the named scenes ----

struct NamedScene {
  const char* name;
  std::function<scenes::Scene()> make;
};

const std::vector<NamedScene>& named_scenes() {
  static const std::vector<NamedScene> kScenes = {
      {"sheet_through_sphere", scenes::sheet_through_sphere},
      {"strip_through_sheet", scenes::strip_through_sheet},
      {"sheets_corner", scenes::sheets_corner},
      {"folded_sheet", scenes::folded_sheet},
      {"tube_around_body", scenes::tube_around_body},
      {"garment_four_loops", scenes::garment_four_loops},
      {"sheet_on_spikes", scenes::sheet_on_spikes},
  };
  return kScenes;
}

class CgalNamedScene : public ::testing::TestWithParam<std::size_t> {};

TEST_P(CgalNamedScene, SameTrianglePairsAsCgal) {
  const NamedScene& named = named_scenes()[GetParam()];
  const scenes::Scene scene = named.make();
  expect_agreement(all_meshes(scene), named.name, true);
}

INSTANTIATE_TEST_SUITE_P(CgalAgreement, CgalNamedScene,
                         ::testing::Range<std::size_t>(0, named_scenes().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& info) {
                           return std::string(named_scenes()[info.param].name);
                         });

TEST(CgalAgreement, SheetThroughCow) {
  if (scenes::cow_path().empty()) {
    GTEST_SKIP() << "cow.off of Debian's libcgal-demo is not installed "
                    "(/usr/share/doc/libcgal-demo/data.tar.gz); install libcgal-demo and re-run "
                    "cmake to compare on the cow";
  }
  const scenes::Scene scene = scenes::sheet_through_cow(41);
  expect_agreement(all_meshes(scene), "sheet_through_cow(41)", true);
}

// ---- random scenes ----

// splitmix64: the same numbers on every platform (std::uniform_real_distribution is not).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(next() >> 11) * 0x1.0p-53);
  }
  int integer(int lo, int hi) {  // in [lo, hi]
    return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1));
  }

 private:
  std::uint64_t state_;
};

// Rotates a mesh by a random rotation (unit quaternion) about the origin and moves it by `shift`.
void random_motion(Mesh& mesh, Random& random, const Vec3& shift) {
  double q[4];
  double norm = 0.0;
  do {
    norm = 0.0;
    for (double& c : q) {
      c = random.uniform(-1.0, 1.0);
      norm += c * c;
    }
  } while (norm < 1e-3 || norm > 1.0);
  norm = std::sqrt(norm);
  for (double& c : q) c /= norm;
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  for (Vec3& p : mesh.positions) {
    const Vec3 old = p;
    for (int i = 0; i < 3; ++i) {
      p[i] = r[i][0] * old[0] + r[i][1] * old[1] + r[i][2] * old[2] + shift[i];
    }
  }
}

// A sheet of random resolution over [-1, 1]^2 with every vertex jittered in 3D by up to
// `jitter` cell sizes: small jitter gives a wavy sheet; jitter near 1 folds triangles over their
// neighbours (self-intersections, many of them between triangles sharing a vertex).
Mesh random_sheet(Random& random, double jitter, const std::string& name) {
  const int nu = random.integer(4, 11), nv = random.integer(4, 11);
  Mesh mesh = scenes::grid_sheet(nu, nv, {-1.0, -1.0, 0.0}, {2.0, 0.0, 0.0}, {0.0, 2.0, 0.0}, name);
  const double cell = 2.0 / std::max(nu - 1, nv - 1);
  for (Vec3& p : mesh.positions) {
    for (double& c : p) c += random.uniform(-jitter, jitter) * cell;
  }
  return mesh;
}

// A closed UV sphere of random resolution and radius with every vertex moved radially and
// tangentially by up to `jitter` times the radius.
Mesh random_sphere(Random& random, double jitter, const std::string& name) {
  const double radius = random.uniform(0.5, 1.0);
  Mesh mesh = scenes::uv_sphere({0.0, 0.0, 0.0}, radius, random.integer(5, 14),
                                random.integer(4, 10), name);
  for (Vec3& p : mesh.positions) {
    for (double& c : p) c += random.uniform(-jitter, jitter) * radius;
  }
  return mesh;
}

Mesh random_mesh(Random& random, const std::string& name) {
  switch (random.integer(0, 3)) {
    case 0:
      return random_sheet(random, 0.15, name);  // wavy sheet, no self-intersection expected
    case 1:
      return random_sheet(random, 0.9, name);  // crumpled sheet, self-intersecting
    case 2:
      return random_sphere(random, 0.05, name);  // bumpy closed sphere
    default:
      return random_sphere(random, 0.3, name);  // crumpled closed sphere, self-intersecting
  }
}

// Two random meshes, randomly rotated, their centres at most 0.4 apart so that they usually cross.
std::vector<Mesh> random_scene(std::uint64_t seed) {
  Random random(seed * 7919 + 1);
  std::vector<Mesh> meshes;
  for (int i = 0; i < 2; ++i) {
    Mesh mesh = random_mesh(random, "random" + std::to_string(i));
    const Vec3 shift = {random.uniform(-0.2, 0.2), random.uniform(-0.2, 0.2),
                        random.uniform(-0.2, 0.2)};
    random_motion(mesh, random, shift);
    mesh.role = i == 0 ? Role::kMovable : Role::kObstacle;
    meshes.push_back(std::move(mesh));
  }
  return meshes;
}

// The same scene with the meshes swapped and, inside each mesh, vertices and triangles in reverse
// order (so that nothing depends on input order).
std::vector<Mesh> permuted(const std::vector<Mesh>& meshes) {
  std::vector<Mesh> out(meshes.rbegin(), meshes.rend());
  for (Mesh& mesh : out) {
    const auto n = static_cast<std::uint32_t>(mesh.positions.size());
    std::reverse(mesh.positions.begin(), mesh.positions.end());
    std::reverse(mesh.triangles.begin(), mesh.triangles.end());
    std::reverse(mesh.polygon.begin(), mesh.polygon.end());
    for (Triangle& t : mesh.triangles) {
      for (std::uint32_t& v : t) v = n - 1 - v;
      std::rotate(t.begin(), t.begin() + 1, t.end());  // same orientation, other first corner
    }
  }
  return out;
}

class CgalRandomScene : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(CgalRandomScene, SameTrianglePairsAsCgal) {
  const std::vector<Mesh> meshes = random_scene(GetParam());
  expect_agreement(meshes, "random scene seed " + std::to_string(GetParam()), false);
  expect_agreement(permuted(meshes),
                   "random scene seed " + std::to_string(GetParam()) + ", permuted", false);
}

INSTANTIATE_TEST_SUITE_P(CgalAgreement, CgalRandomScene, ::testing::Range<std::uint64_t>(0, 20));

// The random scenes are meant to exercise both kinds of pairs; make sure they do.
TEST(CgalAgreement, RandomScenesCoverSelfAndMutualPairs) {
  std::size_t self = 0, mutual = 0, sharing_vertex = 0;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const std::vector<Mesh> meshes = random_scene(seed);
    for (const TrianglePair& p : cgal_reference::triangle_pairs(meshes)) {
      if (p[0] == p[2]) {
        ++self;
        if (shared_corners(meshes[p[0]], p[1], meshes[p[2]], p[3]) == 1) ++sharing_vertex;
      } else {
        ++mutual;
      }
    }
  }
  std::printf("random scenes: %zu pairs between meshes, %zu within (%zu sharing a vertex)\n", mutual,
              self, sharing_vertex);
  EXPECT_GT(mutual, 100u);
  EXPECT_GT(self, 20u);
  EXPECT_GT(sharing_vertex, 5u);
}

// ---- a pinched mesh: two spheres welded at one point ----

// One mesh made of two closed spheres whose poles are the same point P (a non-manifold, pinched
// vertex after welding: two closed fans meet there, as at vertices 44/2903 of CGAL's cow.off). The
// small sphere is tilted about P, so the two surfaces cross along a circle through P: pairs of
// triangles around P share the welded vertex and cross beyond it.
std::vector<Mesh> pinched_spheres() {
  Mesh big = scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 16, 10, "big");
  Mesh small = scenes::uv_sphere({0.0, 0.0, -1.5}, 0.5, 12, 8, "small");
  const auto extreme = [](const Mesh& m, bool top) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < m.positions.size(); ++i) {
      if (top ? m.positions[i][2] > m.positions[best][2] : m.positions[i][2] < m.positions[best][2]) {
        best = i;
      }
    }
    return best;
  };
  const Vec3 pinch = big.positions[extreme(big, false)];
  const std::size_t small_top = extreme(small, true);
  // Tilt the small sphere by 0.6 rad about the x axis through P, nudge it off the plane x = 0 (the
  // spheres' common symmetry plane) and put its pole exactly on P.
  const double c = std::cos(0.6), s = std::sin(0.6);
  for (std::size_t i = 0; i < small.positions.size(); ++i) {
    Vec3& p = small.positions[i];
    const double y = p[1] - pinch[1], z = p[2] - pinch[2];
    p = {p[0] + 0.0123, pinch[1] + c * y - s * z, pinch[2] + s * y + c * z};
    if (i == small_top) p = pinch;
  }
  Mesh mesh = big;
  mesh.name = "pinched";
  const auto offset = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), small.positions.begin(), small.positions.end());
  for (Triangle t : small.triangles) {
    for (std::uint32_t& v : t) v += offset;
    mesh.triangles.push_back(t);
  }
  mesh.polygon.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.polygon.size(); ++t) mesh.polygon[t] = static_cast<std::uint32_t>(t);
  mesh.source_faces = mesh.triangles.size();
  return {mesh};
}

TEST(CgalAgreement, PinchedVertex) {
  const std::vector<Mesh> meshes = pinched_spheres();
  const cgal_reference::ReferenceMesh reference = cgal_reference::to_reference_mesh(meshes[0]);
  EXPECT_EQ(reference.split_vertices, 1u);
  std::size_t at_pinch = 0;
  for (const TrianglePair& p : cgal_reference::triangle_pairs(meshes)) {
    at_pinch += shared_corners(meshes[0], p[1], meshes[0], p[3]) == 1;
  }
  EXPECT_GT(at_pinch, 0u) << "no crossing pair shares the pinched vertex: the scene tests nothing";
  expect_agreement(meshes, "pinched spheres", true);
  expect_agreement(permuted(meshes), "pinched spheres, permuted", true);
}

// ---- the reference itself ----

// The rules of cgal_reference.h stated independently, over all pairs (O(n^2), small scenes only):
// corners at identical positions of one mesh are shared; sharing two never counts; sharing one
// counts when the edge opposite it in one triangle meets the other triangle; otherwise the
// triangles intersect as closed sets.
std::vector<TrianglePair> brute_force_pairs(const std::vector<Mesh>& meshes) {
  using cgal_reference::Point;
  using Segment = cgal_reference::Kernel::Segment_3;
  using Triangle3 = cgal_reference::Kernel::Triangle_3;
  const auto point = [](const Mesh& m, std::uint32_t v) {
    return Point(m.positions[v][0], m.positions[v][1], m.positions[v][2]);
  };
  const auto triangle = [&](const Mesh& m, std::uint32_t t) {
    return Triangle3(point(m, m.triangles[t][0]), point(m, m.triangles[t][1]),
                     point(m, m.triangles[t][2]));
  };
  std::vector<TrianglePair> out;
  for (std::uint32_t a = 0; a < meshes.size(); ++a) {
    for (std::uint32_t b = a; b < meshes.size(); ++b) {
      const Mesh &ma = meshes[a], &mb = meshes[b];
      for (std::uint32_t s = 0; s < ma.triangles.size(); ++s) {
        for (std::uint32_t t = a == b ? s + 1 : 0; t < mb.triangles.size(); ++t) {
          const int shared = shared_corners(ma, s, mb, t);
          bool hit = false;
          if (shared == 0) {
            hit = CGAL::do_intersect(triangle(ma, s), triangle(mb, t));
          } else if (shared == 1) {
            for (int side = 0; side < 2 && !hit; ++side) {
              const Triangle& own = ma.triangles[side == 0 ? s : t];
              const Triangle& other = ma.triangles[side == 0 ? t : s];
              std::vector<std::uint32_t> opposite;  // corners of `own` not shared with `other`
              for (std::uint32_t v : own) {
                bool is_shared = false;
                for (std::uint32_t w : other) is_shared |= ma.positions[v] == ma.positions[w];
                if (!is_shared) opposite.push_back(v);
              }
              hit = CGAL::do_intersect(Segment(point(ma, opposite[0]), point(ma, opposite[1])),
                                       triangle(ma, side == 0 ? t : s));
            }
          }
          if (hit) out.push_back({a, s, b, t});
        }
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(CgalAgreement, ReferenceMatchesBruteForce) {
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const std::vector<Mesh> meshes = random_scene(seed);
    EXPECT_EQ(cgal_reference::triangle_pairs(meshes), brute_force_pairs(meshes))
        << "random scene seed " << seed;
  }
  const std::vector<Mesh> pinched = pinched_spheres();
  EXPECT_EQ(cgal_reference::triangle_pairs(pinched), brute_force_pairs(pinched))
      << "pinched spheres";
}

}  // namespace
}  // namespace untangle
