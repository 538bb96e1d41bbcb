"""What one run of the performance suite measures: the scenes, sizes, curves, repeats
and time limits of the full run and of --quick."""

from dataclasses import dataclass

MAIN_SCENES = ("demo", "million", "instances", "glass8")
ENGINE_NAMES = {"WHITTED": "Whitted", "POVRAY": "POV-Ray", "CYCLES": "Cycles"}
PHASES = ("export", "mesh_bvh", "scene_bvh", "trace", "writeback", "total")
RAY_TYPES = ("camera", "shadow", "reflection", "refraction", "transparent")


@dataclass(frozen=True)
class Plan:
    """What one run of the suite measures, and how long each kind of process may take."""

    sizes: tuple  # ((label, (w, h)), ...): the small size first, the large last
    million: int  # triangles of the "million" scene
    instances: int  # instances of the "instances" scene
    ico_subdivisions: int | None  # of its instanced sphere; None: the scene's default
    triangle_counts: tuple  # the triangle scaling curve, at the small size
    pixel_sizes: tuple  # the pixel scaling curve (the demo)
    depths: tuple  # the depth curve (glass8, small size)
    repeats: int  # Whitted, and the slow engines at the small size
    large_slow_repeats: int  # Cycles and POV-Ray at the large size
    timeouts: dict  # process kind -> seconds; "<engine>_large" for the large size
    budget_minutes: float  # default of --budget-minutes
    slow_scenes: tuple = MAIN_SCENES  # the main scenes POV-Ray and Cycles render
    thread_scenes: tuple = MAIN_SCENES  # the main scenes rendered on 1 thread as well
    # Raw Embree at the small size beyond the main table: these main scenes on one thread,
    # and the scenes of distributed ray tracing (perf_scenes.py) at the quality presets,
    # whose glossy and lens samples multiply the rays.
    embree_thread_scenes: tuple = MAIN_SCENES
    preset_scenes: tuple = ("distributed", "camera")
    presets: tuple = ("PREVIEW", "FINAL")

    @property
    def small(self):
        return self.sizes[0][1]

    @property
    def large(self):
        return self.sizes[-1][1]


def full_plan(repeats):
    return Plan(
        sizes=(("small", (480, 270)), ("1920x1080", (1920, 1080))),
        million=1_000_000,
        instances=10_000,
        ico_subdivisions=None,
        triangle_counts=(1_000, 10_000, 100_000, 1_000_000, 10_000_000),
        pixel_sizes=((240, 135), (480, 270), (960, 540), (1920, 1080)),
        depths=tuple(range(9)),
        repeats=repeats,
        large_slow_repeats=1,
        timeouts={
            "build": 900,
            "WHITTED": 900,
            "NULL": 600,
            "EMBREE": 1800,
            "CYCLES": 600,
            "CYCLES_large": 1500,
            "POVRAY": 150,
            "POVRAY_large": 1200,
        },
        budget_minutes=50.0,
    )


def quick_plan():
    # One tiny size: every kind of process runs, as few times as possible.
    return Plan(
        sizes=(("tiny", (96, 54)),),
        million=20_000,
        instances=100,
        ico_subdivisions=2,
        triangle_counts=(1_000, 10_000),
        pixel_sizes=((64, 36), (96, 54)),
        depths=(0, 4),
        repeats=1,
        large_slow_repeats=1,
        timeouts={"build": 120, "EMBREE": 120, "POVRAY": 30}
        | dict.fromkeys(("WHITTED", "NULL", "CYCLES"), 120),
        budget_minutes=3.0,
        # A smoke test: each kind of process once is enough (POV-Ray alone took 30 s,
        # its time-out, on glass8).
        slow_scenes=("demo",),
        thread_scenes=("demo",),
        embree_thread_scenes=("demo",),
        preset_scenes=("distributed",),
        presets=("PREVIEW",),
    )
