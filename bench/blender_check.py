# Blender's side of bench/blender_check.sh (run by `blender -b --factory-startup --python THIS --
# ...`): renders a sphere with Cycles on the CPU in the scene of `matlas render`, or compares two
# renders of each side. Not run in CI.
#
#   render  --out B.exr --env MAP.exr --size N --spp S --seed K (--snippet FIT.py | --diffuse R,G,B)
#   compare --blender B1.exr B2.exr --matlas M1.exr M2.exr [--json OUT.json]
#   blur    --env MAP.exr --out SMOOTH.exr --radius R   (negative texels clamped to 0, as matlas
#           reads maps, then a box blur of 2R texels along each axis, wrapping in longitude;
#           R = 0: the clamp alone)
#
# The scene, in matlas' frame (+y up; render/scene.h, render/environment.h) turned into Blender's
# (+z up) by (x, y, z) -> (x, -z, y), a proper rotation under which the lat-long map needs no
# change: the unit sphere at the origin (a point of a point cloud, which Cycles renders as an exact
# sphere), the camera at (0, 0.35, 4) looking at the origin with a 32 deg vertical field of view,
# the map with nearest-texel lookup (matlas' piecewise-constant map), strength 1, a box pixel
# filter, no clamping, no denoising, no adaptive sampling, the Standard view transform.
import argparse
import json
import math
import sys

import bpy
import numpy as np
from mathutils import Vector


