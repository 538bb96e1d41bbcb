"""Running the performance suite's measurements: every render a fresh Blender process
(whitted_tools perf-render, whitted_tools perf-raw-embree), scene files and results cached
by configuration, figures the medians of the repeats."""

import time
from dataclasses import dataclass, field
from pathlib import Path

from whitted_tools.blender import (
    addon_env,
    run_for_json,
    run_process,
    verb_in_blender,
    verb_in_bpy,
)
from whitted_tools.pages import size_label
from whitted_tools.perf.plan import MAIN_SCENES, Plan
from whitted_tools.timing import median_or_none, progress


def build_scene(name, path, resolution, timeout, blender="blender", extra=()):
    """Save the suite's scene `name` (whitted_tools perf-scenes) at `resolution` to `path`;
    None, or why it failed."""
    command = verb_in_blender(
        "perf-scenes",
        *("--scene", name, "--resolution", *resolution, "--save", path, *extra),
        blender=blender,
    )
    _, problem = run_process(command, timeout)
    return problem


@dataclass
class Measurement:
    """The JSON of each successful repeat, or why there is none."""

    runs: list = field(default_factory=list)
    missing: str | None = None

    def median(self, getter):
        """Median over the repeats of getter(run); None when no run has the value."""
        return median_or_none(getter(run) for run in self.runs)

    def whitted(self, *keys):
        """Median of run["whitted"][keys[0]][keys[1]]..."""

        def get(run):
            value = run.get("whitted")
            for key in keys:
                value = None if value is None else value.get(key)
            return value

        return self.median(get)


