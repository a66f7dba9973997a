// Cloth simulation corrected by discrete collision detection after every step (paper §IV): a
// small cloth model integrated by projective dynamics, then the repair of fix_meshes on the
// end-of-step positions instead of continuous collision detection.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "untangle/fix.h"
#include "untangle/mesh.h"

namespace untangle {

// The cloth model and its integrator. Units: positions in scene units, time in seconds. Every
// default lives here.
struct ClothOptions {
  // Acceleration of gravity, scene units per s^2 (the default is metres, y up).
  Vec3 gravity{0.0, -9.81, 0.0};
  double time_step = 1.0 / 60.0;  // seconds per frame
  int substeps = 4;               // integration steps (each corrected) per frame
  int solver_iterations = 10;     // local/global iterations of projective dynamics per step
  // Weight of an edge's rest-length term (stretch and shear) against the inertia of its two ends
  // over one step: dimensionless, so the cloth behaves alike in any unit and at any step.
  // 1,000 makes it nearly inextensible at these iterations.
  double stretch = 1000.0;
  // The same for the bending term: the distance across each interior edge between the two
  // opposite corners, kept at its rest value (isotropic bending for nearly flat cloth and, for a
  // garment, relative to its rest shape as read).
  double bend = 2.0;
  // Fraction of the velocity lost per second (air drag and internal damping together).
  double damping = 0.5;
  // Mass per unit area (kg per scene unit^2); with the dimensionless weights above only the
  // distribution of mass matters, not its scale.
  double density = 1.0;
  // Contact, where the correction moved a particle: the fraction of its tangential velocity lost
  // per step (friction), and the share of the correction's displacement kept as velocity
  // (restitution; 0: the cloth lands without bouncing).
  double friction = 0.3;
  double restitution = 0.0;
  // Contact inside the solve: at the start of every step, a particle within contact_reach mean
  // edge lengths (of the cloth at rest), plus the clearance, of an obstacle or of another cloth
  // mesh gets the tangent plane at its closest point there (an obstacle's moved out by the
  // repair's clearance; between cloth meshes each side may close half the gap beyond the
  // thickness), and a cloth face within that reach of a convex obstacle vertex (not a tip) gets
  // one along the vertex's normal; each is kept on its outer side after every global solve of
  // that step. Planes are made fresh every step, so they follow the cloth as it wraps round; the
  // correction then only has what slips between them (an edge over a spike's tip). Off: every
  // step's push into what the cloth lies on is left to the correction.
  bool contacts = true;
  double contact_reach = 1.0;
  // Two cloth layers in contact (two cloth meshes, or far parts of one with self_contacts) are
  // kept this many mean edge lengths apart by their planes (the repair's clearance if that is
  // more), each side closing half the gap beyond it: the cloth's thickness for contact. At most
  // contact_reach. On the cow, 0.5 in place of the clearance (0.05) left the corrections of the
  // stacked sheets half the crossings (docs/PERFORMANCE.md): a correction that lifts the lower
  // layer by less than the gap no longer pushes it through the one above.
  double thickness = 0.5;
  // Self-contact inside the solve (with `contacts`): a particle within that reach of a triangle
  // of its own mesh that is far from it on the cloth (no corner within 1.5 times the reach of it
  // along the cloth's edges at rest) gets a plane as between two cloth meshes, so a sheet's folds
  // are held apart in the solve instead of being left to the correction. Off by default: on the
  // fitting example (a garment whose collar and cuffs lie in layers at rest, on a growing body)
  // the planes between its layers pumped energy in from frame 31 (crossings left to the
  // corrections 104 -> 2,660 a frame by frame 40, an edge at 3.6 times its length; off: frames 31
  // to 40 at most 107 a frame, edges within 1.07). A sheet folded onto itself is where they help
  // (tests/test_simulate.cpp).
  bool self_contacts = false;
  // Largest distance a particle may travel in one step, in mean edge lengths of the cloth at rest.
  double max_speed = 0.5;
  // Whether the repair corrects every step. Off is for showing what the correction does.
  bool correct = true;
  // The repair run after every step (its clearance keeps the next step out of contact). Its
  // relax_sweeps trades the shape for time: on the spikes 3 sweeps in place of 40 halve a frame in
  // contact (1.0 s to 0.45 s of correction) with edges within 1.5 times their rest length, but on
  // the cow the sheets overstretch two frames earlier (docs/PERFORMANCE.md).
  FixOptions fix;
};

// One obstacle that follows a schedule: its positions scaled about `centre` by a factor that goes
// linearly from `from` at frame 0 to 1 at frame `frames` (and stays 1 after): the continuation of
// a garment fitted onto a body that grows back from a shrunken start.
struct ObstacleSchedule {
  std::size_t mesh = 0;  // index into the scene's meshes (an obstacle)
  Vec3 centre{0.0, 0.0, 0.0};
  double from = 1.0;
  int frames = 0;
};

struct SimulationScene {
  std::vector<Mesh> meshes;  // role kMovable = cloth, kObstacle = never moves (but by schedule)
  PinMask pins;              // per mesh, per input vertex: 1 = pinned (never moves)
  std::vector<ObstacleSchedule> schedules;
  ClothOptions options;
};

// What one frame did.
struct FrameRecord {
  int frame = 0;
  std::size_t crossings_before = 0;  // after integration, before the correction (summed over steps)
  std::size_t crossings_after = 0;   // left after the last step's correction
  int correction_iterations = 0;     // summed over the frame's steps
  int corrected_steps = 0;           // steps that found something and ran the repair
  bool corrected = true;             // the frame's last correction ended clean
  int uncorrected_steps = 0;         // steps of the frame whose correction did not end clean
  double kinetic_energy = 0.0;       // (1/2) sum m v^2 at the end of the frame
  double max_stretch = 0.0;          // largest edge length over its rest length
  // Self-contact planes made for the frame's steps (summed; ClothOptions::self_contacts).
  std::size_t self_planes = 0;
  // Time in the integrator, in the detection after each step (incremental: every step), and in
  // the repair (only the steps where the detection found something).
  double integrate_ms = 0.0, detect_ms = 0.0, correct_ms = 0.0;
};

// A running simulation. Deterministic: the same scene gives the same positions at any thread
// count. Never prints.
class Simulation {
 public:
  // Throws Error(kUnreadableInput) for a scene without cloth or with a bad parameter.
  explicit Simulation(SimulationScene scene);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Advances one frame (ClothOptions::substeps corrected steps). `round` (optional) maps positions
  // to what the output stores; the correction judges rounded positions.
  FrameRecord advance(const std::function<Vec3(const Vec3&)>& round = {});
  // The meshes at the current positions (cloth moved, obstacles as scheduled).
  const std::vector<Mesh>& meshes() const;
  int frame() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace untangle
