"""Renders frames of an `lsds export-scene` folder with Blender Cycles (docs/export.md).

    blender -b --factory-startup -noaudio --python render_frames.py -- \
        SCENE_DIR OUTPUT_DIR [--frames 0,1,...] [--samples N] [--threads T] [--denoise]
        [--no-truth] [--all-passes]

For each frame NNNNNN of SCENE_DIR/scene.json (or of --frames) it writes
  OUTPUT_DIR/NNNNNN_rgb.exr    one render of N samples, Blender's default pixel filter: a
                               multilayer EXR with Cycles' Combined pass (linear photometric
                               radiance: RGB whose relative luminance is cd/m^2; no exposure) and
                               its Depth (Z) and Object Index (IndexOB) passes, which
                               `lsds generate --renderer cycles` compares with its own layers.
                               Cycles writes those data passes from each pixel's first sample
                               only, and casts that sample through the pixel's centre
                               (integrate_camera_sample), so they are pixel-centre passes at no
                               cost beyond the rgb render. With --no-truth: the Combined pass
                               alone as RGB.
With --all-passes (bench/bench_python: the bytes of a Blender user's data passes) the multilayer
EXR also has the Normal, Position and Vector passes.

Conventions (the frame's JSON, docs/export.md): the world is +Z up, as Blender's; glTF files
are +Y up and Blender's importer turns them back. The camera is OpenCV's (x right, y down,
z forward) and Blender's looks down -Z with +Y up, so world_from_blender_camera =
world_from_cam * diag(1, -1, -1). Intrinsics: horizontal sensor fit, lens = fx * sensor / W,
pixel aspect fx / fy, principal point through shift_x = (W/2 - cx) / W and
shift_y = (cy - H/2) * aspect_y / (W * aspect_x) (Cycles' blender_camera_viewplane).
"""
import json
import math
import os
import sys
import time

import bpy
import numpy
from mathutils import Matrix, Vector

# Blender 3.4's glTF importer uses numpy's aliases np.bool, np.int, ..., which numpy 1.24 (Debian
# 12's) removed: the import fails with "module 'numpy' has no attribute 'bool'". The aliases meant
# the builtins; restoring them changes nothing else.
for _alias, _builtin in (("bool", bool), ("int", int), ("float", float), ("object", object),
                         ("complex", complex)):
    if _alias not in numpy.__dict__:
        setattr(numpy, _alias, _builtin)

SENSOR_WIDTH_MM = 36.0


def parse_args():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(args) < 2:
        sys.exit("usage: blender -b --python render_frames.py -- SCENE_DIR OUTPUT_DIR "
                 "[--frames 0,1] [--samples N] [--threads T] [--denoise] [--no-truth]")
    options = {"scene": args[0], "output": args[1], "frames": None, "samples": 16,
               "threads": 0, "denoise": False, "truth": True, "all_passes": False}
    i = 2
    while i < len(args):
        flag = args[i]
        if flag == "--frames":
            options["frames"] = [int(f) for f in args[i + 1].split(",") if f]
            i += 2
        elif flag == "--samples":
            options["samples"] = int(args[i + 1])
            i += 2
        elif flag == "--threads":
            options["threads"] = int(args[i + 1])
            i += 2
        elif flag == "--denoise":
            options["denoise"] = True
            i += 1
        elif flag == "--no-truth":
            options["truth"] = False
            i += 1
        elif flag == "--all-passes":
            options["all_passes"] = True
            i += 1
        else:
            sys.exit("render_frames.py: unknown argument " + flag)
    return options


def import_gltf(path):
    """Imports a glTF file; returns the objects it added, by node name."""
    before = set(bpy.data.objects)
    bpy.ops.import_scene.gltf(filepath=path)
    added = {}
    for obj in set(bpy.data.objects) - before:
        if obj.type == "MESH":
            added[obj.name.split(".")[0]] = obj
        elif obj.type == "EMPTY":
            bpy.data.objects.remove(obj, do_unlink=True)
    return added