@dataclass
class Suite:
    """Runs the measurements, each once: scene files and results are cached by key."""

    plan: Plan
    blender: str
    python: str
    workdir: Path
    image_dir: Path
    deadline: float  # time.monotonic() after which slow engines and raw Embree are skipped
    before: Path | None = None  # another build of the add-on, for raw Embree's "before" runs
    files: dict = field(default_factory=dict)
    results: dict = field(default_factory=dict)
    problems: list = field(default_factory=list)

    def past_budget(self):
        return time.monotonic() > self.deadline

    def is_large(self, resolution):
        """Whether resolution is the plan's large size (and that differs from the small)."""
        return tuple(resolution) == tuple(self.plan.large) != tuple(self.plan.small)

    def scene_options(self, name, triangles=None):
        options = []
        if name == "million":
            options += ["--triangles", str(self.plan.million)]
        if name == "triangles":
            options += ["--triangles", str(triangles)]
        if name == "instances":
            options += ["--instances", str(self.plan.instances)]
            if self.plan.ico_subdivisions:
                options += ["--ico-subdivisions", str(self.plan.ico_subdivisions)]
        return options

    def scene_file(self, scene, resolution):
        """The .blend of scene ((name, triangles)) saved at resolution, or None."""
        key = (scene, tuple(resolution))
        if key not in self.files:
            name, triangles = scene
            path = self.workdir / f"{name}-{triangles or 0}-{resolution[0]}x{resolution[1]}.blend"
            problem = build_scene(
                name,
                path,
                resolution,
                self.plan.timeouts["build"],
                self.blender,
                self.scene_options(name, triangles),
            )
            if problem:
                self.problems.append(f"building {name} at {size_label(resolution)}: {problem}")
            self.files[key] = None if problem else path
        return self.files[key]

    def render(self, scene, engine, resolution, *, threads=None, depth=None, image=None, bpy=False):
        """perf_render.py's JSON for each repeat of one configuration (a Measurement)."""
        key = (scene, engine, tuple(resolution), threads, depth, bpy)
        if key not in self.results:
            self.results[key] = self.render_rounds(
                scene, engine, resolution, [threads], depth=depth, image=image, bpy=bpy
            )[0]
        return self.results[key]

    def render_alternating(self, scene, engine, resolution, thread_counts):
        """One Measurement per thread count, their repeats run in rounds (one run of each
        count per round), so that run i of each was made side by side with run i of the
        others: ratios between them are taken round by round (figures.speedup)."""
        keys = [(scene, engine, tuple(resolution), n, "alternating") for n in thread_counts]
        if keys[0] not in self.results:
            measured = self.render_rounds(scene, engine, resolution, thread_counts)
            self.results.update(zip(keys, measured, strict=True))
        return [self.results[key] for key in keys]

    def render_rounds(
        self, scene, engine, resolution, thread_counts, *, depth=None, image=None, bpy=False
    ):
        """A Measurement per entry of thread_counts (None: Blender's), run round by round."""
        blend = self.scene_file(scene, self.plan.small)
        large = self.is_large(resolution)
        slow = engine in ("CYCLES", "POVRAY")
        repeats = 1 if engine == "NULL" else self.plan.repeats
        if slow and large:
            repeats = self.plan.large_slow_repeats
        timeout = self.plan.timeouts.get(f"{engine}_large" if large else engine)
        timeout = timeout or self.plan.timeouts[engine]
        measurements = [Measurement() for _ in thread_counts]
        if blend is None:
            for measurement in measurements:
                measurement.missing = "the scene could not be built"
        elif slow and self.past_budget():
            for measurement in measurements:
                measurement.missing = "not run: past the time budget (--budget-minutes)"
            blend = None
        for index in range(repeats if blend else 0):
            for threads, measurement in zip(thread_counts, measurements, strict=True):
                if measurement.missing:
                    continue
                out = self.workdir / f"run-{len(self.results)}-{threads or 0}-{index}.json"
                options = ["--engine", engine, "--json", str(out)]
                options += ["--resolution", *map(str, resolution)]
                if threads:
                    options += ["--threads", str(threads)]
                if depth is not None:
                    options += ["--depth", str(depth)]
                if image and index == 0:
                    options += ["--image", str(image)]
                if bpy:
                    command = verb_in_bpy(
                        "perf-render", "--blend", blend, *options, python=self.python
                    )
                else:
                    command = self.in_blender("perf-render", blend, *options)
                run, problem = run_for_json(command, out, timeout)
                if problem:
                    measurement.missing = problem
                    where = f"{scene[0]} at {size_label(resolution)}"
                    self.problems.append(f"{engine} on {where}: {problem}")
                    continue
                measurement.runs.append(run)
        return measurements

    def in_blender(self, verb, blend, *args):
        """Blender 3.4 with the add-on enabled running the verb on the saved scene."""
        return verb_in_blender(verb, *args, blend=blend, addons=("whitted",), blender=self.blender)

    def raw_embree(self, scene, resolution, before=False, threads=None, preset=None):
        """whitted_tools perf-raw-embree's JSON for the scene at resolution (a Measurement),
        with the add-on in self.before when `before` (Blender finds it through
        BLENDER_USER_SCRIPTS: blender.addon_env), on `threads` (None: all) and at the
        quality preset `preset` (None: the scene's own controls)."""
        kind = "EMBREE_BEFORE" if before else "EMBREE"
        key = (scene, kind, tuple(resolution), threads, preset)
        if key in self.results:
            return self.results[key]
        measurement = Measurement()
        over = self.past_budget()
        blend = None if over else self.scene_file(scene, resolution)
        if over:
            measurement.missing = "not run: past the time budget (--budget-minutes)"
        elif blend is None:
            measurement.missing = "the scene could not be built"
        else:
            out = self.workdir / f"embree-{len(self.results)}.json"
            # Its own repeats: as Whitted's at the small size, fewer at the large.
            large = self.is_large(resolution)
            repeats = self.plan.large_slow_repeats if large else self.plan.repeats
            options = ["--json", out, "--repeats", repeats]
            options += ["--threads", threads] if threads else []
            options += ["--preset", preset] if preset else []
            command = self.in_blender("perf-raw-embree", blend, *options)
            env = addon_env(self.before, self.workdir / "before") if before else None
            run, problem = run_for_json(command, out, self.plan.timeouts["EMBREE"], env=env)
            if problem:
                measurement.missing = problem
                where = f"{scene[0]} at {size_label(resolution)}"
                build = " (before)" if before else ""
                build += f" on {threads} thread(s)" if threads else ""
                build += f" at {preset}" if preset else ""
                self.problems.append(f"raw Embree{build} on {where}: {problem}")
            else:
                measurement.runs.append(run)
        self.results[key] = measurement
        return measurement


@dataclass
class SceneResults:
    """Everything measured on one main scene, by size label."""

    name: str
    whitted: dict = field(default_factory=dict)
    null: dict = field(default_factory=dict)
    cycles: dict = field(default_factory=dict)
    povray: dict = field(default_factory=dict)
    embree: dict = field(default_factory=dict)
    embree_before: dict = field(default_factory=dict)  # with Suite.before's add-on
    bpy: dict = field(default_factory=dict)


def scene_image(suite, name, engine, size):
    """Where the small-size render of a main scene by engine is kept for the page."""
    if tuple(size) != tuple(suite.plan.small):
        return None
    return suite.image_dir / f"perf_scene_{name}_{engine.lower()}.png"


