# Blender's cloth on the start meshes of an `untangle simulate --example` scene (issue 19's
# comparison; run by cloth_vs_blender.sh, never in CI):
#
#   blender -b --factory-startup -t 1 --python cloth_blender.py -- \
#       --frames N --out DIR --cloth A.obj [--cloth B.obj ...] [--obstacle C.obj ...] \
#       [--quality 4] [--collision-quality 2] [--time-scale S] [--self-distance D]
#       [--set NAME=VALUE ...] [--collision-set NAME=VALUE ...]
#
# --set and --collision-set change any number of the Cloth modifier's settings
# (bpy.types.ClothSettings, e.g. mass=0.01, tension_stiffness=80) or collision settings
# (bpy.types.ClothCollisionSettings, e.g. distance_min=0.005); the rest are Blender's defaults.
#
# The OBJ files are read by the small parser below, not by Blender's importer, so that the
# vertices keep their file order (the importer may split or reorder them): a mesh is built with
# from_pydata, vertex k of the file is vertex k in Blender. Coordinates: the files are y-up
# (untangle's examples, gravity -9.81 in y); Blender is z-up, so (x, y, z) -> (x, -z, y) on the
# way in and back on the way out. Each --cloth mesh gets a Cloth modifier (collision with
# obstacles and self-collision on), each --obstacle a Collision modifier, and with several cloth
# meshes each cloth also a Collision modifier after its Cloth modifier (how Blender makes cloth
# collide with cloth). Frame 1 is the start;
# frames 2 .. N + 1 are simulated one by one with scene.frame_set, each timed with
# time.perf_counter. The cloth's last frame is written to DIR/<stem>.obj: the input file with its
# `v` lines replaced in order, everything else as it was. DIR/blender_timing.json holds the
# per-frame milliseconds and the settings used.
#
# Blender's cloth counts time in frames, not seconds (the scene's fps does not enter its solver),
# so unless --time-scale is given the script first calibrates the Speed Multiplier (time_scale):
# a small free-falling cloth without air drag for 12 frames at time_scale 1, and then
# time_scale = sqrt(the fall of 12 frames of 1/60 s under 9.81 / the fall it measured), so that
# one frame is 1/60 s as in untangle's examples.

import json
import math
import os
import sys
import time

import bpy


def parse_args(argv):
    args = {"cloth": [], "obstacle": [], "frames": 60, "out": None, "quality": 4,
            "collision_quality": 2, "time_scale": None, "self_distance": None, "set": [],
            "collision_set": []}
    i = 0
    while i < len(argv):
        key = argv[i]
        value = argv[i + 1] if i + 1 < len(argv) else None
        if value is None:
            sys.exit("cloth_blender.py: " + key + " needs a value")
        if key == "--cloth":
            args["cloth"].append(value)
        elif key == "--obstacle":
            args["obstacle"].append(value)
        elif key == "--frames":
            args["frames"] = int(value)
        elif key == "--out":
            args["out"] = value
        elif key == "--quality":
            args["quality"] = int(value)
        elif key == "--collision-quality":
            args["collision_quality"] = int(value)
        elif key == "--time-scale":
            args["time_scale"] = float(value)
        elif key == "--self-distance":
            args["self_distance"] = float(value)
        elif key in ("--set", "--collision-set"):
            if "=" not in value:
                sys.exit("cloth_blender.py: " + key + " takes NAME=VALUE")
            args[key[2:].replace("-", "_")].append(value.split("=", 1))
        else:
            sys.exit("cloth_blender.py: unknown option " + key)
        i += 2
    if not args["cloth"] or args["out"] is None:
        sys.exit("cloth_blender.py: needs --cloth and --out")
    return args


def read_obj(path):
    """Vertices (y-up, file order) and faces (0-based, polygons as written) of an OBJ file."""
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                p = line.split()
                verts.append((float(p[1]), float(p[2]), float(p[3])))
            elif line.startswith("f "):
                face = []
                for token in line.split()[1:]:
                    k = int(token.split("/")[0])
                    face.append(k - 1 if k > 0 else len(verts) + k)
                faces.append(face)
    return verts, faces


def to_blender(p):  # y-up -> z-up
    return (p[0], -p[2], p[1])


def from_blender(p):  # z-up -> y-up
    return (p[0], p[2], -p[1])


