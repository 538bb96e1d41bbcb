"""Binding scenes with soft shadows for comparing two builds of whitted_native: the images,
passes, ray costs and counts of each, saved for np.array_equal, and one scene rendered
once on one thread for callgrind (issue 15's shadow-feeler packets).

    .venv/bin/python scripts/bench_shadow_scenes.py save ADDON_DIR OUT.npz [SCENE ...]
    .venv/bin/python scripts/bench_shadow_scenes.py compare OLD.npz NEW.npz
    valgrind --tool=callgrind .venv/bin/python scripts/bench_shadow_scenes.py one ADDON_DIR SCENE

then `callgrind_annotate --inclusive=yes` gives RenderJob::trace's count (a build with
symbols: -DCMAKE_CXX_FLAGS=-g -DCMAKE_STRIP=/bin/true). `one` renders 160x90 with 2x2
samples, `save` 200x120 with 2x2 samples on 2 threads. The scenes: spheres of five
materials (Phong, mirror, glass, coat, a cut-out) on a checkered floor under
  demo   a sun and a point light (one feeler each);
  area   a square area light with 4x4 samples and a sphere light with 3x3;
  mixed  a soft spot (2x2), a soft sun (3x3), a point light and an elliptic area
         light (2x2);
and the variants below (tinted glass shadows, all film passes, no camera packets with
jittered samples, no feeler pruning); `sun` is bench_builds.py's scene, in colour.
"""

import math
import sys

import numpy as np
from whitted_tools.binding_scenes import sphere
from whitted_tools.native_job import run_job

# name: (lights, Settings overrides)
VARIANTS = {
    "sun": ("sun", {}),
    "demo": ("demo", {}),
    "area": ("area", {}),
    "mixed": ("mixed", {}),
    "area_tinted": ("area", {"glass_shadows": "TINTED"}),
    "mixed_tinted_passes": ("mixed", {"glass_shadows": "TINTED", "passes": True}),
    "demo_nopacket_jitter": ("demo", {"packets": False, "aa_mode": "JITTERED"}),
    "area_noprune": ("area", {"feeler_pruning": False}),
}


def materials(wn):
    return {
        "plain": wn.Material(
            diffuse=(0.6, 0.35, 0.2), specular=(0.04,) * 3, shininess=30.0, ambient=0.0
        ),
        "mirror": wn.Material(
            diffuse=(0.05,) * 3, specular=(0.5,) * 3, shininess=200.0, reflectivity=(0.9,) * 3
        ),
        "glass": wn.Material(
            diffuse=(0.0,) * 3,
            specular=(0.3,) * 3,
            shininess=500.0,
            transmissivity=(0.9, 0.95, 0.9),
            ior=1.5,
            ambient=0.0,
        ),
        "coat": wn.Material(
            diffuse=(0.2, 0.4, 0.7),
            specular=(0.1,) * 3,
            coat_specular=1.0,
            coat_reflectivity=1.0,
            coat_ior=1.5,
            coat_shininess=300.0,
        ),
        "cutout": wn.Material(diffuse=(0.3, 0.7, 0.3), alpha=0.4),
    }


def add_lights(wn, scene, lights):
    Light, T = wn.Light, wn.LightType
    if lights == "sun":
        scene.set_light("sun", Light(type=T.SUN, color=(3.0,) * 3, direction=(-0.3, 0.4, -0.8)))
    elif lights == "demo":
        scene.set_light("sun", Light(type=T.SUN, color=(2.0,) * 3, direction=(0.45, -0.55, -0.7)))
        scene.set_light("point", Light(color=(150.0,) * 3, position=(-2.5, 5.5, 6.0)))
    elif lights == "area":
        area = Light(
            type=T.AREA,
            color=(20.0,) * 3,
            position=(0, 0, 5),
            direction=(0, 0, -1),
            size=(2.0, 2.0),
            axis_u=(1, 0, 0),
            axis_v=(0, 1, 0),
            samples=4,
        )
        scene.set_light("area", area)
        scene.set_light(
            "ball", Light(color=(60.0,) * 3, position=(-3, -3, 4), radius=0.3, samples=3)
        )
    else:
        spot = Light(
            type=T.SPOT,
            color=(200.0,) * 3,
            position=(2, -3, 5),
            direction=(-0.3, 0.5, -1),
            spot_size=0.8,
            spot_blend=0.3,
            radius=0.2,
            samples=2,
        )
        scene.set_light("spot", spot)
        sun = Light(type=T.SUN, color=(1.5,) * 3, direction=(0.3, 0.4, -0.8), angle=0.1, samples=3)
        scene.set_light("sun", sun)
        scene.set_light("point", Light(color=(40.0,) * 3, position=(3, 3, 3)))
        ellipse = Light(
            type=T.AREA,
            color=(10.0,) * 3,
            position=(-2, 2, 4),
            direction=(0.3, -0.3, -1),
            size=(1.0, 1.5),
            axis_u=(1, 0, 0.3),
            axis_v=(0, 1, -0.3),
            shape=wn.AreaShape.ELLIPSE,
            samples=2,
        )
        scene.set_light("ellipse", ellipse)


