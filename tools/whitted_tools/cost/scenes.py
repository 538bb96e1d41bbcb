"""Save a scene of the cost report (accuracy-cost) as a .blend (in Blender).

    glass    a 3 x 3 grid of glass spheres and a glass slab over the demo's
             checkerboard, lit by a sphere light (soft shadows): deep refraction
    diffuse  matte boxes and spheres on an image-textured floor under an area
             light and a sun with an angle: soft shadows, textures, no mirrors
    distributed  the diffuse scene lit by an emissive panel and the sun, its balls
             rough gold, rough plastic and frosted glass: glossy rays, emitter feelers
    camera   the diffuse scene through a lens at f/1.4, one ball moving within the
             shutter: depth of field and motion blur (lens and shutter samples)
    volume   a procedural cloud in a cube of fog lit by a spot lamp: a heterogeneous
             medium marched at the volume step rate (whitted_tools.volume_scenes)

    blender -b --factory-startup --python tools/whitted_tools/__main__.py -- cost-scenes \\
        --scene glass --save out/glass.blend

The scenes are whitted_tools.bench_scenes' and volume_scenes'.
"""

import argparse
import os

import bpy

from whitted_tools import bench_scenes, volume_scenes
from whitted_tools.blender import factory_scene
from whitted_tools.verbs import prog

BUILDERS = {
    "glass": bench_scenes.build_glass_scene,
    "diffuse": bench_scenes.build_diffuse_scene,
    "distributed": bench_scenes.build_distributed_scene,
    "camera": bench_scenes.build_camera_scene,
    "volume": lambda scene: volume_scenes.cloud_stage(scene, "SPOT"),
}


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=sorted(BUILDERS), required=True)
    parser.add_argument("--save", required=True, help=".blend file to write")
    args = parser.parse_args(argv)
    scene = BUILDERS[args.scene](factory_scene())
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = 640, 480
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save))
    print(f"cost_scenes: saved {os.path.abspath(args.save)}")