def add_object(name, verts, faces):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([to_blender(p) for p in verts], [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def mean_edge(verts, faces):
    total, count = 0.0, 0
    for face in faces:
        for a, b in zip(face, face[1:] + face[:1]):
            total += math.dist(verts[a], verts[b])
            count += 1
    return total / count if count else 0.0


def assign(target, name, text):
    """Sets target.name from text, converted to the type the property already has."""
    if not hasattr(target, name):
        sys.exit("cloth_blender.py: Blender has no setting " + name)
    old = getattr(target, name)
    if isinstance(old, bool):
        value = text.lower() in ("1", "true", "yes", "on")
    else:
        value = type(old)(text)
    setattr(target, name, value)


def add_cloth(obj, frames, quality, collision_quality, time_scale, self_distance, sets=(),
              collision_sets=()):
    mod = obj.modifiers.new("Cloth", "CLOTH")
    s = mod.settings
    s.quality = quality
    s.time_scale = time_scale
    c = mod.collision_settings
    c.use_collision = True
    c.use_self_collision = True
    c.collision_quality = collision_quality
    if self_distance is not None:
        c.self_distance_min = self_distance
    for name, text in sets:
        assign(s, name, text)
    for name, text in collision_sets:
        assign(c, name, text)
    mod.point_cache.frame_start = 1
    mod.point_cache.frame_end = frames + 1
    return mod


def evaluated_positions(obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    world = obj.matrix_world
    out = [from_blender(tuple(world @ v.co)) for v in mesh.vertices]
    evaluated.to_mesh_clear()
    return out


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)


def calibrate(quality):
    """The fall of a free 3 x 3 cloth without air drag over 12 frames at time_scale 1."""
    clear_scene()
    scene = bpy.context.scene
    verts = [(0.1 * i, 0.0, 0.1 * j) for j in range(3) for i in range(3)]
    faces = [[j * 3 + i, j * 3 + i + 1, (j + 1) * 3 + i + 1, (j + 1) * 3 + i]
             for j in range(2) for i in range(2)]
    obj = add_object("calibration", verts, faces)
    mod = add_cloth(obj, 12, quality, 2, 1.0, None)
    mod.settings.air_damping = 0.0
    mod.collision_settings.use_collision = False
    mod.collision_settings.use_self_collision = False
    scene.frame_start, scene.frame_end = 1, 13
    scene.frame_set(1)
    for f in range(2, 14):
        scene.frame_set(f)
    fall = verts[0][1] - evaluated_positions(obj)[0][1]
    clear_scene()
    return fall


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parse_args(argv)
    frames = args["frames"]
    scene = bpy.context.scene
    scene.render.fps = 60
    scene.render.fps_base = 1.0
    scene.use_gravity = True
    scene.gravity = (0.0, 0.0, -9.81)
    time_scale = args["time_scale"]
    calibration = None
    if time_scale is None:
        fall = calibrate(args["quality"])
        target = 0.5 * 9.81 * (12.0 / 60.0) ** 2
        time_scale = math.sqrt(target / fall)
        calibration = {"frames": 12, "fall_at_time_scale_1": fall, "fall_wanted": target}
    clear_scene()
    cloth, edges = [], []
    for path in args["cloth"]:
        verts, faces = read_obj(path)
        edges.append(mean_edge(verts, faces))
        cloth.append((path, add_object(os.path.splitext(os.path.basename(path))[0], verts, faces)))
    for path in args["obstacle"]:
        verts, faces = read_obj(path)
        obj = add_object(os.path.splitext(os.path.basename(path))[0], verts, faces)
        obj.modifiers.new("Collision", "COLLISION")
    # Self-collision distance: Blender's default 0.015, but at most half the cloth's mean edge (a
    # larger distance makes a flat sheet's own neighbours two rings away collide at rest).
    self_distance = args["self_distance"]
    if self_distance is None:
        self_distance = min(0.015, 0.5 * min(edges))
    mods = [add_cloth(obj, frames, args["quality"], args["collision_quality"], time_scale,
                      self_distance, args["set"], args["collision_set"]) for _, obj in cloth]
    # Cloth against cloth: in Blender a cloth collides with another only when that one also
    # carries a Collision modifier (after its Cloth modifier, so that it collides as deformed).
    if len(cloth) > 1:
        for _, obj in cloth:
            obj.modifiers.new("Collision", "COLLISION")
    scene.frame_start, scene.frame_end = 1, frames + 1
    scene.frame_set(1)
    frame_ms = []
    for f in range(2, frames + 2):
        t0 = time.perf_counter()
        scene.frame_set(f)
        frame_ms.append(1000.0 * (time.perf_counter() - t0))
        print("blender frame %d of %d: %.0f ms" % (f - 1, frames, frame_ms[-1]), flush=True)
    os.makedirs(args["out"], exist_ok=True)
    written = []
    for path, obj in cloth:
        positions = evaluated_positions(obj)
        target = os.path.join(args["out"], os.path.basename(path))
        k = 0
        with open(path) as src, open(target, "w") as dst:
            for line in src:
                if line.startswith("v "):
                    p = positions[k]
                    k += 1
                    line = "v %.9g %.9g %.9g\n" % p
                dst.write(line)
        if k != len(positions):
            sys.exit("cloth_blender.py: %s has %d vertices in Blender, %d in the file" %
                     (path, len(positions), k))
        written.append(target)
    m = mods[0]
    settings = {
        "blender": bpy.app.version_string, "frames": frames, "fps": scene.render.fps, "gravity": tuple(scene.gravity),
        "quality": m.settings.quality, "time_scale": m.settings.time_scale,
        "calibration": calibration, "set": args["set"], "collision_set": args["collision_set"],
        "mass": m.settings.mass,
        "tension_stiffness": m.settings.tension_stiffness,
        "compression_stiffness": m.settings.compression_stiffness,
        "shear_stiffness": m.settings.shear_stiffness,
        "bending_stiffness": m.settings.bending_stiffness,
        "bending_model": m.settings.bending_model, "air_damping": m.settings.air_damping,
        "collision_quality": m.collision_settings.collision_quality,
        "distance_min": m.collision_settings.distance_min,
        "self_distance_min": m.collision_settings.self_distance_min,
        "self_friction": m.collision_settings.self_friction,
        "collision_thickness_outer": {o.name: o.collision.thickness_outer
                                      for o in bpy.data.objects if o.modifiers.get("Collision")},
        "collision_cloth_friction": {o.name: o.collision.cloth_friction
                                     for o in bpy.data.objects if o.modifiers.get("Collision")},
        "mean_edge": edges,
    }
    with open(os.path.join(args["out"], "blender_timing.json"), "w") as f:
        json.dump({"settings": settings, "frame_ms": frame_ms, "written": written}, f, indent=1)


main()