def build(wn, lights):
    scene = wn.Scene()
    positions, triangles, normals = sphere(0.5)
    scene.set_mesh("ball", positions, triangles, vertex_normals=normals)
    floor = np.array([[-6, -6, 0], [6, -6, 0], [6, 6, 0], [-6, 6, 0]], np.float32)
    uvs = np.array([[[0, 0], [6, 0], [6, 6]], [[0, 0], [6, 6], [0, 6]]], np.float32)
    scene.set_mesh("floor", floor, np.array([[0, 1, 2], [0, 2, 3]], np.uint32), uvs=uvs)
    checker = wn.CheckerTexture(color1=(0.8, 0.05, 0.03), color2=(0.8, 0.65, 0.05), scale=1.0)
    scene.set_texture("check", checker)
    floor_material = wn.Material(diffuse=(0.5,) * 3, ambient=0.2, diffuse_texture="check")
    scene.set_material("floor", floor_material)
    scene.set_instance("floor", "floor", np.eye(4), ["floor"])
    kinds = materials(wn)
    for name, material in kinds.items():
        scene.set_material(name, material)
    names = list(kinds)
    grid = 8 if lights in ("sun", "demo") else 4
    for i in range(grid):
        for j in range(grid):
            to_world = np.eye(4)
            to_world[:3, 3] = (1.1 * (i - (grid - 1) / 2), 1.1 * (j - (grid - 1) / 2), 0.5)
            material = "plain" if lights == "sun" else names[(i + j) % len(names)]
            scene.set_instance(f"ball.{i}.{j}", "ball", to_world, [material])
    add_lights(wn, scene, lights)
    to_world = np.eye(4)
    c, s = math.cos(math.radians(35.0)), math.sin(math.radians(35.0))
    to_world[:3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]  # 35 degrees down at the spheres
    to_world[:3, 3] = (0.0, -9.0, 6.5)
    window = (-0.6, 0.6, -0.3375, 0.3375)
    scene.camera = wn.Camera(to_world=to_world, window=window, clip_end=1e4)
    scene.background = (0.25, 0.45, 0.8)
    scene.ambient = (0.1, 0.1, 0.1)
    return scene


def settings(wn, overrides, width, height, threads):
    values = {"width": width, "height": height, "aa_samples": 2, "threads": threads}
    values["max_depth"] = 6
    if "glass_shadows" in overrides:
        values["glass_shadows"] = getattr(wn.GlassShadows, overrides["glass_shadows"])
    if overrides.get("passes"):
        values["passes"] = [p for p in wn.FILM_PASSES if "crypto" not in p.lower()]
    result = wn.Settings(**values)
    if "aa_mode" in overrides:
        result.aa_mode = getattr(wn.AntiAliasing, overrides["aa_mode"])
    for name in ("packets", "feeler_pruning"):
        if name in overrides:
            setattr(result, name, overrides[name])
    return result


def render(wn, name, width, height, threads):
    """{array name: array} of one variant, and its statistics."""
    lights, overrides = VARIANTS[name]
    chosen = settings(wn, overrides, width, height, threads)
    job = wn.RenderJob(build(wn, lights), chosen)
    run_job(job)
    out = {"image": job.image(), "cost": job.cost_image()}
    for film_pass in chosen.passes:
        out[f"pass_{film_pass}"] = job.pass_image(film_pass)
    stats = job.stats()
    rays = stats["rays"]
    out["rays"] = np.array([rays[k] for k in sorted(rays) if isinstance(rays[k], int)])
    return out, stats


def module(addon_dir):
    sys.path.insert(0, addon_dir)
    import whitted_native

    return whitted_native


def main():
    command, args = sys.argv[1], sys.argv[2:]
    if command == "one":
        out, stats = render(module(args[0]), args[1], 160, 90, 1)
        print(args[1], stats["rays"], float(out["image"][..., :3].mean()))
    elif command == "save":
        wn = module(args[0])
        arrays = {}
        for name in args[2:] or list(VARIANTS):
            out, stats = render(wn, name, 200, 120, 2)
            arrays.update({f"{name}/{key}": value for key, value in out.items()})
            print(name, stats["rays"]["total"], float(out["image"][..., :3].mean()))
        np.savez(args[1], **arrays)
    elif command == "compare":
        old, new = np.load(args[0]), np.load(args[1])
        if sorted(old.files) != sorted(new.files):
            sys.exit("the two files hold different arrays")
        differ = [
            k for k in sorted(old.files) if not np.array_equal(old[k], new[k], equal_nan=True)
        ]
        for key in differ:
            print(f"differs: {key}")
        print(f"{len(old.files)} arrays compared, {len(differ)} differ")
        sys.exit(1 if differ else 0)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