def remove_objects(objects):
    for obj in objects.values():
        mesh = obj.data
        bpy.data.objects.remove(obj, do_unlink=True)
        if mesh is not None and mesh.users == 0:
            bpy.data.meshes.remove(mesh)


def add_fog(material):
    """The reference renderer's fog on a material (the frame's `atmosphere`, docs/export.md): seen
    by a camera ray at distance d, the surface's radiance L becomes
    L * exp(-extinction * d) + fog_radiance * (1 - exp(-extinction * d)), Koschmieder's model,
    as a mix of its BSDF with an emission of the fog's radiance. Lighting rays see the plain BSDF,
    as the reference renderer's shadow and sky rays see no fog. Returns the nodes set per frame
    (set_material_fog)."""
    nodes, links = material.node_tree.nodes, material.node_tree.links
    output = nodes["Material Output"]
    bsdf = output.inputs["Surface"].links[0].from_node
    path = nodes.new("ShaderNodeLightPath")
    optical_depth = nodes.new("ShaderNodeMath")  # -extinction * d
    optical_depth.operation = "MULTIPLY"
    links.new(path.outputs["Ray Length"], optical_depth.inputs[0])
    transmittance = nodes.new("ShaderNodeMath")
    transmittance.operation = "EXPONENT"
    links.new(optical_depth.outputs[0], transmittance.inputs[0])
    fog_share = nodes.new("ShaderNodeMath")  # (1 - transmittance), on camera rays only
    fog_share.operation = "MULTIPLY_ADD"
    links.new(transmittance.outputs[0], fog_share.inputs[0])
    fog_share.inputs[1].default_value = -1.0
    fog_share.inputs[2].default_value = 1.0
    camera_fog = nodes.new("ShaderNodeMath")
    camera_fog.operation = "MULTIPLY"
    links.new(fog_share.outputs[0], camera_fog.inputs[0])
    links.new(path.outputs["Is Camera Ray"], camera_fog.inputs[1])
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    mix = nodes.new("ShaderNodeMixShader")
    links.new(camera_fog.outputs[0], mix.inputs["Fac"])
    links.new(bsdf.outputs[0], mix.inputs[1])
    links.new(emission.outputs[0], mix.inputs[2])
    links.new(mix.outputs[0], output.inputs["Surface"])
    return {"tree": material.node_tree, "bsdf": bsdf, "mix": mix, "output": output,
            "optical_depth": optical_depth, "emission": emission, "foggy": True}


def set_material_fog(fog_nodes, extinction, radiance):
    """Clear air links the BSDF straight to the output: no fog nodes for Cycles to evaluate."""
    fog_nodes["optical_depth"].inputs[1].default_value = -extinction
    fog_nodes["emission"].inputs["Color"].default_value = tuple(radiance) + (1.0,)
    foggy = extinction > 0
    if foggy != fog_nodes["foggy"]:
        source = fog_nodes["mix"] if foggy else fog_nodes["bsdf"]
        fog_nodes["tree"].links.new(source.outputs[0], fog_nodes["output"].inputs["Surface"])
        fog_nodes["foggy"] = foggy


