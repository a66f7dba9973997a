// Roles by name inside one file: glob patterns on mesh, node, object and group names.
#include "untangle/roles_by_name.h"

#include <fnmatch.h>

#include <algorithm>
#include <limits>
#include <set>
#include <sstream>

#include "untangle/error.h"

namespace untangle {
namespace {

constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();

void add_name(const std::string& name, std::vector<std::string>& out) {
  if (!name.empty() && std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
}

bool grouped(const Mesh& mesh) { return !mesh.group_names.empty(); }

bool matches(const std::string& pattern, const std::vector<std::string>& names) {
  for (const std::string& name : names)
    if (::fnmatch(pattern.c_str(), name.c_str(), 0) == 0) return true;
  return false;
}

// The first pattern of `patterns` matching `names`, or null.
const std::string* first_match(const std::vector<std::string>& patterns,
                               const std::vector<std::string>& names) {
  for (const std::string& p : patterns)
    if (matches(p, names)) return &p;
  return nullptr;
}

std::string listed(const std::vector<std::string>& names) {
  if (names.empty()) return "(none: the movable inputs name no mesh, node, object or group)";
  constexpr std::size_t kShown = 20;
  std::string text;
  for (std::size_t k = 0; k < names.size() && k < kShown; ++k) text += (k ? ", " : "") + names[k];
  if (names.size() > kShown) text += ", ... (" + std::to_string(names.size() - kShown) + " more)";
  return text;
}

// The role of one mesh or group, or a usage error when it matches both kinds of pattern.
Role role_of(const std::vector<std::string>& names, const NamePatterns& patterns,
             const std::string& what, std::vector<std::uint8_t>& used_obstacle,
             std::vector<std::uint8_t>& used_movable) {
  for (std::size_t k = 0; k < patterns.obstacle.size(); ++k)
    if (matches(patterns.obstacle[k], names)) used_obstacle[k] = 1;
  for (std::size_t k = 0; k < patterns.movable.size(); ++k)
    if (matches(patterns.movable[k], names)) used_movable[k] = 1;
  const std::string* obstacle = first_match(patterns.obstacle, names);
  const std::string* movable = first_match(patterns.movable, names);
  if (obstacle != nullptr && movable != nullptr) {
    throw Error(ExitCode::kUsage, "",
                what + " matches both --obstacle-name " + *obstacle + " and --movable-name " +
                    *movable + "; give it one role");
  }
  if (obstacle != nullptr) return Role::kObstacle;
  if (movable != nullptr || patterns.movable.empty()) return Role::kMovable;
  return Role::kObstacle;
}

// The part of `source` made of the triangles whose role is `role`, with the vertices they use.
Mesh part_of(const Mesh& source, const std::vector<Role>& triangle_role, Role role,
             std::vector<std::uint32_t>& vertices) {
  Mesh part;
  part.path = source.path;
  part.node_name = source.node_name;
  part.role = role;
  part.source_faces = source.source_faces;
  part.group_names = source.group_names;
  part.group_objects = source.group_objects;
  std::vector<std::uint32_t> index(source.positions.size(), kUnused);
  for (std::size_t t = 0; t < source.triangles.size(); ++t)
    if (triangle_role[t] == role)
      for (std::uint32_t v : source.triangles[t]) index[v] = 0;
  vertices.clear();
  for (std::size_t v = 0; v < index.size(); ++v) {
    if (index[v] == kUnused) continue;
    index[v] = static_cast<std::uint32_t>(vertices.size());
    vertices.push_back(static_cast<std::uint32_t>(v));
    part.positions.push_back(source.positions[v]);
  }
  std::vector<std::string> groups;
  for (std::size_t t = 0; t < source.triangles.size(); ++t) {
    if (triangle_role[t] != role) continue;
    const Triangle& tri = source.triangles[t];
    part.triangles.push_back({index[tri[0]], index[tri[1]], index[tri[2]]});
    part.polygon.push_back(source.polygon[t]);
    part.triangle_group.push_back(source.triangle_group[t]);
    add_name(source.group_names[source.triangle_group[t]], groups);
  }
  // Named after its groups, so that messages and reports tell the two parts apart.
  constexpr std::size_t kNamed = 3;
  for (std::size_t k = 0; k < groups.size() && k < kNamed; ++k)
    part.name += (k ? "," : "") + groups[k];
  if (groups.size() > kNamed) part.name += ",+" + std::to_string(groups.size() - kNamed);
  return part;
}

}  // namespace

std::vector<std::string> names_of(const Mesh& mesh, std::size_t triangle) {
  std::vector<std::string> names;
  if (grouped(mesh)) {
    if (triangle >= mesh.triangle_group.size()) return names;
    const std::string& group = mesh.group_names[mesh.triangle_group[triangle]];
    add_name(group, names);
    std::istringstream words(group);
    std::string word;
    while (words >> word) add_name(word, names);
    // A `g` group inside an object answers to the object's name too.
    const std::uint32_t g = mesh.triangle_group[triangle];
    if (g < mesh.group_objects.size()) add_name(mesh.group_objects[g], names);
    return names;
  }
  add_name(mesh.name, names);
  add_name(mesh.node_name, names);
  return names;
}

std::vector<std::string> all_names(const std::vector<Mesh>& meshes) {
  std::vector<std::string> names;
  for (const Mesh& mesh : meshes) {
    if (!grouped(mesh)) {
      for (const std::string& n : names_of(mesh)) add_name(n, names);
      continue;
    }
    // Each group once, not once per triangle.
    std::vector<std::uint8_t> seen(mesh.group_names.size(), 0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (seen[mesh.triangle_group[t]]) continue;
      seen[mesh.triangle_group[t]] = 1;
      for (const std::string& n : names_of(mesh, t)) add_name(n, names);
    }
  }
  return names;
}

RoleSplit split_by_name(const std::vector<Mesh>& meshes, const PinMask& pins,
                        const NamePatterns& patterns) {
  RoleSplit split;
  std::vector<std::uint8_t> used_obstacle(patterns.obstacle.size(), 0);
  std::vector<std::uint8_t> used_movable(patterns.movable.size(), 0);
  std::vector<Mesh> movable_meshes;
  auto pins_of = [&](std::size_t m) {
    std::vector<std::uint8_t> p = m < pins.size() ? pins[m] : std::vector<std::uint8_t>{};
    p.resize(meshes[m].positions.size(), 0);
    return p;
  };
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = meshes[m];
    if (mesh.role == Role::kMovable) movable_meshes.push_back(mesh);
    if (mesh.role == Role::kObstacle || patterns.empty()) {
      split.meshes.push_back(mesh);
      split.parts.push_back({m, {}});
      split.pins.push_back(pins_of(m));
      continue;
    }
    std::vector<Role> triangle_role(mesh.triangles.size(), Role::kMovable);
    if (grouped(mesh)) {
      // Decided once per group (each group is one `o` or `g` line's names).
      std::vector<int> group_role(mesh.group_names.size(), -1);
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        int& r = group_role[mesh.triangle_group[t]];
        if (r < 0) {
          const std::string name = mesh.group_names[mesh.triangle_group[t]];
          const std::string what = mesh.path + ": " + (name.empty() ? "the faces before the first o or g line" : "group " + name);
          r = static_cast<int>(role_of(names_of(mesh, t), patterns, what, used_obstacle, used_movable));
        }
        triangle_role[t] = static_cast<Role>(r);
      }
    } else {
      const Role r = role_of(names_of(mesh), patterns, mesh_label(mesh, true), used_obstacle,
                             used_movable);
      triangle_role.assign(mesh.triangles.size(), r);
    }
    const bool all_movable = std::all_of(triangle_role.begin(), triangle_role.end(),
                                         [](Role r) { return r == Role::kMovable; });
    const bool all_obstacle = std::all_of(triangle_role.begin(), triangle_role.end(),
                                          [](Role r) { return r == Role::kObstacle; });
    if (all_movable || all_obstacle) {
      split.meshes.push_back(mesh);
      split.meshes.back().role = all_movable ? Role::kMovable : Role::kObstacle;
      split.parts.push_back({m, {}});
      split.pins.push_back(pins_of(m));
      continue;
    }
    const std::vector<std::uint8_t> source_pins = pins_of(m);
    std::vector<std::uint8_t> in_obstacle(mesh.positions.size(), 0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      if (triangle_role[t] == Role::kObstacle)
        for (std::uint32_t v : mesh.triangles[t]) in_obstacle[v] = 1;
    for (Role role : {Role::kMovable, Role::kObstacle}) {
      RolePart part{m, {}};
      split.meshes.push_back(part_of(mesh, triangle_role, role, part.vertices));
      std::vector<std::uint8_t> part_pins(part.vertices.size(), 0);
      for (std::size_t k = 0; k < part.vertices.size(); ++k)
        part_pins[k] = source_pins[part.vertices[k]] || in_obstacle[part.vertices[k]] ? 1 : 0;
      split.pins.push_back(std::move(part_pins));
      split.parts.push_back(std::move(part));
    }
  }
  const std::vector<std::string> present = all_names(movable_meshes);
  for (std::size_t k = 0; k < used_obstacle.size(); ++k)
    if (!used_obstacle[k])
      throw Error(ExitCode::kUsage, "",
                  "--obstacle-name " + patterns.obstacle[k] +
                      " matches no name in the movable inputs; names present: " + listed(present));
  for (std::size_t k = 0; k < used_movable.size(); ++k)
    if (!used_movable[k])
      throw Error(ExitCode::kUsage, "",
                  "--movable-name " + patterns.movable[k] +
                      " matches no name in the movable inputs; names present: " + listed(present));
  return split;
}

std::vector<Mesh> apply_split(const RoleSplit& split, const std::vector<Mesh>& sources) {
  std::size_t expected = 0;
  for (const RolePart& part : split.parts) expected = std::max(expected, part.source + 1);
  if (sources.size() != expected) {
    throw Error(ExitCode::kOutputNotWritten, sources.empty() ? "" : sources.front().path,
                "read back as " + std::to_string(sources.size()) + " meshes instead of " +
                    std::to_string(expected) + "; the roles by name cannot be applied again");
  }
  std::vector<Mesh> out;
  for (std::size_t k = 0; k < split.meshes.size(); ++k) {
    const RolePart& part = split.parts[k];
    const Mesh& source = sources[part.source];
    if (part.vertices.empty()) {
      out.push_back(source);
      out.back().role = split.meshes[k].role;
      continue;
    }
    const Mesh& model = split.meshes[k];
    const std::uint32_t last = part.vertices.back();
    if (last >= source.positions.size()) {
      throw Error(ExitCode::kOutputNotWritten, source.path,
                  "read back with " + std::to_string(source.positions.size()) +
                      " vertices, fewer than the mesh it was written from");
    }
    Mesh mesh = model;
    mesh.path = source.path;
    for (std::size_t v = 0; v < part.vertices.size(); ++v)
      mesh.positions[v] = source.positions[part.vertices[v]];
    out.push_back(std::move(mesh));
  }
  return out;
}

void merge_positions(const RoleSplit& split, std::vector<Mesh>& sources) {
  for (std::size_t k = 0; k < split.meshes.size(); ++k) {
    const RolePart& part = split.parts[k];
    Mesh& source = sources[part.source];
    const Mesh& mesh = split.meshes[k];
    if (part.vertices.empty()) {
      source.positions = mesh.positions;
      continue;
    }
    // The obstacle part's vertices are either its own or pinned in the movable part: both parts
    // hold the same position for a shared vertex.
    for (std::size_t v = 0; v < part.vertices.size(); ++v)
      source.positions[part.vertices[v]] = mesh.positions[v];
  }
}

}  // namespace untangle
