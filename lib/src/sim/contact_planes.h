// Contact inside the integrator: at the start of every step, each cloth particle within reach of
// an obstacle, of another cloth mesh or of a far part of its own mesh gets, per such mesh, the
// tangent plane at its closest point there as a one-sided constraint of that step's solve
// (cloth_model.h, integrate_step). The planes are made fresh every step, so they follow the cloth
// as it wraps round and as the sheets below it move; resting contact then holds without the
// correction having to undo every step's push into what the cloth lies on. What slips between the
// planes (an edge over a spike's tip, an edge of a fold through an edge of the layer under it) is
// the correction's, as before.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "resolve/triangle_tree.h"
#include "sim/cloth_model.h"
#include "resolve/scene_measures.h"
#include "topology/scene_topology.h"
#include "untangle/mesh.h"

namespace untangle {

class ContactPlanes {
 public:
  // The obstacles of `meshes` (their exposed faces: a buried face of an obstacle that passes
  // through itself, like the cow's tail through its rump, is inside it and gives no plane) and
  // the cloth of `model`.
  ContactPlanes(const std::vector<Mesh>& meshes, const ClothModel& model, int threads);
  ~ContactPlanes();
  // The obstacles moved (a schedule): the same faces at their new positions.
  void update_obstacles(const std::vector<Mesh>& meshes);
  // The planes of this step, for particles at `x`, within `reach` (scene units) of a surface:
  //  - an obstacle's plane lies `clearance` out from the closest point (never farther than the
  //    particle is now), so the particle may come up to the clearance but not nearer;
  //  - another cloth mesh moves too, so each side may close half of the gap beyond `gap` (the
  //    cloth's thickness, at least the clearance): the plane lies (d + gap) / 2 out for a particle
  //    d away (d, if d is under the gap), and the two sides' planes keep them apart;
  //  - a convex obstacle vertex within reach of a cloth face gives that face's closest point a
  //    plane `clearance` out from the vertex along the vertex's outward normal (a face plane: a
  //    coarse ball's vertices poke out between the cloth's particles; integrate_step spreads the
  //    lift over rings round the face's corners). A tip (an angle defect beyond about 57
  //    degrees: a spike's, the cow's horns) gets none; the correction handles it.
  //  - with `self`, a particle within reach of a triangle of its own mesh that is far from it on
  //    the cloth (no corner within 1.5 times the reach of it along the edges of the rest shape,
  //    model.topo.points) gets a plane as against another cloth mesh, from the closest such
  //    point: a fold of the sheet onto itself is held apart in the solve. A flat sheet gets none.
  void make(const ClothModel& model, const std::vector<Vec3>& x, double reach, double clearance,
            double gap, bool self, ContactSet& out);
  // How many of the planes of the last make are self-contact planes.
  std::size_t self_planes() const { return self_planes_; }

 private:
  void build_obstacle_tree();
  // near_ and near_begin_ for `radius` (scene units).
  void find_near(const SceneTopology& cloth, double radius);

  // Obstacles.
  std::vector<std::uint32_t> obstacle_mesh_;  // scene index of each obstacle mesh of topo_
  SceneTopology topo_;                        // of the obstacles alone
  SceneMeasures measures_;                    // of topo_: orientations, buried faces
  std::vector<std::uint32_t> exposed_;        // triangles of topo_ that are not buried
  std::vector<std::uint32_t> exposed_vertices_;  // their convex corners but tips (face planes)
  std::vector<Vec3> vertex_outward_;  // per entry of exposed_vertices_: unit, 0 unknown
  // Per entry of exposed_vertices_: its distance to the cloth when last measured (-INFINITY not
  // yet) and travel_ then; travel_ sums the cloth's largest particle step from call to call.
  std::vector<double> vertex_lower_, vertex_travel_;
  double travel_ = 0.0;
  std::vector<Vec3> last_x_;
  TreeTriangleList obstacle_triangles_;
  std::unique_ptr<TriangleTree> obstacle_tree_;
  std::vector<double> lower_;  // per particle: obstacle distance measured at at_, or INFINITY
  std::vector<Vec3> at_;
  // Cloth meshes of the model (topology meshes), their triangles and trees of this step.
  std::vector<TreeTriangleList> cloth_triangles_;
  std::vector<std::unique_ptr<TriangleTree>> cloth_trees_;
  std::size_t self_planes_ = 0;
  // Self-contact: per particle, the particles within near_radius_ times kSelfApart of it along
  // the cloth's edges at rest (CSR: near_[near_begin_[i] .. near_begin_[i + 1]), itself first),
  // whose triangles give it no plane; stamp_ marks them while particle i is tested (i + 1).
  double near_radius_ = -1.0;
  std::vector<std::uint32_t> near_begin_, near_, stamp_;
};

}  // namespace untangle
