"""Issue 7's performance suite: measure Whitted against raw Embree, POV-Ray and Cycles,
and write docs/PERFORMANCE.md with its plots (docs/images/perf_*.png).

    .venv/bin/python scripts/bench_performance.py [--quick] [--repeats 3] \\
        [--out docs/PERFORMANCE.md] [--notes NOTES.md ...] [--blender blender]

Scenes (scripts/perf_scenes.py): the demo; about a million triangles of glass and
mirrors; 10,000 geometry-nodes instances; a glass-heavy scene at depth 8; each at a
small size and at 1920x1080. Every measurement is a fresh Blender process
(scripts/perf_render.py, scripts/perf_raw_embree.py, POV-Ray through
scripts/perf_povray.py); figures are medians of the repeats. Whitted runs --repeats
times everywhere; Cycles and POV-Ray run --repeats times at the small size and once
at 1920x1080, and are not run at 1920x1080 on a scene whose small run failed or timed
out. Then the scaling curves: time against triangle count (1k..10M, a fixed small
size), against pixel count (the demo), against depth (0..8 on the glass scene), and 1
against 2 threads. A target table says pass or miss, and by how much.

--quick runs tiny sizes, small scenes and few points, once each (a smoke test of the
whole pipeline in a minute or two); give it an --out outside docs/. --notes inserts
Markdown files (the profiling explanation of the misses) in the page's notes section.
"""

import argparse
import json
import os
import shlex
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import machine_lines, run_process

REPO = Path(__file__).resolve().parents[1]
SCRIPTS = REPO / "scripts"
MAIN_SCENES = ("demo", "million", "instances", "glass8")
ENGINE_NAMES = {"WHITTED": "Whitted", "POVRAY": "POV-Ray", "CYCLES": "Cycles"}
PHASES = ("export", "mesh_bvh", "scene_bvh", "trace", "writeback", "total")
RAY_TYPES = ("camera", "shadow", "reflection", "refraction", "transparent")
HD_PIXELS = 1920 * 1080
MIB = 1024.0 * 1024.0


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
        budget_minutes=40.0,
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
    )


@dataclass
class Measurement:
    """The JSON of each successful repeat, or why there is none."""

    runs: list = field(default_factory=list)
    missing: str | None = None

    def median(self, getter):
        """Median over the repeats of getter(run); None when no run has the value."""
        values = []
        for run in self.runs:
            value = getter(run)
            if value is not None:
                values.append(value)
        return statistics.median(values) if values else None

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
            command = [
                *(self.blender, "-b", "--factory-startup", "--python-exit-code", "1"),
                *("--python", str(SCRIPTS / "perf_scenes.py"), "--", "--scene", name),
                *("--resolution", *map(str, resolution), "--save", str(path)),
                *self.scene_options(name, triangles),
            ]
            _, problem = run_process(command, self.plan.timeouts["build"])
            if problem:
                self.problems.append(f"building {name} at {size_label(resolution)}: {problem}")
            self.files[key] = None if problem else path
        return self.files[key]

    def render(self, scene, engine, resolution, *, threads=None, depth=None, image=None, bpy=False):
        """perf_render.py's JSON for each repeat of one configuration (a Measurement)."""
        key = (scene, engine, tuple(resolution), threads, depth, bpy)
        if key in self.results:
            return self.results[key]
        blend = self.scene_file(scene, self.plan.small)
        large = self.is_large(resolution)
        slow = engine in ("CYCLES", "POVRAY")
        repeats = 1 if engine == "NULL" else self.plan.repeats
        if slow and large:
            repeats = self.plan.large_slow_repeats
        timeout = self.plan.timeouts.get(f"{engine}_large" if large else engine)
        timeout = timeout or self.plan.timeouts[engine]
        measurement = Measurement()
        if blend is None:
            measurement.missing = "the scene could not be built"
        elif slow and self.past_budget():
            measurement.missing = "not run: past the time budget (--budget-minutes)"
            blend = None
        for index in range(repeats if blend else 0):
            out = self.workdir / f"run-{len(self.results)}-{index}.json"
            options = ["--engine", engine, "--json", str(out)]
            options += ["--resolution", *map(str, resolution)]
            if threads:
                options += ["--threads", str(threads)]
            if depth is not None:
                options += ["--depth", str(depth)]
            if image and index == 0:
                options += ["--image", str(image)]
            if bpy:
                command = [self.python, str(SCRIPTS / "perf_render.py"), "--blend", str(blend)]
                command += options
            else:
                command = [*self.blender_prefix(blend), str(SCRIPTS / "perf_render.py"), "--"]
                command += options
            _, problem = run_process(command, timeout)
            if problem:
                measurement.missing = problem
                where = f"{scene[0]} at {size_label(resolution)}"
                self.problems.append(f"{engine} on {where}: {problem}")
                break
            run = json.loads(out.read_text())
            if engine == "POVRAY" and not run["povray"].get("available", True):
                measurement.missing = f"not available ({run['povray'].get('reason')})"
                break
            measurement.runs.append(run)
        self.results[key] = measurement
        return measurement

    def blender_prefix(self, blend):
        return [
            *(self.blender, "-b", "--factory-startup", "--addons", "whitted", str(blend)),
            *("--python-exit-code", "1", "--python"),
        ]

    def raw_embree(self, scene, resolution):
        """scripts/perf_raw_embree.py's JSON for the scene at resolution (a Measurement)."""
        key = (scene, "EMBREE", tuple(resolution))
        if key in self.results:
            return self.results[key]
        measurement = Measurement()
        script = SCRIPTS / "perf_raw_embree.py"
        over = self.past_budget()
        blend = self.scene_file(scene, resolution) if script.exists() and not over else None
        if not script.exists():
            measurement.missing = "not available (no scripts/perf_raw_embree.py)"
        elif over:
            measurement.missing = "not run: past the time budget (--budget-minutes)"
        elif blend is None:
            measurement.missing = "the scene could not be built"
        else:
            out = self.workdir / f"embree-{len(self.results)}.json"
            command = [*self.blender_prefix(blend), str(script), "--", "--json", str(out)]
            if "--repeats" in script.read_text(encoding="utf-8"):
                # Its own repeats: as Whitted's at the small size, fewer at the large.
                large = self.is_large(resolution)
                repeats = self.plan.large_slow_repeats if large else self.plan.repeats
                command += ["--repeats", str(repeats)]
            _, problem = run_process(command, self.plan.timeouts["EMBREE"])
            if problem:
                measurement.missing = problem
                where = f"{scene[0]} at {size_label(resolution)}"
                self.problems.append(f"raw Embree on {where}: {problem}")
            else:
                measurement.runs.append(json.loads(out.read_text()))
        self.results[key] = measurement
        return measurement


