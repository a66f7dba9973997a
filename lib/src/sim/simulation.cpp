// Simulation: per frame, substeps of projective dynamics, each corrected by the repair of
// fix_meshes on the end-of-step positions; velocities follow the corrected positions.
#include <chrono>
#include <cmath>

#include "geometry/vec3.h"
#include "sim/cloth_model.h"
#include "sim/contact_planes.h"
#include "sim/step_detector.h"
#include "resolve/repair_loop.h"
#include "untangle/error.h"
#include "untangle/simulate.h"

namespace untangle {

struct Simulation::State {
  SimulationScene scene;
  ClothModel model;
  std::vector<Vec3> x, v;                        // per particle
  std::vector<std::vector<Vec3>> obstacle_rest;  // per mesh: positions at frame 0 (obstacles)
  // Per mesh: the shape each correction relaxes toward: the cloth's rest shape (its positions at
  // frame 0), an obstacle's positions now.
  std::vector<std::vector<Vec3>> relax_toward;
  std::unique_ptr<StepDetector> detector;        // kept across steps (correct only)
  std::unique_ptr<ContactPlanes> planes;         // ClothOptions::contacts
  ContactSet contacts;                           // this step's
  std::vector<std::uint32_t> touching;           // per particle: the plane it ended on, + 1
  int frame = 0;
  double h = 0.0;
};

namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

void check_options(const ClothOptions& o) {
  auto bad = [](const char* what) {
    throw Error(ExitCode::kUnreadableInput, "", std::string("simulation: ") + what);
  };
  if (!(o.time_step > 0.0) || !std::isfinite(o.time_step)) bad("time_step must be positive");
  if (o.substeps < 1) bad("substeps must be at least 1");
  if (o.solver_iterations < 1) bad("solver_iterations must be at least 1");
  if (!(o.stretch > 0.0) || !std::isfinite(o.stretch)) bad("stretch must be positive");
  if (!(o.bend >= 0.0) || !std::isfinite(o.bend)) bad("bend must be zero or positive");
  if (!(o.damping >= 0.0) || !std::isfinite(o.damping)) bad("damping must be zero or positive");
  if (!(o.density > 0.0) || !std::isfinite(o.density)) bad("density must be positive");
  if (!(o.friction >= 0.0 && o.friction <= 1.0)) bad("friction must be in [0, 1]");
  if (!(o.restitution >= 0.0 && o.restitution <= 1.0)) bad("restitution must be in [0, 1]");
  if (!(o.max_speed > 0.0) || !std::isfinite(o.max_speed)) bad("max_speed must be positive");
  if (!(o.contact_reach > 0.0) || !std::isfinite(o.contact_reach))
    bad("contact_reach must be positive");
  if (!(o.thickness >= 0.0 && o.thickness <= o.contact_reach))
    bad("thickness must be from 0 to contact_reach");
  for (double g : o.gravity)
    if (!std::isfinite(g)) bad("gravity must be finite");
}

// Writes particle positions to every input vertex of the cloth meshes.
void to_meshes(const ClothModel& model, const std::vector<Vec3>& x, std::vector<Mesh>& meshes) {
  for (std::size_t k = 0; k < model.cloth_mesh.size(); ++k) {
    Mesh& mesh = meshes[model.cloth_mesh[k]];
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
      mesh.positions[i] = x[model.topo.welded[k][i]];
  }
}

// Reads particle positions back (every vertex of a welded group holds the same position).
void from_meshes(const ClothModel& model, const std::vector<Mesh>& meshes, std::vector<Vec3>& x) {
  for (std::size_t k = 0; k < model.cloth_mesh.size(); ++k) {
    const Mesh& mesh = meshes[model.cloth_mesh[k]];
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
      x[model.topo.welded[k][i]] = mesh.positions[i];
  }
}

}  // namespace

Simulation::Simulation(SimulationScene scene) : state_(std::make_unique<State>()) {
  State& s = *state_;
  check_options(scene.options);
  s.scene = std::move(scene);
  for (const ObstacleSchedule& schedule : s.scene.schedules)
    if (schedule.mesh >= s.scene.meshes.size() ||
        s.scene.meshes[schedule.mesh].role != Role::kObstacle || schedule.frames < 0)
      throw Error(ExitCode::kUnreadableInput, "", "simulation: a schedule names no obstacle");
  s.h = s.scene.options.time_step / s.scene.options.substeps;
  build_cloth_model(s.scene.meshes, s.scene.pins, s.scene.options, s.model);
  s.x = s.model.topo.points;
  s.v.assign(s.x.size(), Vec3{0.0, 0.0, 0.0});
  s.obstacle_rest.resize(s.scene.meshes.size());
  for (std::size_t m = 0; m < s.scene.meshes.size(); ++m)
    if (s.scene.meshes[m].role == Role::kObstacle) s.obstacle_rest[m] = s.scene.meshes[m].positions;
  for (const Mesh& mesh : s.scene.meshes) s.relax_toward.push_back(mesh.positions);
  if (s.scene.options.contacts)
    s.planes = std::make_unique<ContactPlanes>(s.scene.meshes, s.model, s.scene.options.fix.threads);
  if (s.scene.options.correct)
    s.detector = std::make_unique<StepDetector>(s.scene.meshes, s.scene.options.fix.threads);
}

Simulation::~Simulation() = default;

const std::vector<Mesh>& Simulation::meshes() const { return state_->scene.meshes; }
int Simulation::frame() const { return state_->frame; }

