"""The plots of docs/PERFORMANCE.md (docs/images/perf_*.png): the four scaling curves
from the suite's measurements."""

from whitted_tools.pages import ratio_text, scale
from whitted_tools.perf.figures import bvh_seconds, bytes_per_triangle, mesh_triangles, speedup
from whitted_tools.perf.plan import MAIN_SCENES
from whitted_tools.plots import dress, plot_series, plt, save


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
        plot_series(times, counts, values, positive=True, marker="o", label=label)
    dress(times, "Time against triangle count", "triangles", "seconds (median)")
    # A difference within ru_maxrss's noise can be negative: not on a log axis.
    values = [bytes_per_triangle(w, null, c) for c, (_, w, null) in zip(counts, rows, strict=True)]
    plot_series(memory, counts, values, positive=True, marker="o", color="tab:purple")
    memory.axhline(200.0, color="red", linestyle="--", label="target: 200 bytes/triangle")
    dress(
        memory,
        "Memory per triangle",
        "triangles",
        "peak memory beyond Blender's own, bytes per triangle",
    )
    save(figure, path)


def plot_pixels(rows, path):
    figure, axis = plt.subplots(figsize=(7, 4.5))
    pixels = [w * h for w, h, _ in rows]
    for label, getter in (
        ("trace", lambda m: m.whitted("phases", "trace")),
        ("write-back", lambda m: m.whitted("phases", "writeback")),
        ("engine total", lambda m: m.whitted("phases", "total")),
    ):
        values = [getter(m) for _, _, m in rows]
        plot_series(axis, pixels, values, positive=True, marker="o", label=label)
    dress(axis, "The demo: time against pixel count", "pixels", "seconds (median)")
    save(figure, path)


def plot_depth(rows, path):
    figure, axis = plt.subplots(figsize=(7, 4.5))
    depths = [d for d, _ in rows]
    traces = [m.whitted("phases", "trace") for _, m in rows]
    plot_series(axis, depths, traces, marker="o", label="trace (s)")
    axis.set_xlabel("max depth")
    axis.set_ylabel("trace seconds (median)")
    rays = axis.twinx()
    counts = [scale(m.whitted("rays", "total"), 1e-6) for _, m in rows]
    style = {"marker": "s", "linestyle": "--", "color": "tab:orange", "label": "rays (M)"}
    plot_series(rays, depths, counts, **style)
    rays.set_ylabel("million rays")
    axis.set_title("Glass scene: time and rays against max depth")
    figure.legend(loc="upper left", fontsize=8)
    save(figure, path)


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
    save(figure, path)


def write_plots(suite, scaling):
    plot_triangles(scaling["triangles"], suite.image_dir / "perf_triangles.png")
    plot_pixels(scaling["pixels"], suite.image_dir / "perf_pixels.png")
    plot_depth(scaling["depth"], suite.image_dir / "perf_depth.png")
    plot_threads(scaling, suite.image_dir / "perf_threads.png")