# --- Measuring -------------------------------------------------------------------


@dataclass
class SceneResults:
    """Everything measured on one main scene, by size label."""

    name: str
    whitted: dict = field(default_factory=dict)
    null: dict = field(default_factory=dict)
    cycles: dict = field(default_factory=dict)
    povray: dict = field(default_factory=dict)
    embree: dict = field(default_factory=dict)
    bpy: dict = field(default_factory=dict)


def _progress(text):
    print(f"[{time.strftime('%H:%M:%S')}] {text}", flush=True)


def _scene_image(suite, name, engine, size):
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
        _progress(f"{name} at {size_label(size)}: Whitted, null engine, raw Embree")
        image = _scene_image(suite, name, "WHITTED", size)
        results.whitted[label] = suite.render(scene, "WHITTED", size, image=image)
        results.null[label] = suite.render(scene, "NULL", size)
        results.embree[label] = suite.raw_embree(scene, size)
        if name == "demo":
            results.bpy[label] = suite.render(scene, "WHITTED", size, bpy=True)
    return results


def measure_slow(suite, results, label):
    """POV-Ray and Cycles on a main scene at one size. At the large size, not when the
    small one failed, nor when its time scaled by the pixel count would end the run
    past the time budget."""
    size = dict(suite.plan.sizes)[label]
    small = suite.plan.small
    _progress(f"{results.name} at {size_label(size)}: POV-Ray, Cycles")
    for engine, store in (("POVRAY", results.povray), ("CYCLES", results.cycles)):
        first = store.get(suite.plan.sizes[0][0])
        estimate = None
        if first is not None and first.runs:
            seconds = first.median(lambda r: r["seconds"])
            estimate = seconds * (size[0] * size[1]) / (small[0] * small[1])
            estimate *= suite.plan.large_slow_repeats
        if first is not None and first.missing:
            store[label] = Measurement(missing=f"not run: at the small size, {first.missing}")
        elif estimate is not None and estimate > suite.deadline - time.monotonic():
            store[label] = Measurement(
                missing=f"not run: about {estimate:.0f} s (the small size's time scaled by "
                "the pixels) would end past the time budget (--budget-minutes)"
            )
            suite.problems.append(f"{engine} on {results.name} at {size_label(size)}: skipped")
        else:
            image = _scene_image(suite, results.name, engine, size)
            store[label] = suite.render((results.name, None), engine, size, image=image)


def measure_scaling(suite):
    """The four curves: {"triangles": [(count, whitted, null)], "pixels": [(w, h, m)],
    "depth": [(d, m)], "threads": {scene: {threads: m}}}."""
    plan = suite.plan
    _progress("scaling curves")
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
        default = suite.render((name, None), "WHITTED", plan.small)
        # Blender's default on a 2-processor machine is 2 threads: that run serves.
        two = default
        if default.median(lambda r: r["threads"]) != 2:
            two = suite.render((name, None), "WHITTED", plan.small, threads=2)
        threads[name] = {1: suite.render((name, None), "WHITTED", plan.small, threads=1), 2: two}
    return {"triangles": triangles, "pixels": pixels, "depth": depth, "threads": threads}


# --- Derived figures ---------------------------------------------------------------


def beyond_blender_mib(whitted, null):
    """Whitted's peak RSS less Blender's own (the NULL engine's) for the same file, MiB."""
    ours, own = (
        whitted.median(lambda r: r["peak_rss_mib"]),
        null.median(lambda r: r["peak_rss_mib"]),
    )
    return None if ours is None or own is None else ours - own


def bytes_per_triangle(whitted, null, triangles):
    beyond = beyond_blender_mib(whitted, null)
    return None if beyond is None or not triangles else beyond * MIB / triangles


def mesh_triangles(measurement):
    return measurement.median(lambda r: r.get("mesh_triangles"))


def bvh_seconds(measurement):
    return measurement.median(
        lambda r: r["whitted"]["phases"]["mesh_bvh"] + r["whitted"]["phases"]["scene_bvh"]
    )


def export_per_million(measurement):
    triangles = mesh_triangles(measurement)
    export = measurement.whitted("phases", "export")
    return None if export is None or not triangles else export / (triangles / 1e6)


def writeback_per_hd_pass(measurement):
    """Write-back seconds per render pass written (the engine writes Combined and its
    ray-count pass), scaled to 1920x1080 (exact at that size)."""
    writeback = measurement.whitted("phases", "writeback")
    passes = measurement.runs[0].get("whitted", {}).get("passes") if measurement.runs else None
    pixels = measurement.median(lambda r: r["width"] * r["height"])
    if writeback is None or not pixels or not passes:
        return None
    return writeback / len(passes) * HD_PIXELS / pixels


