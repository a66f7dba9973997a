// The cloth model of the simulation: particles at the welded vertices of the cloth meshes, lumped
// masses, stretch and bending as rest-length terms, integrated by projective dynamics with one
// sparse Cholesky factorization made at the start (Liu et al. 2013, "Fast simulation of
// mass-spring systems").
#pragma once

#include <Eigen/Sparse>
#include <array>
#include <cstdint>
#include <vector>

#include "topology/scene_topology.h"
#include "untangle/simulate.h"

namespace untangle {

struct ClothModel {
  // A term w/2 |x_a - x_b - p|^2 with p = rest (x_a - x_b) / |x_a - x_b| projected every iteration.
  struct Spring {
    std::uint32_t a, b;  // particles (welded vertices of the cloth topology)
    double rest;
    double weight;  // in units of mass (already divided through by h^2)
    bool stretch;   // an edge (stretch and shear), not a bending pair
  };
  SceneTopology topo;                     // over the cloth meshes only (in scene order)
  std::vector<std::uint32_t> cloth_mesh;  // topology mesh -> scene mesh index
  std::vector<double> mass;               // per particle
  std::vector<std::uint8_t> pinned;       // per particle
  std::vector<std::uint32_t> unknown;     // per particle: index among the free ones, or kNone
  std::vector<Spring> springs;
  double mean_edge = 0.0;  // mean rest length of the stretch springs (the cloth's edges)
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;  // M + sum w A^T A, free particles
  bool factored = false;
};

// Builds the model of the movable meshes of `meshes` (rest shape: their positions now). The weights
// are relative to the inertia of one step, so the step length cancels out of the matrix. Throws
// Error(kUnreadableInput) when the cloth has no triangle or the matrix cannot be factored.
void build_cloth_model(const std::vector<Mesh>& meshes, const PinMask& pins,
                       const ClothOptions& options, ClothModel& model);

// A one-sided contact: the particle stays on the outer side of the plane through `point` with
// unit normal `normal` (ContactPlanes makes them, fresh at every step).
struct ContactPlane {
  Vec3 point{0.0, 0.0, 0.0};
  Vec3 normal{0.0, 0.0, 0.0};
};

// A point of a cloth triangle (corners `corner`, barycentric `weight`) that stays on the outer
// side of a plane: a convex obstacle vertex (a coarse ball's) under the cloth, which no
// particle's own plane sees because it meets the cloth between the particles.
struct FacePlane {
  std::array<std::uint32_t, 3> corner{};
  Vec3 weight{0.0, 0.0, 0.0};
  ContactPlane plane;
};

// The planes of every particle: particle i's are planes[begin[i] .. begin[i + 1]) (begin has one
// entry more than there are particles, or none at all); and the face planes.
struct ContactSet {
  std::vector<std::uint32_t> begin;
  std::vector<ContactPlane> planes;
  std::vector<FacePlane> faces;
};

// One step of `h` seconds: x and v (per particle) in, x the predicted end of the step out (v
// unchanged; the caller sets it from the corrected positions). A particle with contact planes is
// projected back onto each plane's outer side after every global solve, so the stiff edges cannot
// pull it through what it lies on. `touching` (if given) gets, per particle, the index + 1 into
// contacts.planes of the last plane the last iteration projected it onto (0: none): it ends the
// step in contact there (or planes.size() + 1 + k for face plane k).
void integrate_step(const ClothModel& model, const ClothOptions& options, double h,
                    std::vector<Vec3>& x, const std::vector<Vec3>& v,
                    const ContactSet& contacts = {},
                    std::vector<std::uint32_t>* touching = nullptr);

}  // namespace untangle