class Nodes:
    """Builds math on a node tree: each function takes sockets or numbers, returns a socket."""

    def __init__(self, tree):
        self.tree = tree

    def new(self, kind):
        return self.tree.nodes.new(kind)

    def feed(self, socket, value):
        if isinstance(value, (int, float)):
            socket.default_value = value
        elif isinstance(value, tuple):
            socket.default_value = value + (1.0,) * (len(socket.default_value) - len(value))
        else:
            self.tree.links.new(value, socket)

    def math(self, operation, a, b=0.0, c=0.0, clamp=False):
        node = self.new("ShaderNodeMath")
        node.operation = operation
        node.use_clamp = clamp
        for socket, value in zip(node.inputs, (a, b, c)):
            self.feed(socket, value)
        return node.outputs[0]

    def mix(self, factor, a, b, blend="MIX"):
        node = self.new("ShaderNodeMixRGB")
        node.blend_type = blend
        self.feed(node.inputs["Fac"], factor)
        self.feed(node.inputs["Color1"], a)
        self.feed(node.inputs["Color2"], b)
        return node.outputs[0]

    def noise(self, position, scale, offset=(0.0, 0.0, 0.0), octaves=1):
        """lsds's Perlin::Noise / Fbm(point * scale + offset, octaves) in about [-1, 1]:
        Blender's Noise Texture is gradient noise of the same kind (Fac = 0.5 + 0.5 * noise)
        and sums octaves as Fbm does (each twice the frequency, half the weight, normalized),
        so its values have the same spread and wavelengths; not the same field."""
        mapping = self.new("ShaderNodeMapping")
        self.feed(mapping.inputs["Vector"], position)
        mapping.inputs["Scale"].default_value = scale if isinstance(scale, tuple) else (scale,) * 3
        mapping.inputs["Location"].default_value = offset
        texture = self.new("ShaderNodeTexNoise")
        texture.noise_dimensions = "3D"
        self.tree.links.new(mapping.outputs[0], texture.inputs["Vector"])
        texture.inputs["Scale"].default_value = 1.0
        texture.inputs["Detail"].default_value = octaves - 1
        texture.inputs["Roughness"].default_value = 0.5
        texture.inputs["Distortion"].default_value = 0.0
        return self.math("MULTIPLY_ADD", texture.outputs["Fac"], 2.0, -1.0)


def pattern_value(nodes, position, pattern):
    """The pattern's noise n of generator/scene/materials.cc (Albedo), per kind."""
    f = pattern["frequency_per_m"]
    kind = pattern["kind"]
    if kind == "speckle":
        grain = nodes.noise(position, f * 8, (31.7, 0.0, 0.0))
        grains = nodes.math("MULTIPLY_ADD", nodes.math("GREATER_THAN", grain, 0.25), 0.9, -0.1)
        return nodes.math("MULTIPLY_ADD", nodes.noise(position, f, octaves=2), 0.6, grains)
    if kind == "strata":
        warp = nodes.noise(position, f * 0.5, octaves=2)
        z = nodes.new("ShaderNodeSeparateXYZ")
        nodes.feed(z.inputs[0], position)
        phase = nodes.math("MULTIPLY_ADD", warp, 2.5, nodes.math("MULTIPLY", z.outputs["Z"], f * 3))
        bands = nodes.math("SINE", nodes.math("MULTIPLY", phase, math.pi))
        fine = nodes.noise(position, f * 4)
        return nodes.math("MULTIPLY_ADD", bands, 0.7, nodes.math("MULTIPLY", fine, 0.4))
    if kind == "brushed":
        return nodes.noise(position, (f * 0.1, f * 4, f * 4), octaves=2)
    return nodes.noise(position, f, octaves=3)  # mottled


