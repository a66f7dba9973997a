// Roles by name inside one file (issue 22 §3): which meshes, or which OBJ objects and groups, of
// a movable input are obstacles, chosen by glob patterns on their names.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "untangle/fix.h"
#include "untangle/mesh.h"

namespace untangle {

// Glob patterns (fnmatch(3) without flags: `*`, `?`, `[...]`, `\` escapes; `/` and a leading `.`
// are ordinary characters) on the names a mesh offers (names_of). Each pattern is repeatable.
//   obstacle: what matches becomes an obstacle;
//   movable:  when given, only what matches stays movable, everything else of the movable inputs
//             becomes an obstacle.
// Both empty: roles stay as read.
struct NamePatterns {
  std::vector<std::string> obstacle;
  std::vector<std::string> movable;
  bool empty() const { return obstacle.empty() && movable.empty(); }
};

// The names a mesh offers to the patterns. OBJ (and anything with named groups): per triangle the
// `o` or `g` line it follows, the whole text after the keyword and each of its words (`g a b`
// offers "a b", "a" and "b"), and the name of the `o` line in effect (`o shirt` then `g sleeve`:
// "sleeve" and "shirt"); the mesh as a whole offers nothing. Other formats: the mesh's own
// name and the name of the node that places it (glTF 2: the mesh's name, or "<name>-<k>" for its
// k-th primitive when it has several, and the node's name; glTF 1.0: the ids instead of the
// names; FBX, Collada, 3DS: the mesh and node names assimp reports). The names of the group of `triangle` for grouped meshes, else of the mesh.
std::vector<std::string> names_of(const Mesh& mesh, std::size_t triangle = 0);

// Every distinct name the meshes offer, in first-seen order (for `untangle info` and errors).
std::vector<std::string> all_names(const std::vector<Mesh>& meshes);

// A mesh of the split scene, and where its vertices come from.
struct RolePart {
  std::size_t source = 0;                // index of the mesh it came from
  std::vector<std::uint32_t> vertices;   // part vertex -> source vertex; empty = the same numbering
};

struct RoleSplit {
  std::vector<Mesh> meshes;    // the meshes with their roles; a mesh whose groups differ in role
                               // is split into its movable and its obstacle triangles
  std::vector<RolePart> parts;  // one per mesh of `meshes`
  PinMask pins;                 // per mesh of `meshes`: the input pins, plus every movable vertex
                                // that an obstacle triangle of the same source mesh also uses
};

// Applies `patterns` to the movable meshes (obstacles stay obstacles). A mesh keeps its numbering
// when all of it takes one role; a grouped mesh whose groups take both roles becomes two meshes
// (movable triangles first, then obstacle triangles, each with only the vertices it uses, in
// source order, named after its groups). Vertices shared by both parts are pinned, so that the
// obstacle part keeps every one of its vertices as read. `pins` is per source mesh (may be empty).
// Throws Error(kUsage) when a pattern matches no name of the movable meshes (the message lists
// the names present), or when a mesh or group matches both an obstacle and a movable pattern.
RoleSplit split_by_name(const std::vector<Mesh>& meshes, const PinMask& pins,
                        const NamePatterns& patterns);

// The split of `split` applied to `sources`, meshes laid out like those passed to split_by_name
// (the written files read back, then the obstacles): each part takes its role, triangles and
// names from the split and its positions from its source. Throws Error(kOutputNotWritten) when
// the layout differs (another number of meshes, or of vertices in a split mesh).
std::vector<Mesh> apply_split(const RoleSplit& split, const std::vector<Mesh>& sources);

// Copies the positions of the split meshes back into their source meshes (`sources` as passed
// to split_by_name, positions possibly changed since).
void merge_positions(const RoleSplit& split, std::vector<Mesh>& sources);

}  // namespace untangle