def speedup(scaling, name, getter):
    one, two = (getter(scaling["threads"][name][n]) for n in (1, 2))
    return None if one is None or not two else one / two


def ratio(numerator, denominator):
    return None if numerator is None or not denominator else numerator / denominator


# --- Formatting --------------------------------------------------------------------


def num(value, digits=3, suffix=""):
    """A number for a table, '—' when missing."""
    if value is None:
        return "—"
    return f"{value:.{digits}f}{suffix}"


def seconds_text(value):
    if value is None:
        return "—"
    return f"{value:.3f}" if value < 10 else f"{value:.1f}"


def ratio_text(value):
    return "—" if value is None else f"{value:.2f}x"


def cell(measurement, value):
    """value as text, or why it is missing."""
    if value is not None:
        return value
    return measurement.missing or "—"


def size_label(size):
    return f"{size[0]}x{size[1]}"


def repeats_note(measurement):
    return f"{len(measurement.runs)}" if measurement.runs else "0"


# --- Plots -------------------------------------------------------------------------


def _save(figure, path):
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    plt.close(figure)


def _plot_series(axis, xs, ys, positive=False, **style):
    """Plot the (x, y) pairs whose y is known (and above 0 when positive: log axes)."""
    points = [(x, y) for x, y in zip(xs, ys, strict=True) if y is not None]
    points = [(x, y) for x, y in points if y > 0.0 or not positive]
    if points:
        axis.plot(*zip(*points, strict=True), **style)


def _dress(axis, title, xlabel, ylabel, log=True):
    """Title, axis labels, log scales (when log) and the legend of one plot."""
    if log:
        axis.set_xscale("log")
        axis.set_yscale("log")
    axis.set_xlabel(xlabel)
    axis.set_ylabel(ylabel)
    axis.set_title(title)
    axis.legend(fontsize=8)


def plot_triangles(rows, path):
    figure, (times, memory) = plt.subplots(1, 2, figsize=(12, 4.5))
    counts = [mesh_triangles(w) or n for n, w, _ in rows]
    series = {
        "export": lambda m: m.whitted("phases", "export"),
        "BVH build": bvh_seconds,
        "trace": lambda m: m.whitted("phases", "trace"),
        "engine total": lambda m: m.whitted("phases", "total"),
        "end to end in Blender": lambda m: m.median(lambda r: r["seconds"]),
    }
    for label, getter in series.items():
        values = [getter(whitted) for _, whitted, _ in rows]
        _plot_series(times, counts, values, positive=True, marker="o", label=label)
    _dress(times, "Time against triangle count", "triangles", "seconds (median)")
    # A difference within ru_maxrss's noise can be negative: not on a log axis.
    values = [bytes_per_triangle(w, null, c) for c, (_, w, null) in zip(counts, rows, strict=True)]
    _plot_series(memory, counts, values, positive=True, marker="o", color="tab:purple")
    memory.axhline(200.0, color="red", linestyle="--", label="target: 200 bytes/triangle")
    _dress(
        memory,
        "Memory per triangle",
        "triangles",
        "peak memory beyond Blender's own, bytes per triangle",
    )
    _save(figure, path)


def plot_pixels(rows, path):
    figure, axis = plt.subplots(figsize=(7, 4.5))
    pixels = [w * h for w, h, _ in rows]
    for label, getter in (
        ("trace", lambda m: m.whitted("phases", "trace")),
        ("write-back", lambda m: m.whitted("phases", "writeback")),
        ("engine total", lambda m: m.whitted("phases", "total")),
    ):
        values = [getter(m) for _, _, m in rows]
        _plot_series(axis, pixels, values, positive=True, marker="o", label=label)
    _dress(axis, "The demo: time against pixel count", "pixels", "seconds (median)")
    _save(figure, path)


def plot_depth(rows, path):
    figure, axis = plt.subplots(figsize=(7, 4.5))
    depths = [d for d, _ in rows]
    traces = [m.whitted("phases", "trace") for _, m in rows]
    _plot_series(axis, depths, traces, marker="o", label="trace (s)")
    axis.set_xlabel("max depth")
    axis.set_ylabel("trace seconds (median)")
    rays = axis.twinx()
    counts = [_scale(m.whitted("rays", "total"), 1e-6) for _, m in rows]
    style = {"marker": "s", "linestyle": "--", "color": "tab:orange", "label": "rays (M)"}
    _plot_series(rays, depths, counts, **style)
    rays.set_ylabel("million rays")
    axis.set_title("Glass scene: time and rays against max depth")
    figure.legend(loc="upper left", fontsize=8)
    _save(figure, path)


def plot_threads(scaling, path):
    figure, axis = plt.subplots(figsize=(8, 4.5))
    width = 0.38
    for offset, threads in ((-width / 2, 1), (width / 2, 2)):
        values = [
            scaling["threads"][name][threads].whitted("phases", "trace") or 0.0
            for name in MAIN_SCENES
        ]
        bars = axis.bar(
            [i + offset for i in range(len(MAIN_SCENES))], values, width, label=f"{threads} thr"
        )
        if threads == 2:
            for bar, name in zip(bars, MAIN_SCENES, strict=True):
                gain = speedup(scaling, name, lambda m: m.whitted("phases", "trace"))
                axis.annotate(
                    ratio_text(gain), (bar.get_x() + bar.get_width() / 2, bar.get_height())
                )
    axis.set_xticks(range(len(MAIN_SCENES)), MAIN_SCENES)
    axis.set_ylabel("trace seconds (median)")
    axis.set_title("1 against 2 threads (labels: speed-up)")
    axis.legend(fontsize=8)
    _save(figure, path)


# --- The page ----------------------------------------------------------------------