def procedural_albedo(nodes, position, spec):
    """The material's albedo as generator/scene/materials.cc (Albedo) makes it: the pattern's
    mix of base and secondary colour, the large patches, and the ground detail's octaves
    (generator/scene/ground_detail.cc, DetailFactor) with their tilt of the normal as a bump.
    Returns the colour socket and the bump's normal socket (None without detail)."""
    colour = tuple(spec["base_color"])
    pattern = spec.get("pattern")
    if pattern is not None:
        n = pattern_value(nodes, position, pattern)
        share = nodes.math("MULTIPLY_ADD", n, 0.8, 0.5, clamp=True)
        share = nodes.math("MULTIPLY", share, pattern["contrast"])
        colour = nodes.mix(share, colour, tuple(pattern["secondary_color"]))
        if pattern["patches"] > 0:
            g = pattern["frequency_per_m"] / 8
            patch = nodes.noise(position, g, (113.1, 71.3, 0.0), octaves=2)
            scale = nodes.math("MULTIPLY_ADD", patch, 1.5 * pattern["patches"], 1.0)
            scale = nodes.math("MINIMUM", nodes.math("MAXIMUM", scale, 0.0), 2.0)
            colour = nodes.mix(1.0, colour, scale, blend="MULTIPLY")
    normal = None
    detail = spec.get("detail")
    if detail is not None:
        total, height, norm, weight = 0.0, 0.0, 0.0, 1.0
        wavelength, octave, octaves = detail["coarsest_m"], 0, []
        while wavelength >= detail["finest_m"] * 0.999:
            octaves.append((wavelength, weight, octave))
            norm += weight
            wavelength *= 0.5
            weight *= detail["persistence"]
            octave += 1
        for wavelength, weight, octave in octaves:
            offset = 37.71 * (octave + 1)
            n = nodes.noise(position, 1.0 / wavelength, (offset, -offset, 0.5 * offset))
            if wavelength < detail["ridged_below_m"]:  # ridges: blades of grass from above
                n = nodes.math("MULTIPLY_ADD", nodes.math("ABSOLUTE", n), -2.0, 0.4)
            total = nodes.math("MULTIPLY_ADD", n, weight, total)
            # A height whose slope tilts the normal by about bump_rad, shared among the octaves.
            height = nodes.math("MULTIPLY_ADD", n,
                                0.5 * detail["bump_rad"] * wavelength * weight / norm, height)
        d = nodes.math("MULTIPLY", total, 2.0 / norm)
        d = nodes.math("MINIMUM", nodes.math("MAXIMUM", d, -1.0), 1.0)
        # factor_c = 1 + contrast * d * (tint_c where d > 0, else 1)
        bright = nodes.math("GREATER_THAN", d, 0.0)
        channels = []
        for tint in detail["tint"]:
            gain = nodes.math("MULTIPLY_ADD", bright, tint - 1.0, 1.0)
            factor = nodes.math("MULTIPLY", nodes.math("MULTIPLY", d, gain), detail["contrast"])
            channels.append(nodes.math("MAXIMUM", nodes.math("ADD", factor, 1.0), 0.0))
        combine = nodes.new("ShaderNodeCombineRGB")
        for socket, value in zip(combine.inputs, channels):
            nodes.feed(socket, value)
        colour = nodes.mix(1.0, colour, combine.outputs[0], blend="MULTIPLY")
        if detail["bump_rad"] > 0:
            bump = nodes.new("ShaderNodeBump")
            bump.inputs["Strength"].default_value = 1.0
            bump.inputs["Distance"].default_value = 1.0
            nodes.feed(bump.inputs["Height"], height)
            normal = bump.outputs["Normal"]
    if not isinstance(colour, tuple):
        clamp = nodes.new("ShaderNodeMixRGB")  # albedo at most 1
        clamp.use_clamp = True
        clamp.blend_type = "MIX"
        clamp.inputs["Fac"].default_value = 0.0
        nodes.feed(clamp.inputs["Color1"], colour)
        colour = clamp.outputs[0]
    return colour, normal


class Materials:
    """One Principled BSDF per distinct material of the frames' JSON (the JSON is authoritative;
    the glTF's own materials are for other importers), seen through the frame's fog."""

    def __init__(self, folder):
        self.folder = folder
        self.made = {}
        self.fog_nodes = []
        self.fog = {"extinction_per_m": 0.0, "fog_radiance": [0.0, 0.0, 0.0]}

    def set_fog(self, atmosphere):
        """The frame's fog (its `atmosphere`; absent in exports before it had fog_radiance)."""
        self.fog = {"extinction_per_m": atmosphere.get("extinction_per_m", 0.0),
                    "fog_radiance": atmosphere.get("fog_radiance", [0.0, 0.0, 0.0])}
        for fog_nodes in self.fog_nodes:
            set_material_fog(fog_nodes, self.fog["extinction_per_m"], self.fog["fog_radiance"])

    def get(self, spec):
        key = json.dumps(spec, sort_keys=True)
        if key not in self.made:
            material = bpy.data.materials.new(spec["name"])
            material.use_nodes = True
            bsdf = material.node_tree.nodes["Principled BSDF"]
            nodes = Nodes(material.node_tree)
            position = nodes.new("ShaderNodeNewGeometry").outputs["Position"]  # world
            if "albedo_map" in spec:
                colour, normal = mapped_albedo(nodes, self.folder, spec["albedo_map"]), None
            else:
                colour, normal = procedural_albedo(nodes, position, spec)
            nodes.feed(bsdf.inputs["Base Color"], colour)
            if normal is not None:
                nodes.feed(bsdf.inputs["Normal"], normal)
            bsdf.inputs["Roughness"].default_value = spec["roughness"]
            bsdf.inputs["Metallic"].default_value = spec["metallic"]
            # Principled's Specular 0.5 is a 4 % reflectance at normal incidence, the reference
            # renderer's dielectric F0 at specular weight 1.
            bsdf.inputs["Specular"].default_value = 0.5 * spec["specular"]
            self.fog_nodes.append(add_fog(material))
            self.set_fog(self.fog)
            self.made[key] = material
        return self.made[key]