FrameRecord Simulation::advance(const std::function<Vec3(const Vec3&)>& round) {
  State& s = *state_;
  const ClothOptions& o = s.scene.options;
  FrameRecord record;
  record.frame = s.frame + 1;
  const double keep = std::max(0.0, 1.0 - o.damping * s.h);
  for (int step = 0; step < o.substeps; ++step) {
    // Scheduled obstacles at the end of this step.
    const double t = s.frame + static_cast<double>(step + 1) / o.substeps;
    bool obstacles_moved = false;
    for (const ObstacleSchedule& schedule : s.scene.schedules) {
      const double t_before = t - 1.0 / o.substeps;
      if (schedule.frames <= 0 || t_before >= schedule.frames) continue;  // at 1 already
      const double u = std::min(1.0, t / schedule.frames);
      const double factor = schedule.from + (1.0 - schedule.from) * u;
      Mesh& mesh = s.scene.meshes[schedule.mesh];
      const std::vector<Vec3>& rest = s.obstacle_rest[schedule.mesh];
      for (std::size_t i = 0; i < rest.size(); ++i)
        mesh.positions[i] = add(schedule.centre, scale(sub(rest[i], schedule.centre), factor));
      s.relax_toward[schedule.mesh] = mesh.positions;
      obstacles_moved = true;
    }
    const auto t0 = Clock::now();
    const std::vector<Vec3> start = s.x;
    for (Vec3& vel : s.v) vel = scale(vel, keep);
    if (s.planes) {
      if (obstacles_moved) s.planes->update_obstacles(s.scene.meshes);
      const double clearance = o.fix.clearance * s.model.mean_edge;
      s.planes->make(s.model, s.x, clearance + o.contact_reach * s.model.mean_edge, clearance,
                     std::max(clearance, o.thickness * s.model.mean_edge),
                     o.self_contacts, s.contacts);
      record.self_planes += s.planes->self_planes();
    }
    integrate_step(s.model, o, s.h, s.x, s.v, s.contacts, &s.touching);
    if (round)
      for (Vec3& p : s.x) p = round(p);
    to_meshes(s.model, s.x, s.scene.meshes);
    const std::vector<Vec3> predicted = s.x;
    const auto t1 = Clock::now();
    record.integrate_ms += ms(t0, t1);
    if (o.correct) {
      // Detection first, incrementally: the repair runs only where it finds something.
      s.detector->detect(s.scene.meshes, obstacles_moved);
      const auto t2 = Clock::now();
      record.detect_ms += ms(t1, t2);
      const std::size_t found = s.detector->crossings() + s.detector->inside_vertices();
      if (found == 0) {
        record.crossings_after = 0;
        record.corrected = true;
      } else {
        // A step's contact is shallow: neither the layering (garments laid one at a time over a
        // body from the input) nor the continuation (the obstacles shrunk and grown back) is
        // what corrects it, and each would redo the step's whole scene; a piece moved whole
        // would jump, and its velocity with it.
        FixOptions correction = o.fix;
        correction.layering = false;
        correction.continuation = false;
        correction.piece_moves = false;
        const FixResult fixed = fix_meshes_toward(s.scene.meshes, &s.relax_toward, correction,
                                                  s.scene.pins, round, {});
        record.crossings_before += fixed.before.crossings;
        record.crossings_after = fixed.after.crossings;
        record.correction_iterations += fixed.iterations;
        record.corrected = fixed.clean;
        if (!fixed.clean) ++record.uncorrected_steps;
        ++record.corrected_steps;
        from_meshes(s.model, s.scene.meshes, s.x);
      }
      record.correct_ms += ms(t2, Clock::now());
    }
    // Velocities follow the positions. Where the correction moved a particle by d, or where it
    // ended the step on its contact plane, it is in contact: the velocity toward the other
    // surface (against d, or against the plane's normal) is taken out and the tangential part
    // reduced by the friction, rather than d / h turned into velocity, which made the cloth
    // bounce off what it lands on (measured: kinetic energy stayed at a quarter of the impact's).
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      Vec3 vel = scale(sub(predicted[i], start[i]), 1.0 / s.h);
      const Vec3 d = sub(s.x[i], predicted[i]);
      const double length = norm(d);
      const std::uint32_t touching = s.touching.empty() ? 0 : s.touching[i];
      if (length > 0.0 || touching > 0) {
        const std::size_t planes = s.contacts.planes.size();
        const Vec3 n = length > 0.0       ? scale(d, 1.0 / length)
                       : touching <= planes ? s.contacts.planes[touching - 1].normal
                                            : s.contacts.faces[touching - 1 - planes].plane.normal;
        const double toward = dot(vel, n);
        if (toward < 0.0) vel = sub(vel, scale(n, toward));
        const Vec3 tangential = sub(vel, scale(n, dot(vel, n)));
        vel = sub(vel, scale(tangential, o.friction));
        vel = add(vel, scale(d, o.restitution / s.h));
      }
      // A particle never leaves a step faster than max_speed edge lengths per step: the stiff
      // edge terms turn a correction's stretch into velocity, which flung the cloth off the
      // spikes' tips.
      const double speed = norm(vel), cap = o.max_speed * s.model.mean_edge / s.h;
      s.v[i] = speed > cap ? scale(vel, cap / speed) : vel;
    }
  }
  ++s.frame;
  for (std::size_t i = 0; i < s.x.size(); ++i)
    record.kinetic_energy += 0.5 * s.model.mass[i] * dot(s.v[i], s.v[i]);
  for (const ClothModel::Spring& sp : s.model.springs)
    if (sp.stretch)
      record.max_stretch = std::max(record.max_stretch, norm(sub(s.x[sp.a], s.x[sp.b])) / sp.rest);
  return record;
}

}  // namespace untangle