def build_scene(a):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = a.spp
    c.seed = a.seed
    c.use_denoising = False
    c.use_adaptive_sampling = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.resolution_x = scene.render.resolution_y = a.size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"

    world = bpy.data.worlds.new("environment")
    scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    tex = nt.nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(a.env)
    tex.image.colorspace_settings.name = "Linear"
    tex.interpolation = "Closest"
    background = nt.nodes["Background"]
    background.inputs["Strength"].default_value = 1.0
    nt.links.new(tex.outputs["Color"], background.inputs["Color"])

    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.data.sensor_fit = "VERTICAL"
    camera.data.angle_y = math.radians(32.0)
    camera.location = (0.0, -4.0, 0.35)  # matlas (0, 0.35, 4)
    camera.rotation_euler = (Vector((0, 0, 0)) - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera

    # The sphere: one vertex made a point of radius 1 by geometry nodes.
    mesh = bpy.data.meshes.new("sphere")
    mesh.from_pydata([(0.0, 0.0, 0.0)], [], [])
    sphere = bpy.data.objects.new("sphere", mesh)
    scene.collection.objects.link(sphere)
    bpy.context.view_layer.objects.active = sphere
    return scene, sphere


def point_sphere(sphere, material):
    group = bpy.data.node_groups.new("unit sphere", "GeometryNodeTree")
    group.inputs.new("NodeSocketGeometry", "Geometry")
    group.outputs.new("NodeSocketGeometry", "Geometry")
    n_in, n_out = group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")
    to_points = group.nodes.new("GeometryNodeMeshToPoints")
    to_points.inputs["Radius"].default_value = 1.0
    set_material = group.nodes.new("GeometryNodeSetMaterial")
    set_material.inputs["Material"].default_value = material
    group.links.new(n_in.outputs["Geometry"], to_points.inputs["Mesh"])
    group.links.new(to_points.outputs["Points"], set_material.inputs["Geometry"])
    group.links.new(set_material.outputs["Geometry"], n_out.inputs["Geometry"])
    sphere.modifiers.new("unit sphere", "NODES").node_group = group


def render(a):
    scene, sphere = build_scene(a)
    if a.snippet:
        before = set(bpy.data.materials)
        exec(compile(open(a.snippet, encoding="utf-8").read(), a.snippet, "exec"), {"__name__": "__main__"})
        material = next(m for m in bpy.data.materials if m not in before)
        bsdf = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
        print("blender_check: Principled BSDF, distribution", bsdf.distribution)
    else:
        material = bpy.data.materials.new("lambert")
        material.use_nodes = True
        nt = material.node_tree
        for n in list(nt.nodes):
            if n.type != "OUTPUT_MATERIAL":
                nt.nodes.remove(n)
        diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = [float(v) for v in a.diffuse.split(",")] + [1.0]
        diffuse.inputs["Roughness"].default_value = 0.0  # Lambert
        nt.links.new(diffuse.outputs["BSDF"], nt.nodes["Material Output"].inputs["Surface"])
    point_sphere(sphere, material)
    scene.render.filepath = a.out
    bpy.ops.render.render(write_still=True)


def pixels(path):
    """RGB, top row first (Blender stores images bottom row first)."""
    image = bpy.data.images.load(path)
    image.colorspace_settings.name = "Linear"
    w, h = image.size
    buf = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(buf)
    return buf.reshape(h, w, 4)[::-1, :, :3].astype(np.float64)


def sphere_mask(n):
    """Pixels wholly on the sphere: all four corners' rays (render/scene.cpp's camera) hit it."""
    t = math.tan(math.radians(16.0))
    eye = np.array([0.0, 0.35, 4.0])
    f = -eye / np.linalg.norm(eye)
    r = np.cross(f, [0.0, 1.0, 0.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    c = np.arange(n + 1, dtype=np.float64)
    sx, sy = np.meshgrid(2.0 * c / n - 1.0, 1.0 - 2.0 * c / n)
    d = f + r * (sx * t)[..., None] + u * (sy * t)[..., None]
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    b = d @ eye
    hit = b * b - (eye @ eye - 1.0) > 0.0
    return hit[:-1, :-1] & hit[1:, :-1] & hit[:-1, 1:] & hit[1:, 1:]


def compare(a):
    b1, b2 = pixels(a.blender[0]), pixels(a.blender[1])
    m1, m2 = pixels(a.matlas[0]), pixels(a.matlas[1])
    mask = sphere_mask(b1.shape[0])
    n = int(mask.sum())
    B, M = 0.5 * (b1 + b2)[mask], 0.5 * (m1 + m2)[mask]
    # Noise of each side's mean image from its two seeds: var((x1 + x2) / 2) = var(x1 - x2) / 4.
    var_b, var_m = np.var((b1 - b2)[mask], axis=0) / 4.0, np.var((m1 - m2)[mask], axis=0) / 4.0
    mean_m = M.mean(axis=0)
    diff = (B - M).mean(axis=0)
    se = np.sqrt((var_b + var_m) / n)
    rms = np.sqrt(((B - M) ** 2).mean(axis=0))
    noise_rms = np.sqrt(var_b + var_m)
    out = {
        "pixels": n,
        "matlas_mean": mean_m.tolist(), "blender_mean": B.mean(axis=0).tolist(),
        "mean_difference_relative": (diff / mean_m).tolist(),
        "standard_error_relative": (se / mean_m).tolist(),
        "z": (diff / se).tolist(),
        "pixel_rms_relative": (rms / mean_m).tolist(),
        "pixel_noise_rms_relative": (noise_rms / mean_m).tolist(),
    }
    print("blender_check:", json.dumps(out))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=2)


def blur(a):
    image = bpy.data.images.load(a.env)
    image.colorspace_settings.name = "Linear"
    w, h = image.size
    px = np.array(image.pixels[:], dtype=np.float64).reshape(h, w, 4)
    # Negative texels (ringing around a processed map's lights) as matlas reads them: 0. Cycles
    # would render them as negative light.
    print("blender_check: negative texel values clamped to 0:", int((px[:, :, :3] < 0).sum()))
    px[:, :, :3] = np.maximum(px[:, :, :3], 0.0)
    r = a.radius
    for axis, mode in ((1, "wrap"), (0, "edge")) if r > 0 else ():  # longitude wraps, latitude stops at the poles
        pad = [(r, r) if ax == axis else (0, 0) for ax in range(3)]
        c = np.cumsum(np.pad(px, pad, mode=mode), axis=axis)
        n = px.shape[axis]
        px = (np.take(c, np.arange(2 * r, 2 * r + n), axis=axis) - np.take(c, np.arange(n), axis=axis)) / (2 * r)
    px[:, :, 3] = 1.0
    out = bpy.data.images.new("smooth", width=w, height=h, float_buffer=True)
    out.pixels[:] = px.astype(np.float32).ravel()
    # Saved as the linear values themselves: Image.save() would apply the view transform.
    scene = bpy.context.scene
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.view_settings.view_transform = "Raw"
    scene.view_settings.look = "None"
    scene.display_settings.display_device = "None"
    out.save_render(a.out, scene=scene)
    print("blender_check: blurred map mean", float(px[:, :, :3].mean()), "max", float(px[:, :, :3].max()))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="blender_check.py")
    sub = p.add_subparsers(dest="mode", required=True)
    r = sub.add_parser("render")
    r.add_argument("--out", required=True)
    r.add_argument("--env", required=True)
    r.add_argument("--size", type=int, default=192)
    r.add_argument("--spp", type=int, default=128)
    r.add_argument("--seed", type=int, default=1)
    r.add_argument("--snippet")
    r.add_argument("--diffuse")
    c = sub.add_parser("compare")
    c.add_argument("--blender", nargs=2, required=True)
    c.add_argument("--matlas", nargs=2, required=True)
    c.add_argument("--json")
    b = sub.add_parser("blur")
    b.add_argument("--env", required=True)
    b.add_argument("--out", required=True)
    b.add_argument("--radius", type=int, default=4)
    a = p.parse_args(argv)
    if a.mode == "blur":
        blur(a)
    elif a.mode == "render":
        if bool(a.snippet) == bool(a.diffuse):
            p.error("render: give --snippet FIT.py or --diffuse R,G,B")
        render(a)
    else:
        compare(a)


main()