def mapped_albedo(nodes, folder, file):
    """A loaded asset's base-colour map (a node's `parts`, docs/export.md) on the mesh's UVs, as
    the reference renderer samples it: bilinear, repeating. PNG maps are 8-bit sRGB, EXR ones
    linear."""
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = load_image(os.path.join(folder, file),
                               "sRGB" if file.lower().endswith(".png") else "Non-Color")
    texture.interpolation = "Linear"
    texture.extension = "REPEAT"
    uv = nodes.new("ShaderNodeUVMap")
    nodes.feed(texture.inputs["Vector"], uv.outputs["UV"])
    return texture.outputs["Color"]


def part_material(material, part):
    """The material of one part of a node (`parts`): the node's BSDF with the part's albedo,
    which replaces the material's own (pattern and detail) as in the reference renderer."""
    if not part:
        return material
    spec = {k: v for k, v in material.items() if k not in ("pattern", "detail")}
    if "albedo" in part:
        spec["base_color"] = part["albedo"]
    else:
        spec["albedo_map"] = part["albedo_map"]
    return spec


def assign(objects, nodes, materials):
    for node in nodes:
        obj = objects.get(node["name"])
        if obj is None:
            continue
        obj.pass_index = node["pass_index"]
        if "parts" in node:
            # Primitive k's glTF material is NAME_partK (Blender may add a ".001" suffix).
            for slot in obj.material_slots:
                k = int(slot.material.name.split(".")[0].rsplit("_part", 1)[1])
                slot.material = materials.get(part_material(node["material"], node["parts"][k]))
        else:
            obj.data.materials.clear()
            obj.data.materials.append(materials.get(node["material"]))
        for polygon in obj.data.polygons:
            polygon.use_smooth = True  # the exported corner normals shade it


def set_camera(camera, spec, scene):
    width, height = spec["width"], spec["height"]
    fx, fy, cx, cy = spec["fx"], spec["fy"], spec["cx"], spec["cy"]
    rotation = Matrix(spec["cam_from_world"]["rotation"])  # cam_from_world, OpenCV camera
    translation = Vector(spec["cam_from_world"]["translation"])
    world_from_cam = rotation.transposed()
    centre = -(world_from_cam @ translation)
    blender_from_opencv = Matrix(((1, 0, 0), (0, -1, 0), (0, 0, -1)))
    world_from_blender = world_from_cam @ blender_from_opencv
    matrix = world_from_blender.to_4x4()
    matrix.translation = centre
    camera.matrix_world = matrix
    data = camera.data
    data.type = "PERSP"
    data.sensor_fit = "HORIZONTAL"
    data.sensor_width = SENSOR_WIDTH_MM
    data.lens = fx * SENSOR_WIDTH_MM / width
    aspect_x, aspect_y = (1.0, fx / fy) if fx >= fy else (fy / fx, 1.0)
    scene.render.pixel_aspect_x = aspect_x
    scene.render.pixel_aspect_y = aspect_y
    data.shift_x = (width / 2 - cx) / width
    data.shift_y = (cy - height / 2) * aspect_y / (width * aspect_x)
    data.clip_start = 0.01
    data.clip_end = 1e8
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100