def scene_section(suite, results, image_rel):
    plan = suite.plan
    labels = [label for label, _ in plan.sizes]
    sizes = dict(plan.sizes)
    first = next((m for m in results.whitted.values() if m.runs), None)
    titles = {
        "demo": "the demo scene",
        "million": f"{plan.million:,} triangles of glass and mirrors",
        "instances": f"{plan.instances:,} instances",
        "glass8": "glass-heavy, max depth 8",
    }
    lines = [f"### {results.name}: {titles[results.name]}", ""]
    if first is None:
        reason = next(iter(results.whitted.values())).missing
        return [*lines, f"No Whitted render: {reason}.", ""]
    stats = first.runs[0]["whitted"]
    lines += [
        f"{mesh_triangles(first):,} mesh triangles (each instanced mesh once), "
        f"{stats['triangles']:,} triangles instanced, {stats['instances']:,} instances, "
        f"lights: {stats['lights']}; Whitted {stats['settings']['aa_mode'].lower()} "
        f"{stats['settings']['aa_samples']}x{stats['settings']['aa_samples']} samples per "
        f"pixel, max depth {stats['settings']['max_depth']}, {stats['threads']} threads, "
        f"Blender {stats['blender']}.",
        "",
        "| Whitted | "
        + " | ".join(f"{label} ({size_label(sizes[label])})" for label in labels)
        + " |",
        "|---|" + "---:|" * len(labels),
    ]
    for phase in PHASES:
        values = [seconds_text(results.whitted[label].whitted("phases", phase)) for label in labels]
        lines.append(f"| {phase} (s) | " + " | ".join(values) + " |")
    rows = {
        "BVH build, mesh + scene (s)": lambda label: seconds_text(
            bvh_seconds(results.whitted[label])
        ),
        "end to end in Blender (s)": lambda label: seconds_text(
            results.whitted[label].median(lambda r: r["seconds"])
        ),
        "export per million mesh triangles (s)": lambda label: num(
            export_per_million(results.whitted[label])
        ),
        "write-back per 1920x1080 pass (ms)": lambda label: num(
            _scale(writeback_per_hd_pass(results.whitted[label]), 1000.0), 2
        ),
    }
    for ray in (*RAY_TYPES, "total"):
        rows[f"{ray} rays (M/s over the trace)"] = lambda label, ray=ray: num(
            _rays_per_second(results.whitted[label], ray), 2
        )
    rows |= {
        "total rays (millions)": lambda label: num(
            _scale(results.whitted[label].whitted("rays", "total"), 1e-6), 2
        ),
        "Whitted peak RSS (MiB)": lambda label: num(
            results.whitted[label].median(lambda r: r["peak_rss_mib"]), 0
        ),
        "Blender's own peak RSS, null engine (MiB)": lambda label: num(
            results.null[label].median(lambda r: r["peak_rss_mib"]), 0
        ),
        "beyond Blender's own (MiB)": lambda label: num(
            beyond_blender_mib(results.whitted[label], results.null[label]), 0
        ),
        "bytes per mesh triangle beyond Blender's own": lambda label: num(
            bytes_per_triangle(results.whitted[label], results.null[label], mesh_triangles(first)),
            0,
        ),
        "bytes per instanced triangle beyond Blender's own": lambda label: num(
            bytes_per_triangle(results.whitted[label], results.null[label], stats["triangles"]),
            2,
        ),
        "Whitted repeats (median of)": lambda label: repeats_note(results.whitted[label]),
    }
    for title, value in rows.items():
        lines.append(f"| {title} | " + " | ".join(value(label) for label in labels) + " |")
    lines.append("")
    images = [
        (ENGINE_NAMES[engine], _scene_image(suite, results.name, engine, plan.small))
        for engine in ENGINE_NAMES
    ]
    shown = [(engine, path) for engine, path in images if path.exists()]
    if shown:
        lines += [
            f"Rendered at {size_label(plan.small)}:",
            "",
            "| " + " | ".join(engine for engine, _ in shown) + " |",
            "|" + "---|" * len(shown),
            "| " + " | ".join(f"![{results.name}, {e}]({image_rel(p)})" for e, p in shown) + " |",
            "",
        ]
    return lines


def _scale(value, factor):
    return None if value is None else value * factor


def _rays_per_second(measurement, ray):
    rays = measurement.whitted("rays", ray)
    trace = measurement.whitted("phases", "trace")
    return None if rays is None or not trace else rays / trace / 1e6