def measure_whitted(suite, name):
    """Whitted (Blender 3.4 and, on the demo, the bpy module), Blender's own memory and
    raw Embree on a main scene at each size."""
    scene = (name, None)
    results = SceneResults(name)
    for label, size in suite.plan.sizes:
        progress(f"{name} at {size_label(size)}: Whitted, null engine, raw Embree")
        image = scene_image(suite, name, "WHITTED", size)
        results.whitted[label] = suite.render(scene, "WHITTED", size, image=image)
        results.null[label] = suite.render(scene, "NULL", size)
        results.embree[label] = suite.raw_embree(scene, size)
        if suite.before:
            results.embree_before[label] = suite.raw_embree(scene, size, before=True)
        if name == "demo":
            results.bpy[label] = suite.render(scene, "WHITTED", size, bpy=True)
    return results


def measure_slow(suite, results, label):
    """POV-Ray and Cycles on a main scene at one size. At the large size, not when the
    small one failed, nor when its time scaled by the pixel count would end the run
    past the time budget."""
    size = dict(suite.plan.sizes)[label]
    small = suite.plan.small
    progress(f"{results.name} at {size_label(size)}: POV-Ray, Cycles")
    for engine, store in (("POVRAY", results.povray), ("CYCLES", results.cycles)):
        first = store.get(suite.plan.sizes[0][0])
        estimate = None
        if first is not None and first.runs:
            seconds = first.median(lambda r: r["seconds"])
            estimate = seconds * (size[0] * size[1]) / (small[0] * small[1])
            estimate *= suite.plan.large_slow_repeats
        if results.name not in suite.plan.slow_scenes:
            store[label] = Measurement(missing="not run: this plan renders it on fewer scenes")
        elif first is not None and first.missing:
            store[label] = Measurement(missing=f"not run: at the small size, {first.missing}")
        elif estimate is not None and estimate > suite.deadline - time.monotonic():
            store[label] = Measurement(
                missing=f"not run: about {estimate:.0f} s (the small size's time scaled by "
                "the pixels) would end past the time budget (--budget-minutes)"
            )
            suite.problems.append(f"{engine} on {results.name} at {size_label(size)}: skipped")
        else:
            image = scene_image(suite, results.name, engine, size)
            store[label] = suite.render((results.name, None), engine, size, image=image)


def measure_scaling(suite):
    """The four curves: {"triangles": [(count, whitted, null)], "pixels": [(w, h, m)],
    "depth": [(d, m)], "threads": {scene: {threads: m}}}."""
    plan = suite.plan
    progress("scaling curves")
    triangles = [
        (
            count,
            suite.render(("triangles", count), "WHITTED", plan.small),
            suite.render(("triangles", count), "NULL", plan.small),
        )
        for count in plan.triangle_counts
    ]
    pixels = [(w, h, suite.render(("demo", None), "WHITTED", (w, h))) for w, h in plan.pixel_sizes]
    depth = [
        (d, suite.render(("glass8", None), "WHITTED", plan.small, depth=d)) for d in plan.depths
    ]
    threads = {}
    for name in MAIN_SCENES:
        if name not in plan.thread_scenes:
            missing = Measurement(missing="not run: this plan measures threads on fewer scenes")
            threads[name] = {1: missing, 2: suite.render((name, None), "WHITTED", plan.small)}
            continue
        # 1 and 2 threads alternating, so that each speed-up is taken between two runs
        # made side by side (the page of 2026-12-02 took the 2-thread runs from the
        # scene's first measurements and the 1-thread ones from minutes later).
        one, two = suite.render_alternating((name, None), "WHITTED", plan.small, (1, 2))
        threads[name] = {1: one, 2: two}
    return {"triangles": triangles, "pixels": pixels, "depth": depth, "threads": threads}


def measure_embree_variants(suite):
    """Raw Embree at the small size beyond the main table: the plan's main scenes on one
    thread, and its scenes of distributed ray tracing at each quality preset (on all
    threads). {"one_thread": {name: Measurement}, "presets": {(name, key): Measurement}}."""
    plan = suite.plan
    progress("raw Embree on one thread, and at the quality presets")
    one_thread = {
        name: suite.raw_embree((name, None), plan.small, threads=1)
        for name in plan.embree_thread_scenes
    }
    presets = {
        (name, key): suite.raw_embree((name, None), plan.small, preset=key)
        for name in plan.preset_scenes
        for key in plan.presets
    }
    return {"one_thread": one_thread, "presets": presets}