def set_sun(sun, spec):
    to_sun = Vector(spec["direction_to_sun"]).normalized()
    # A sun light shines down its local -Z: its +Z points at the sun.
    sun.rotation_mode = "QUATERNION"
    sun.rotation_quaternion = Vector((0, 0, 1)).rotation_difference(to_sun)
    irradiance = spec["irradiance"]
    strength = max(irradiance)
    sun.data.energy = strength  # W/m^2 in Blender, here lux: the units carry through
    sun.data.color = [c / strength for c in irradiance] if strength > 0 else (1, 1, 1)
    sun.data.angle = math.radians(spec["angular_diameter_deg"])


def sky_image_colour(tree, folder, spec):
    """The reference renderer's own sky (Perez/Preetham, haze, clouds; no sun disc), from the
    export's equirectangular image: column u = 0.5 + atan2(d_y, d_x) / (2 pi), row
    v = 0.5 + asin(d_z) / pi (v up, as Blender's images are) for the view direction d."""
    nodes = Nodes(tree)
    coords = nodes.new("ShaderNodeTexCoord")
    split = nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(coords.outputs["Generated"], split.inputs[0])
    longitude = nodes.math("ARCTAN2", split.outputs["Y"], split.outputs["X"])
    u = nodes.math("MULTIPLY_ADD", longitude, 1 / (2 * math.pi), 0.5)
    latitude = nodes.math("ARCSINE", nodes.math("MINIMUM", nodes.math("MAXIMUM", split.outputs["Z"], -1.0), 1.0))
    v = nodes.math("MULTIPLY_ADD", latitude, 1 / math.pi, 0.5)
    uv = nodes.new("ShaderNodeCombineXYZ")
    nodes.feed(uv.inputs["X"], u)
    nodes.feed(uv.inputs["Y"], v)
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = load_image(os.path.join(folder, spec["image"]))
    texture.interpolation = "Linear"
    texture.extension = "EXTEND"
    tree.links.new(uv.outputs[0], texture.inputs["Vector"])
    return texture.outputs["Color"]


def load_image(path, colour_space="Non-Color"):
    """An image read as stored (Non-Color: linear float, no colour transform); one load per
    file."""
    image = bpy.data.images.load(path, check_existing=True)
    image.colorspace_settings.name = colour_space
    return image


def set_sky(world, spec, folder):
    """The reference renderer's sky: its image when the export has one, else (exports before
    format 1.1) mix(horizon, zenith, sqrt(z)) above the horizon and a hazy floor below; lighting
    rays see it scaled by the skylight intensity."""
    key = json.dumps(spec, sort_keys=True)
    if world.get("lsds_sky") == key:
        return  # the same sky: no new shader, no new importance map
    world["lsds_sky"] = key
    tree = world.node_tree
    tree.nodes.clear()
    nodes, links = tree.nodes, tree.links
    if "image" in spec:
        sky_colour = sky_image_colour(tree, folder, spec)
        add_background(tree, sky_colour, spec["skylight_intensity"])
        return
    coords = nodes.new("ShaderNodeTexCoord")
    split = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coords.outputs["Generated"], split.inputs[0])
    up = nodes.new("ShaderNodeClamp")
    links.new(split.outputs["Z"], up.inputs["Value"])
    root = nodes.new("ShaderNodeMath")
    root.operation = "SQRT"
    links.new(up.outputs[0], root.inputs[0])
    gradient = nodes.new("ShaderNodeMixRGB")
    links.new(root.outputs[0], gradient.inputs["Fac"])
    gradient.inputs["Color1"].default_value = tuple(spec["horizon_radiance"]) + (1,)
    gradient.inputs["Color2"].default_value = tuple(spec["zenith_radiance"]) + (1,)
    below = nodes.new("ShaderNodeMath")
    below.operation = "LESS_THAN"
    links.new(split.outputs["Z"], below.inputs[0])
    below.inputs[1].default_value = 0.0
    floor = nodes.new("ShaderNodeMixRGB")
    links.new(below.outputs[0], floor.inputs["Fac"])
    links.new(gradient.outputs[0], floor.inputs["Color1"])
    floor.inputs["Color2"].default_value = tuple(spec["below_horizon_radiance"]) + (1,)
    add_background(tree, floor.outputs[0], spec["skylight_intensity"])


