// Generated test scenes: primitive meshes and the named scenes of the test suite and benchmarks.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "untangle/mesh.h"

namespace untangle::scenes {

// ---- primitives (all return Mesh with role kMovable, path "" and the given name) ----
// Every primitive is welded by construction (no two vertices share a position), consistently
// oriented (closed ones outward) and has one source face per triangle (polygon[t] = t).

// A flat sheet of nu x nv vertices (so (nu-1)*(nv-1)*2 triangles): origin + i/(nu-1)*u +
// j/(nv-1)*v.
Mesh grid_sheet(int nu, int nv, Vec3 origin, Vec3 u, Vec3 v, const std::string& name);
// A closed UV sphere (poles are single vertices): slices around, stacks from pole to pole.
Mesh uv_sphere(Vec3 centre, double radius, int slices, int stacks, const std::string& name);
// An open cylinder along axis z through `centre`: two boundary loops. `rings` (>= 2) rings of
// `slices` vertices, the end rings at z = centre +- length / 2; normals point away from the axis.
Mesh open_tube(Vec3 centre, double radius, double length, int slices, int rings,
               const std::string& name);
// A closed capsule (cylinder with hemispherical caps) along z. `length` is the cylinder's (the caps
// add `radius` at each end), `rings` (>= 2) the cylinder's vertex rings; caps of max(2, slices / 4)
// stacks end in single pole vertices.
Mesh capsule(Vec3 centre, double radius, double length, int slices, int rings,
             const std::string& name);
// A closed mesh of `count` x `count` cone spikes on a square base plate (one closed mesh). The
// plate is `size` x `size`, centred on base_centre, its top at base_centre's z, 0.1 * size thick;
// each spike is a cone of radius 0.45 * size / count and height `height` (tip on a vertex).
Mesh cone_spikes(Vec3 base_centre, double size, int count, double height, const std::string& name);
// A garment-like open mesh with four boundary loops (a "t-shirt" tube: neck, two sleeves, waist):
// a cube's surface of resolution^3 cells (resolution a multiple of 8) projected onto an ellipsoid
// of half-axes 0.9, 0.5, 1.2 times `size`, with the -z face (waist), the middle of the +z face
// (neck) and the middles of the +-x faces (sleeves) removed. Genus 0.
Mesh garment_like(Vec3 centre, double size, int resolution, const std::string& name);

// ---- the cow of Debian's libcgal-demo (empty path when not installed) ----
// Path of cow.off, or "" when the package is absent (tests skip with a visible reason).
std::string cow_path();

// ---- named scenes ----
struct Scene {
  std::string name;             // folder name under testdata/
  std::vector<Mesh> movable;    // positional inputs
  std::vector<Mesh> obstacles;  // --obstacle inputs
};

// A sheet through a closed sphere (one CL/CL contour).
Scene sheet_through_sphere();
// A narrow strip through a sheet (BB/II).
Scene strip_through_sheet();
// Two sheets overlapping at a corner (BI/BI).
Scene sheets_corner();
// A sheet folded through itself (self-intersection).
Scene folded_sheet();
// An open tube with two boundary loops around a closed body that pokes through it; some contours
// join both loops (non-separating tracks).
Scene tube_around_body();
// A garment-like mesh with four loops where a contour joins two loops.
Scene garment_four_loops();
// A sheet lying on cone spikes whose tips poke through (spikes as obstacle).
Scene sheet_on_spikes();
// A square panel of side `side` through the middle of a closed unit sphere (the body), its
// vertices about 0.05 apart. At the default 1.8 it is mostly inside, only its corners outside: the
// case where "small is illegal" picks the wrong side. Inside the body lie about pi / side^2 of a
// panel of side 2 or more, all of it within its boundary (not in named_scenes()).
Scene panel_in_body(double side = 1.8);
// An n x n sheet through the cow (requires cow_path() non-empty). The sheet cuts the cow's body
// across its middle.
Scene sheet_through_cow(int n);
// An n x n horizontal sheet at height y (the cow's up axis; its back is at 0.21 to 0.24 over the
// rump) over the back half of the cow, rump and tail (requires cow_path() non-empty). The cow
// intersects itself where its tail passes through its rump, at heights 0.19 to 0.215: a sheet
// between 0.2 and 0.215 is pressed into the rump around that self-intersection; one lower than
// 0.2 is pierced by the hanging tail. The cow is the obstacle.
Scene sheet_over_cow_rump(double y, int n);

// Every position of `meshes` scaled by `factor` about the centre of their common bounding box.
std::vector<Mesh> scaled_about_centre(std::vector<Mesh> meshes, double factor);

// The garment/body pairs of a MakeHuman-style folder, sorted: every DIR/garments/<prefix>_*.obj
// with its body DIR/bodies/<prefix>_generic.obj. A garment without its body is left out with a
// line in `notes`. Throws Error(kUnreadableInput) when the folders are missing or hold no pair.
std::vector<std::pair<std::string, std::string>> garment_body_pairs(const std::string& dir,
                                                                    std::vector<std::string>& notes);
// The same pairs from two given folders (which may be one: then the bodies are not garments):
// every GARMENTS/<prefix>_*.obj other than a body, with BODIES/<prefix>_generic.obj. Empty when
// there is none; a garment without its body is left out with a line in `notes`.
std::vector<std::pair<std::string, std::string>> garment_body_pairs_in(
    const std::string& garments, const std::string& bodies, std::vector<std::string>& notes);

// An n x n sheet (3 x 3) across the cylinder of a closed capsule (radius 0.6, obstacle): one
// CL/CL contour around a disc of about n^2 / 8 sheet vertices, for timing larger repairs without
// the cow.
Scene sheet_through_capsule(int n);

// A garment sewn to its body (contact, DESIGN §2): the body a closed capsule (radius 0.5,
// cylinder length 2, 24 slices, 9 rings; obstacle), the garment an open band around it whose top
// and bottom rings are the body's rings at z = 0.5 and z = -0.5, bit for bit the same positions
// (48 seam vertices), bulging out to radius 0.58 between them. `dent`: four vertices of the
// garment's middle ring pushed in to radius 0.46, inside the body (penetration away from the
// seams). `repeated`: every face of both meshes repeated with the opposite winding, after all
// the others (double-sided export).
Scene sewn_garment(bool dent, bool repeated);
// The scene's meshes rotated about the x, y and z axes in turn by `angles` (radians), about the
// origin: equal positions stay equal bit for bit.
Scene rotated_scene(Scene scene, Vec3 angles);

// The named scenes above except the cow and sheet_through_capsule, in the order listed (what testdata/ holds).
std::vector<Scene> named_scenes();

// The meshes of a scene as find_intersections takes them: movable first, then the obstacles (with
// role kObstacle), each in order.
std::vector<Mesh> scene_meshes(const Scene& scene);

// Writes a mesh as OBJ (v and f lines, full double precision via %.17g).
void write_obj(const Mesh& mesh, const std::string& path);

// The files of a scene written by write_scene_files, in scene order.
struct SceneFiles {
  std::vector<std::string> movable, obstacles;
};
// Writes every mesh of `scene` under `folder` (created if missing) as movable_<i>.obj and
// obstacle_<i>.obj (the layout of testdata/). Throws Error(kOutputNotWritten).
SceneFiles write_scene_files(const Scene& scene, const std::string& folder);

}  // namespace untangle::scenes