def comparison_section(suite, scenes):
    lines = [
        "## Side by side: ratios",
        "",
        "Each row is one scene at one size, measured in the same run. Efficiency is "
        "Whitted's rays per second over raw Embree's on the same rays "
        "(scripts/perf_raw_embree.py: a bare single-ray loop over the recorded queries). "
        "POV-Ray is POV-Ray 3.7 through Blender 3.4's bundled render_povray add-on "
        "(scripts/perf_povray.py matches the settings): its end-to-end time in Blender, "
        "and its own trace time (what POV-Ray reports) against Whitted's trace phase. "
        "Cycles renders its own 64 samples (CPU, no adaptive sampling, no denoising). "
        "A ratio above 1 means Whitted is faster.",
        "",
        "| scene | size | Whitted end to end (s) | raw Embree efficiency | POV-Ray end to end "
        "(s) | POV-Ray / Whitted, end to end | POV-Ray trace (s) | POV-Ray trace / Whitted "
        "trace | Cycles 64 samples (s) | Cycles / Whitted, end to end |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for results in scenes:
        for label, size in suite.plan.sizes:
            whitted = results.whitted[label]
            ours = whitted.median(lambda r: r["seconds"])
            trace = whitted.whitted("phases", "trace")
            embree = results.embree[label]
            povray = results.povray[label]
            cycles = results.cycles[label]
            pov_total = povray.median(lambda r: r["seconds"])
            pov_trace = povray.median(lambda r: r["povray"].get("povray_seconds"))
            cycles_total = cycles.median(lambda r: r["seconds"])
            efficiency = embree.median(lambda r: r.get("efficiency"))
            lines.append(
                f"| {results.name} | {size_label(size)} | {seconds_text(ours)} | "
                f"{cell(embree, num(efficiency, 2) if efficiency is not None else None)} | "
                f"{cell(povray, seconds_text(pov_total) if pov_total is not None else None)} | "
                f"{ratio_text(ratio(pov_total, ours))} | {seconds_text(pov_trace)} | "
                f"{ratio_text(ratio(pov_trace, trace))} | "
                f"{cell(cycles, seconds_text(cycles_total) if cycles_total else None)} | "
                f"{ratio_text(ratio(cycles_total, ours))} |"
            )
    lines += [
        "",
        *image_agreement(suite, scenes),
        *embree_details(suite, scenes),
        *bpy_section(suite, scenes),
    ]
    return lines


# Mean absolute difference (display values 0..1) above which two engines' pictures of
# a scene are not the same picture: Cycles' soft light and noise stay well below it.
SAME_PICTURE = 0.1


def image_agreement(suite, scenes):
    """Whether POV-Ray and Cycles drew the picture Whitted drew (small size): a time
    ratio means something only for the same picture."""
    lines = [
        "Do the engines draw the same picture? Mean absolute difference of each engine's "
        f"PNG from Whitted's at {size_label(suite.plan.small)} (display values 0..1); "
        f"above {SAME_PICTURE} the pictures differ and that engine's ratios above do not "
        "compare like with like.",
        "",
        "| scene | POV-Ray | Cycles |",
        "|---|---:|---:|",
    ]
    for results in scenes:
        ours = _scene_image(suite, results.name, "WHITTED", suite.plan.small)
        cells = []
        for engine in ("POVRAY", "CYCLES"):
            theirs = _scene_image(suite, results.name, engine, suite.plan.small)
            if ours is None or theirs is None or not (ours.exists() and theirs.exists()):
                cells.append("no image")
                continue
            a = plt.imread(ours)[..., :3]
            b = plt.imread(theirs)[..., :3]
            difference = float(abs(a - b).mean()) if a.shape == b.shape else None
            if difference is None:
                cells.append("sizes differ")
            elif difference > SAME_PICTURE:
                cells.append(f"**{difference:.3f}: a different picture**")
            else:
                cells.append(f"{difference:.3f}")
        lines.append(f"| {results.name} | {' | '.join(cells)} |")
    return [*lines, ""]


def embree_details(suite, scenes):
    lines = [
        "Raw Embree in detail (Mrays/s, one process each, all threads). Whitted without "
        "packets is the same render with each camera ray its own query (Settings.packets "
        "off), in the same process: the packet gain is the ratio of the two.",
        "",
        "| scene | size | Whitted | Whitted without packets | packet gain | raw Embree "
        "| efficiency | rays recorded |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for results in scenes:
        for label, size in suite.plan.sizes:
            embree = results.embree[label]
            if not embree.runs:
                lines.append(f"| {results.name} | {size_label(size)} | {embree.missing} |||||")
                continue
            run = embree.runs[0]
            packets = run.get("whitted_rays_per_second")
            single = run.get("whitted_single_ray_rays_per_second")
            lines.append(
                f"| {results.name} | {size_label(size)} | "
                f"{num(_scale(packets, 1e-6), 2)} | {num(_scale(single, 1e-6), 2)} | "
                f"{ratio_text(ratio(packets, single))} | "
                f"{num(_scale(run.get('embree_rays_per_second'), 1e-6), 2)} | "
                f"{num(run.get('efficiency'), 2)} | {run.get('recorded_rays', '—')} |"
            )
    return [*lines, ""]


def bpy_section(suite, scenes):
    demo = next(r for r in scenes if r.name == "demo")
    lines = [
        "Whitted on the demo in both Blenders (the same file; Blender 5.0 is the `bpy` module):",
        "",
        "| Blender | size | export (s) | BVH (s) | trace (s) | write-back (s) | engine total (s) "
        "| end to end (s) | Mrays/s |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for label, size in suite.plan.sizes:
        for measurement in (demo.whitted[label], demo.bpy[label]):
            if not measurement.runs:
                lines.append(f"| ? | {size_label(size)} | {measurement.missing} | | | | | | |")
                continue
            phases = [measurement.whitted("phases", p) for p in PHASES]
            lines.append(
                f"| {measurement.runs[0]['blender']} | {size_label(size)} | "
                f"{seconds_text(phases[0])} | {seconds_text(bvh_seconds(measurement))} | "
                f"{seconds_text(phases[3])} | {num(phases[4], 4)} | {seconds_text(phases[5])} | "
                f"{seconds_text(measurement.median(lambda r: r['seconds']))} | "
                f"{num(_scale(measurement.whitted('rays_per_second'), 1e-6), 2)} |"
            )
    return [*lines, ""]


def scaling_section(suite, scaling, image_rel):
    plan = suite.plan
    lines = [
        "## Scaling",
        "",
        f"### Triangles (a torus of N triangles, a mirror, a floor; {size_label(plan.small)})",
        "",
        f"![time against triangles]({image_rel(suite.image_dir / 'perf_triangles.png')})",
        "",
        "| mesh triangles | export (s) | export per M triangles (s) | BVH build (s) | "
        "BVH per M triangles (s) | trace (s) | engine total (s) | end to end (s) | beyond "
        "Blender's own (MiB) | bytes per triangle |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for count, whitted, null in scaling["triangles"]:
        triangles = mesh_triangles(whitted)
        if triangles is None:
            lines.append(f"| {count:,} | {whitted.missing} | | | | | | | | |")
            continue
        lines.append(
            f"| {triangles:,} | {seconds_text(whitted.whitted('phases', 'export'))} | "
            f"{num(export_per_million(whitted))} | {seconds_text(bvh_seconds(whitted))} | "
            f"{num(ratio(bvh_seconds(whitted), triangles / 1e6))} | "
            f"{seconds_text(whitted.whitted('phases', 'trace'))} | "
            f"{seconds_text(whitted.whitted('phases', 'total'))} | "
            f"{seconds_text(whitted.median(lambda r: r['seconds']))} | "
            f"{num(beyond_blender_mib(whitted, null), 0)} | "
            f"{num(bytes_per_triangle(whitted, null, triangles), 0)} |"
        )
    lines += [
        "",
        "### Pixels (the demo)",
        "",
        f"![time against pixels]({image_rel(suite.image_dir / 'perf_pixels.png')})",
        "",
        "| size | pixels | trace (s) | trace per M pixels (s) | write-back (ms) | "
        "write-back per 1920x1080 pass (ms) | engine total (s) |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for width, height, measurement in scaling["pixels"]:
        trace = measurement.whitted("phases", "trace")
        lines.append(
            f"| {width}x{height} | {width * height:,} | {seconds_text(trace)} | "
            f"{num(ratio(trace, width * height / 1e6))} | "
            f"{num(_scale(measurement.whitted('phases', 'writeback'), 1000.0), 2)} | "
            f"{num(_scale(writeback_per_hd_pass(measurement), 1000.0), 2)} | "
            f"{seconds_text(measurement.whitted('phases', 'total'))} |"
        )
    lines += [
        "",
        f"### Depth (the glass scene, {size_label(plan.small)})",
        "",
        f"![time against depth]({image_rel(suite.image_dir / 'perf_depth.png')})",
        "",
        "| max depth | rays (M) | reflection (M) | refraction (M) | cut by depth | trace (s) "
        "| Mrays/s |",
        "|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for depth, measurement in scaling["depth"]:
        lines.append(
            f"| {depth} | {num(_scale(measurement.whitted('rays', 'total'), 1e-6), 2)} | "
            f"{num(_scale(measurement.whitted('rays', 'reflection'), 1e-6), 2)} | "
            f"{num(_scale(measurement.whitted('rays', 'refraction'), 1e-6), 2)} | "
            f"{num(measurement.whitted('depth_limited'), 0)} | "
            f"{seconds_text(measurement.whitted('phases', 'trace'))} | "
            f"{num(_scale(measurement.whitted('rays_per_second'), 1e-6), 2)} |"
        )
    lines += [
        "",
        f"### Threads: 1 against 2 ({size_label(plan.small)})",
        "",
        f"![1 against 2 threads]({image_rel(suite.image_dir / 'perf_threads.png')})",
        "",
        "| scene | trace, 1 thread (s) | trace, 2 threads (s) | trace speed-up | engine "
        "total speed-up | end-to-end speed-up |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for name in MAIN_SCENES:
        runs = scaling["threads"][name]
        lines.append(
            f"| {name} | {seconds_text(runs[1].whitted('phases', 'trace'))} | "
            f"{seconds_text(runs[2].whitted('phases', 'trace'))} | "
            f"{ratio_text(speedup(scaling, name, lambda m: m.whitted('phases', 'trace')))} | "
            f"{ratio_text(speedup(scaling, name, lambda m: m.whitted('phases', 'total')))} | "
            f"{ratio_text(speedup(scaling, name, lambda m: m.median(lambda r: r['seconds'])))} |"
        )
    return [*lines, ""]


@dataclass(frozen=True)
class Target:
    title: str
    threshold: float
    at_least: bool  # True: measured >= threshold passes; False: <=
    unit: str
    measured: float | None
    where: str


def verdict(target):
    """(result, margin text) of one target."""
    value, threshold = target.measured, target.threshold
    if value is None:
        return "not measured", "—"
    passed = value >= threshold if target.at_least else value <= threshold
    gap = abs(value - threshold)
    share = gap / threshold
    amount = f"{gap:.3g}{target.unit} ({share:.0%} of the target)"
    return ("pass", f"{amount} to spare") if passed else ("**miss**", f"missed by {amount}")


def _worst(pairs, at_least):
    """(value, where) with the worst value of (value, where) pairs, None if none."""
    pairs = [(v, w) for v, w in pairs if v is not None]
    if not pairs:
        return None, "not measured"
    return min(pairs) if at_least else max(pairs)


def targets(suite, scenes, scaling):
    plan = suite.plan
    large_label, large = plan.sizes[-1]
    small_label = plan.sizes[0][0]
    by_name = {r.name: r for r in scenes}
    efficiency = _worst(
        [
            (r.embree[label].median(lambda x: x.get("efficiency")), f"{r.name}, {size_label(s)}")
            for r in scenes
            for label, s in plan.sizes
        ],
        at_least=True,
    )
    threads = _worst(
        [
            (speedup(scaling, n, lambda m: m.whitted("phases", "trace")), f"{n} (trace phase)")
            for n in MAIN_SCENES
        ],
        at_least=True,
    )
    largest_sweep = scaling["triangles"][-1][1]
    export_candidates = [
        (export_per_million(by_name["million"].whitted[label]), f"million, {size_label(s)}")
        for label, s in plan.sizes
    ] + [
        (
            export_per_million(largest_sweep),
            f"triangle curve, {mesh_triangles(largest_sweep) or 0:,} triangles",
        )
    ]
    export = _worst(export_candidates, at_least=False)
    writeback = _worst(
        [(_scale(writeback_per_hd_pass(r.whitted[large_label]), 1000.0), r.name) for r in scenes],
        at_least=False,
    )
    demo = by_name["demo"]
    povray = _worst(
        [
            (
                ratio(
                    demo.povray[label].median(lambda r: r["seconds"]),
                    demo.whitted[label].median(lambda r: r["seconds"]),
                ),
                f"demo, {size_label(s)}",
            )
            for label, s in plan.sizes[-1:]
        ],
        at_least=True,
    )
    million = by_name["million"]
    memory = _worst(
        [
            (
                bytes_per_triangle(
                    million.whitted[small_label],
                    million.null[small_label],
                    mesh_triangles(million.whitted[small_label]),
                ),
                f"million, {size_label(plan.small)}",
            ),
            (
                bytes_per_triangle(
                    largest_sweep, scaling["triangles"][-1][2], mesh_triangles(largest_sweep)
                ),
                f"triangle curve, {mesh_triangles(largest_sweep) or 0:,} triangles",
            ),
        ],
        at_least=False,
    )
    writeback_where = writeback[1] + (
        f", {size_label(large)}" if large == (1920, 1080) else f", scaled from {size_label(large)}"
    )
    return [
        Target("efficiency against raw Embree (worst scene)", 0.9, True, "", *efficiency),
        Target("2 threads against 1 (worst scene)", 1.8, True, "x", *threads),
        Target("export per million triangles (worst)", 0.5, False, " s", *export),
        Target(
            "pixel write-back per 1920x1080 pass (worst scene)",
            10.0,
            False,
            " ms",
            writeback[0],
            writeback_where,
        ),
        Target(
            "end to end in Blender against POV-Ray through its add-on (demo)",
            5.0,
            True,
            "x",
            *povray,
        ),
        Target(
            "peak memory beyond Blender's own per triangle (worst)", 200.0, False, " B", *memory
        ),
    ]


def targets_section(suite, scenes, scaling):
    lines = [
        "## Targets",
        "",
        "| target | threshold | measured | where | result | margin |",
        "|---|---:|---:|---|---|---|",
    ]
    for target in targets(suite, scenes, scaling):
        result, margin = verdict(target)
        sign = ">=" if target.at_least else "<="
        lines.append(
            f"| {target.title} | {sign} {target.threshold:g}{target.unit} | "
            f"{num(target.measured, 3, target.unit)} | {target.where} | {result} | {margin} |"
        )
    million = next(r for r in scenes if r.name == "million")
    bvh = [
        f"{size_label(s)}: {seconds_text(bvh_seconds(million.whitted[label]))} s"
        for label, s in suite.plan.sizes
    ]
    sweep = scaling["triangles"][-1][1]
    lines += [
        f"| BVH build time (stated) | — | million scene: {', '.join(bvh)}; "
        f"{mesh_triangles(sweep) or 0:,} triangles: {seconds_text(bvh_seconds(sweep))} s | "
        "mesh BVHs + the top-level BVH | stated | — |",
        "",
    ]
    return lines


def method_lines(plan):
    slow = f"Cycles and POV-Ray {plan.repeats}x"
    if plan.large != plan.small:
        slow += f" at {size_label(plan.small)} and {plan.large_slow_repeats}x at "
        slow += size_label(plan.large)
    return [
        "## How each figure is measured",
        "",
        "- **Runs**: every render is a fresh `blender -b --factory-startup --addons whitted "
        "FILE.blend --python scripts/perf_render.py` process (Blender 3.4; the `bpy` rows "
        "use the Blender 5.0 module); tables give the median of the repeats: Whitted "
        f"{plan.repeats}x, {slow} (they are slow; timeouts: "
        + ", ".join(f"{k} {v} s" for k, v in plan.timeouts.items())
        + f"). A scene whose small-size run of a slow engine failed is not run at the large "
        f"size. The cheap figures run first, the slow engines at the large size last; a "
        f"POV-Ray, Cycles or raw Embree run not started within the budget "
        f"({plan.budget_minutes:g} minutes unless --budget-minutes says otherwise), or a "
        "large-size run whose small-size time scaled by the pixels would end past it, is "
        "skipped and says so.",
        "- **Phases** are the engine's own (`scene.whitted.last_stats`, addon/stats.py): "
        "export (Blender data to the native scene, less the mesh BVH builds), mesh_bvh, "
        "scene_bvh (the top-level BVH), trace (first tile to last, all threads), writeback "
        "(every tile copied into Blender's render result, summed over the render: at "
        "1920x1080 one render is one pass), total (the engine's render call). **End to "
        "end** is the wall time around `bpy.ops.render.render` in the same process "
        "(Blender's render pipeline included, start-up and file load not), the same clock "
        "for every engine.",
        "- **Rays per second** by type: that type's rays over the trace phase; total: all "
        "rays over the trace phase.",
        "- **Export per million triangles**: the export phase over the mesh triangles "
        "Whitted exports (each distinct mesh once, counted by perf_scenes.py from the "
        "evaluated meshes).",
        "- **Write-back per 1920x1080 pass**: the writeback phase of a render (every "
        "write into Blender's render result: Blender's begin_result, the pixels handed over "
        "with foreach_set, and end_result, which merges them into the image) over the "
        "passes it writes (Combined and Whitted Rays), scaled by 1920x1080 / its pixel "
        "count (exact for the 1920x1080 renders).",
        "- **Memory**: peak resident set size of the Blender process (getrusage "
        "ru_maxrss) after the render. **Blender's own** is the peak of the same Blender "
        "loading the same file at the same size and rendering it with a do-nothing "
        "engine (perf_render.py's NULL: Blender evaluates the scene and allocates the "
        "render result as for any engine; the engine walks every object instance and "
        "writes an empty image). The difference is what Whitted adds (its native module, "
        "exported arrays, BVHs, image buffers); bytes per triangle divide it by the mesh "
        "triangles. The target is judged where triangles dominate: the million scene at "
        "the small size and the largest point of the triangle curve. ru_maxrss varies by a "
        "few MiB from run to run, so the small scenes' differences are noise.",
        "- **Threads**: Blender's render threads fixed at 1 (`--threads 1`) against 2 (the "
        "default runs where Blender's default is 2 threads, else `--threads 2`); the "
        "speed-up is the 1-thread trace time over the 2-thread one (engine total and end "
        "to end shown too: export is single-threaded Python).",
        "- **Raw Embree**: scripts/perf_raw_embree.py (one process per scene and size, its "
        "own repeats).",
        "- **POV-Ray**: scripts/perf_povray.py `configure(scene)` then `render(scene, "
        "image)`: end to end is its `render_seconds` (the wall time of the add-on's "
        "`bpy.ops.render.render`: export, POV-Ray, reading the image back), POV-Ray's own "
        "trace time its `povray_seconds` (the Trace Time POV-Ray reports).",
        "",
    ]


def write_plots(suite, scaling):
    plot_triangles(scaling["triangles"], suite.image_dir / "perf_triangles.png")
    plot_pixels(scaling["pixels"], suite.image_dir / "perf_pixels.png")
    plot_depth(scaling["depth"], suite.image_dir / "perf_depth.png")
    plot_threads(scaling, suite.image_dir / "perf_threads.png")


def page(suite, args, scenes, scaling, elapsed):
    page_dir = args.out.resolve().parent

    def image_rel(path):
        return Path(os.path.relpath(path, page_dir)).as_posix()

    python = sys.executable
    if Path(python).is_relative_to(REPO):
        python = os.path.relpath(python, REPO)
    versions = sorted(
        {run["blender"] for m in suite.results.values() for run in m.runs if "blender" in run}
    )
    lines = [
        "# Performance",
        "",
        "Generated by `scripts/bench_performance.py` (issue 7's suite); do not edit by hand "
        "(the explanation of the misses comes from the --notes files). Command, from the "
        "repository root:",
        "",
        f"    {shlex.join([python, *sys.argv])}",
        "",
        f"The run took {elapsed / 60:.1f} minutes"
        + (" (--quick: tiny sizes and scenes, a smoke test, not results)" if args.quick else "")
        + ".",
        "",
        *machine_lines(),
        f"- Blender versions: {', '.join(versions)} (Blender 3.4 runs every comparison; "
        "POV-Ray's add-on exists only there)",
        "",
        "Ratios are the results, not the absolute times: the machine is shared.",
        "",
        *targets_section(suite, scenes, scaling),
        "## Notes: why targets are missed",
        "",
    ]
    if args.notes:
        for note in args.notes:
            lines += [note.read_text().rstrip(), ""]
    else:
        lines += [
            "_No notes given: the profiling explanation of each miss goes in a Markdown file "
            "passed with --notes._",
            "",
        ]
    lines += comparison_section(suite, scenes)
    lines += ["## Scenes", ""]
    for results in scenes:
        lines += scene_section(suite, results, image_rel)
    lines += scaling_section(suite, scaling, image_rel)
    lines += method_lines(suite.plan)
    if suite.problems:
        lines += ["## Runs that failed, timed out or were skipped", ""]
        lines += [f"- {problem}" for problem in suite.problems]
        lines.append("")
    return "\n".join(lines) + "\n"


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="tiny smoke-test run")
    parser.add_argument("--repeats", type=int, default=3, help="Whitted's repeats (full run)")
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "PERFORMANCE.md")
    parser.add_argument("--notes", nargs="*", type=Path, default=[])
    parser.add_argument("--blender", default="blender", help="Blender 3.4")
    parser.add_argument("--python", default=sys.executable, help="Python with the bpy module")
    parser.add_argument("--keep", type=Path, help="keep the scene files and JSON here")
    parser.add_argument(
        "--budget-minutes",
        type=float,
        help="after this long, skip the POV-Ray, Cycles and raw Embree runs not yet made "
        "(default: 40 for the full run, 3 with --quick)",
    )
    return parser.parse_args()


def main():
    args = parse_args()
    started = time.perf_counter()
    plan = quick_plan() if args.quick else full_plan(args.repeats)
    image_dir = args.out.resolve().parent / "images"
    image_dir.mkdir(parents=True, exist_ok=True)
    for stale in image_dir.glob("perf_scene_*.png"):  # a failed run must not show an old one
        stale.unlink()
    with tempfile.TemporaryDirectory(prefix="whitted-perf-") as tmp:
        workdir = args.keep or Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        deadline = time.monotonic() + 60.0 * (args.budget_minutes or plan.budget_minutes)
        suite = Suite(plan, args.blender, args.python, workdir.resolve(), image_dir, deadline)
        # The cheap figures first; the slow engines last, the large size last of all, so
        # a run past its budget loses only those.
        scenes = [measure_whitted(suite, name) for name in MAIN_SCENES]
        scaling = measure_scaling(suite)
        for label, _ in plan.sizes:
            for results in scenes:
                measure_slow(suite, results, label)
    write_plots(suite, scaling)
    text = page(suite, args, scenes, scaling, time.perf_counter() - started)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text, encoding="utf-8")
    print(f"bench_performance: wrote {args.out.resolve()} in {time.perf_counter() - started:.0f} s")
    # POV-Ray and Cycles may time out (the page says so); our own runs may not.
    ours = [p for p in suite.problems if not p.startswith(("POVRAY", "CYCLES"))]
    if ours:
        sys.exit("bench_performance: Whitted's own measurements failed:\n" + "\n".join(ours))


if __name__ == "__main__":
    main()