def add_background(tree, colour, skylight_intensity):
    """The world's output: `colour` to camera rays, scaled by the skylight intensity for
    lighting rays."""
    nodes, links = tree.nodes, tree.links
    path = nodes.new("ShaderNodeLightPath")
    lighting = nodes.new("ShaderNodeMath")  # skylight intensity, or 1 for camera rays
    lighting.operation = "MULTIPLY_ADD"
    links.new(path.outputs["Is Camera Ray"], lighting.inputs[0])
    lighting.inputs[1].default_value = 1.0 - skylight_intensity
    lighting.inputs[2].default_value = skylight_intensity
    background = nodes.new("ShaderNodeBackground")
    links.new(colour, background.inputs["Color"])
    links.new(lighting.outputs[0], background.inputs["Strength"])
    output = nodes.new("ShaderNodeOutputWorld")
    links.new(background.outputs[0], output.inputs["Surface"])


class CloudDeck:
    """The cloud deck's shadows: a plane at the deck's height that only shadow rays see, letting
    through the share of sunlight the export's image gives (`clouds`, docs/export.md), as the
    reference renderer's Sky::CloudTransmittance dims the sun. Only rays towards the sun's disc
    are dimmed: the sky's light passes, as in the reference renderer, since the sky's image
    already draws the clouds (a shadow ray towards a cloud brings the cloud's radiance)."""

    # Shadow rays towards the sun lamp lie within its 0.265 degree radius; 1 degree keeps them all
    # and the sky's rays (a share of about 1e-4 of the hemisphere) outside.
    SUN_CONE_COS = math.cos(math.radians(1.0))

    def __init__(self):
        self.obj = None
        self.key = None

    def set(self, scene, folder, spec, to_sun):
        key = json.dumps([spec, to_sun], sort_keys=True) if spec else None
        if key == self.key:
            return
        self.key = key
        if self.obj is not None:
            mesh = self.obj.data
            bpy.data.objects.remove(self.obj, do_unlink=True)
            bpy.data.meshes.remove(mesh)
            self.obj = None
        if spec is None:
            return
        (x0, y0), (x1, y1), z = spec["min_xy"], spec["max_xy"], spec["deck_height_m"]
        mesh = bpy.data.meshes.new("cloud_deck")
        mesh.from_pydata([(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)], [],
                         [(0, 1, 2, 3)])
        self.obj = bpy.data.objects.new("cloud_deck", mesh)
        scene.collection.objects.link(self.obj)
        for ray in ("camera", "diffuse", "glossy", "transmission", "volume_scatter"):
            setattr(self.obj, "visible_" + ray, False)
        self.obj.visible_shadow = True
        material = bpy.data.materials.new("cloud_deck")
        material.use_nodes = True
        tree = material.node_tree
        tree.nodes.clear()
        nodes = Nodes(tree)
        coords = nodes.new("ShaderNodeTexCoord")  # Generated: the plane's [0, 1]^2
        texture = nodes.new("ShaderNodeTexImage")
        texture.image = load_image(os.path.join(folder, spec["shadow_image"]))
        texture.interpolation = "Linear"
        texture.extension = "EXTEND"
        tree.links.new(coords.outputs["Generated"], texture.inputs["Vector"])
        # Incoming points back along the ray, down to the shaded point: -to_sun on its sun ray.
        incoming = nodes.new("ShaderNodeNewGeometry").outputs["Incoming"]
        towards_sun = nodes.new("ShaderNodeVectorMath")
        towards_sun.operation = "DOT_PRODUCT"
        nodes.feed(towards_sun.inputs[0], incoming)
        towards_sun.inputs[1].default_value = tuple(-c for c in Vector(to_sun).normalized())
        sun_ray = nodes.math("GREATER_THAN", towards_sun.outputs["Value"], self.SUN_CONE_COS)
        share = nodes.mix(sun_ray, (1.0, 1.0, 1.0), texture.outputs["Color"])
        transparent = nodes.new("ShaderNodeBsdfTransparent")
        nodes.feed(transparent.inputs["Color"], share)
        output = nodes.new("ShaderNodeOutputMaterial")
        tree.links.new(transparent.outputs[0], output.inputs["Surface"])
        mesh.materials.append(material)


