"""Blender Cycles peer of `lsds generate --demo` for bench_generate (bench/README.md).

Renders a scene of the demo's size and kind with Cycles, the engine BlenderProc
and Kubric drive: a 300 m x 300 m displaced terrain, 24 objects of box, cylinder
and sphere shapes standing on it, a sun and a sky, the demo's camera (70 degree
horizontal field of view, 25 m high, pitched 60 degrees down, flying 2 m along
+y per frame), S samples per pixel, with the truth passes the peers write:
depth (Z), normal, position, object index and vector, into one multilayer EXR
per frame (Blender's default ZIP compression).

    blender -b --factory-startup -noaudio --python bench/peers/cycles_demo.py -- \
        WIDTH HEIGHT FRAMES SPP OUTPUT_DIR [THREADS]
"""
import math
import random
import sys

import bpy


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    width, height, frames, spp = (int(a) for a in args[:4])
    output = args[4]
    threads = int(args[5]) if len(args) > 5 else 0

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    random.seed(0)

    # Terrain: a subdivided plane displaced by noise, about the demo's 3 m relief.
    bpy.ops.mesh.primitive_plane_add(size=300)
    terrain = bpy.context.active_object
    terrain.pass_index = 1000
    sub = terrain.modifiers.new("subdivide", "SUBSURF")
    sub.subdivision_type = "SIMPLE"
    sub.levels = sub.render_levels = 8  # 256 x 256 quads, about the demo terrain's grid
    texture = bpy.data.textures.new("relief", "CLOUDS")
    texture.noise_scale = 25.0
    displace = terrain.modifiers.new("relief", "DISPLACE")
    displace.texture = texture
    displace.strength = 3.0
    grass = bpy.data.materials.new("grass")
    grass.diffuse_color = (0.2, 0.35, 0.1, 1.0)
    terrain.data.materials.append(grass)

    # Objects: the demo's 24, cycling through three shapes.
    adders = [bpy.ops.mesh.primitive_cube_add, bpy.ops.mesh.primitive_cylinder_add,
              bpy.ops.mesh.primitive_uv_sphere_add]
    for i in range(24):
        x = random.uniform(-16, 16)
        y = random.uniform(-16, 6 + 2.0 * frames)
        adders[i % 3](location=(x, y, 0.8))
        obj = bpy.context.active_object
        obj.scale = (random.uniform(0.3, 1.0),) * 3
        obj.rotation_euler[2] = random.uniform(0, 2 * math.pi)
        obj.pass_index = i + 1
        paint = bpy.data.materials.new("paint%d" % i)
        paint.diffuse_color = (random.random(), random.random(), random.random(), 1.0)
        obj.data.materials.append(paint)

    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(45), 0, math.radians(150)))
    bpy.context.active_object.data.energy = 3.0
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs[0].default_value = (0.5, 0.7, 1.0, 1.0)
    scene.world = world

    bpy.ops.object.camera_add()
    camera = bpy.context.active_object
    camera.data.sensor_fit = "HORIZONTAL"
    camera.data.angle = math.radians(70)
    camera.rotation_euler = (math.radians(30), 0, 0)  # 60 degrees below the horizon, facing +y
    scene.camera = camera
    for f in range(frames):
        camera.location = (0, -26 + 2.0 * f, 25)
        camera.keyframe_insert("location", frame=f + 1)

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = spp
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 1
    scene.render.use_motion_blur = False  # the vector pass needs it off
    if threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = threads
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    layer = scene.view_layers[0]
    layer.use_pass_z = True
    layer.use_pass_normal = True
    layer.use_pass_position = True
    layer.use_pass_object_index = True
    layer.use_pass_vector = True
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "ZIP"
    scene.render.filepath = output.rstrip("/") + "/frame_"
    scene.frame_start = 1
    scene.frame_end = frames
    bpy.ops.render.render(animation=True)


main()
