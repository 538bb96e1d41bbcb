"""Figures derived from the measurements, and the targets they are judged against
(pure functions of the JSON each render wrote: tested without Blender)."""

from dataclasses import dataclass

from whitted_tools.pages import ratio, scale, size_label
from whitted_tools.perf.measure import Measurement
from whitted_tools.perf.plan import MAIN_SCENES
from whitted_tools.timing import paired_median

HD_PIXELS = 1920 * 1080
MIB = 1024.0 * 1024.0


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
    """getter's 1-thread figure over its 2-thread one: the median of the runs' ratios
    where the runs were made in pairs (Suite.render_alternating: as many of each), else
    the ratio of the medians."""
    one, two = (scaling["threads"][name][n] for n in (1, 2))
    if one.runs and len(one.runs) == len(two.runs):
        pairs = [
            (getter(Measurement(runs=[a])), getter(Measurement(runs=[b])))
            for a, b in zip(one.runs, two.runs, strict=True)
        ]
        pairs = [(x, y) for x, y in pairs if x is not None and y]
        return paired_median(*zip(*pairs, strict=True)) if pairs else None
    x, y = getter(one), getter(two)
    return None if x is None or not y else x / y


def cell(measurement, value):
    """value as text, or why it is missing."""
    if value is not None:
        return value
    return measurement.missing or "—"


def repeats_note(measurement):
    return f"{len(measurement.runs)}" if measurement.runs else "0"


def rays_per_second(measurement, ray):
    rays = measurement.whitted("rays", ray)
    trace = measurement.whitted("phases", "trace")
    return None if rays is None or not trace else rays / trace / 1e6


def per_ray_ns(run, key):
    """Nanoseconds a thread spends on a ray at run[key] rays per second (all of the run's
    threads together): threads / rate. None when either is missing."""
    rate, threads = run.get(key), run.get("threads")
    return None if not rate or not threads else threads * 1e9 / rate


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


def worst(pairs, at_least):
    """(value, where) with the worst value of (value, where) pairs, None if none."""
    pairs = [(v, w) for v, w in pairs if v is not None]
    if not pairs:
        return None, "not measured"
    return min(pairs) if at_least else max(pairs)


def targets(suite, scenes, scaling, variants):
    """The page's targets; `variants` as measure.measure_embree_variants gives them."""
    plan = suite.plan
    large_label, large = plan.sizes[-1]
    small_label = plan.sizes[0][0]
    by_name = {r.name: r for r in scenes}
    efficiency = worst(
        [
            (r.embree[label].median(lambda x: x.get("efficiency")), f"{r.name}, {size_label(s)}")
            for r in scenes
            for label, s in plan.sizes
        ],
        at_least=True,
    )
    # Tracing in waves (issue 33): the wave kernel's efficiency, and its speed over the
    # recursion's, each the median of the rounds' paired ratios (perf_raw_embree.py).
    waves_efficiency = worst(
        [
            (
                r.embree[label].median(lambda x: x.get("waves_efficiency")),
                f"{r.name}, {size_label(s)}",
            )
            for r in scenes
            for label, s in plan.sizes
        ],
        at_least=True,
    )
    waves_gain = worst(
        [
            (r.embree[label].median(lambda x: x.get("waves_gain")), f"{r.name}, {size_label(s)}")
            for r in scenes
            for label, s in plan.sizes
        ],
        at_least=True,
    )
    # The same at one thread, and at the quality presets (all threads).
    one_thread = worst(
        [
            (m.median(lambda x: x.get("waves_efficiency")), f"{name}, {size_label(plan.small)}")
            for name, m in variants["one_thread"].items()
        ],
        at_least=True,
    )
    at_presets = worst(
        [
            (m.median(lambda x: x.get("waves_efficiency")), f"{name} at {preset}")
            for (name, preset), m in variants["presets"].items()
        ],
        at_least=True,
    )
    threads = worst(
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
    export = worst(export_candidates, at_least=False)
    writeback = worst(
        [(scale(writeback_per_hd_pass(r.whitted[large_label]), 1000.0), r.name) for r in scenes],
        at_least=False,
    )
    demo = by_name["demo"]
    povray = worst(
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
    memory = worst(
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
        Target(
            "efficiency in waves against raw Embree (worst scene)",
            0.9,
            True,
            "",
            *waves_efficiency,
        ),
        Target(
            "efficiency in waves against raw Embree, one thread (worst scene)",
            0.9,
            True,
            "",
            *one_thread,
        ),
        Target(
            "efficiency in waves at the quality presets (worst scene and preset)",
            0.9,
            True,
            "",
            *at_presets,
        ),
        Target("waves against the recursion (worst scene)", 1.5, True, "x", *waves_gain),
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