def render(scene, path, samples, multilayer):
    """One render written to `path`: the Combined pass as RGB, or with `multilayer` every enabled
    pass in a multilayer EXR."""
    scene.cycles.samples = samples
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR_MULTILAYER" if multilayer else "OPEN_EXR"
    settings.color_mode = "RGBA" if multilayer else "RGB"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    # Written under a temporary name and renamed: a file under its final name is complete (lsds
    # reads each frame while Blender renders the next).
    partial = path[:-len(".exr")] + ".partial.exr"
    scene.render.filepath = partial
    bpy.ops.render.render(write_still=True)
    os.replace(partial, path)


def main():
    options = parse_args()
    if options["denoise"]:
        import _cycles
        if not getattr(_cycles, "with_openimagedenoise", False):
            sys.exit("render_frames.py: --denoise: this Blender was built without "
                     "OpenImageDenoise (Debian's blender 3.4 is); render without denoising")
    folder = options["scene"]
    with open(os.path.join(folder, "scene.json")) as f:
        index = json.load(f)
    frames = options["frames"]
    if frames is None:
        frames = [entry["index"] for entry in index["frames"]]
    os.makedirs(options["output"], exist_ok=True)

    # The factory scene's cube, light and camera go (the glTF importer stays enabled).
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = options["denoise"]
    layer = scene.view_layers[0]
    layer.use_pass_z = options["truth"] or options["all_passes"]
    layer.use_pass_object_index = options["truth"] or options["all_passes"]
    for data_pass in ("use_pass_normal", "use_pass_position", "use_pass_vector"):
        setattr(layer, data_pass, options["all_passes"])
    scene.cycles.seed = 0
    scene.cycles.filter_width = 1.5  # Blender's default pixel filter (Blackman-Harris)
    scene.render.use_motion_blur = False
    # Keep the synchronized scene and its BVH between renders: the next frame (the same ground)
    # changes only what changed.
    scene.render.use_persistent_data = True
    scene.view_settings.view_transform = "Standard"  # EXR is scene-linear either way
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    if options["threads"] > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = options["threads"]
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    # The sky is smooth but for its clouds and the glow around the sun: a 256 x 128 importance map
    # samples it well, and Blender's default (1024 x 512, built whenever the sky changes) would
    # cost more than a small frame's samples.
    world.cycles.sampling_method = "MANUAL"
    world.cycles.sample_map_resolution = 256
    scene.world = world
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    scene.collection.objects.link(sun)

    materials = Materials(folder)
    clouds = CloudDeck()
    ground = {}
    if os.path.exists(os.path.join(folder, "ground.glb")):
        ground = import_gltf(os.path.join(folder, "ground.glb"))
    for frame in frames:
        start = time.time()
        stem = "%06d" % frame
        with open(os.path.join(folder, stem + ".json")) as f:
            spec = json.load(f)
        objects = {}
        objects_file = os.path.join(folder, stem + ".glb")
        if os.path.exists(objects_file):
            objects = import_gltf(objects_file)
        materials.set_fog(spec.get("atmosphere", {}))
        assign(ground, spec["nodes"], materials)
        assign(objects, spec["nodes"], materials)
        set_camera(camera, spec["camera"], scene)
        set_sun(sun, spec["sun"])
        set_sky(world, spec["sky"], folder)
        clouds.set(scene, folder, spec.get("clouds"), spec["sun"]["direction_to_sun"])
        render(scene, os.path.join(options["output"], stem + "_rgb.exr"), options["samples"],
               options["truth"] or options["all_passes"])
        remove_objects(objects)
        print("render_frames: frame %d %.3f s" % (frame, time.time() - start), flush=True)


main()
