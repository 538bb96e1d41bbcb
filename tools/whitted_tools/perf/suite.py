"""The performance suite against raw Embree, POV-Ray and Cycles: docs/PERFORMANCE.md.

Issue 7's performance suite: measure Whitted against raw Embree, POV-Ray and Cycles,
and write docs/PERFORMANCE.md with its plots (docs/images/perf_*.png).

    .venv/bin/python -m whitted_tools bench-performance [--quick] [--repeats 3] \\
        [--out docs/PERFORMANCE.md] [--notes NOTES.md ...] [--blender blender] \
        [--before ADDON_DIR]

Scenes (whitted_tools perf-scenes): the demo; about a million triangles of glass and
mirrors; 10,000 geometry-nodes instances; a glass-heavy scene at depth 8; each at a
small size and at 1920x1080. Every measurement is a fresh Blender process
(whitted_tools perf-render, whitted_tools perf-raw-embree, POV-Ray through
whitted_tools perf-povray); figures are medians of the repeats. Whitted runs --repeats
times everywhere; Cycles and POV-Ray run --repeats times at the small size and once
at 1920x1080, and are not run at 1920x1080 on a scene whose small run failed or timed
out. Then the scaling curves: time against triangle count (1k..10M, a fixed small
size), against pixel count (the demo), against depth (0..8 on the glass scene), and 1
against 2 threads. Then raw Embree on one thread, and on the scenes of distributed ray
tracing at the quality presets. A target table says pass or miss, and by how much.

--before ADDON_DIR also makes the raw Embree runs (only those) with another build of
the add-on (a folder holding an add-on with its whitted_native*.so), each beside the
same run with this checkout's: the page then gives the efficiency before and after.

--quick runs tiny sizes, small scenes and few points, once each (a smoke test of the
whole pipeline in a minute or two); give it an --out outside docs/. --notes inserts
Markdown files (the profiling explanation of the misses) in the page's notes section.
"""

import argparse
import sys
import tempfile
import time
from pathlib import Path

from whitted_tools import REPO
from whitted_tools.pages import write_page
from whitted_tools.perf.measure import (
    Suite,
    measure_embree_variants,
    measure_scaling,
    measure_slow,
    measure_whitted,
)
from whitted_tools.perf.page import page
from whitted_tools.perf.plan import MAIN_SCENES, full_plan, quick_plan
from whitted_tools.perf.plots import write_plots
from whitted_tools.verbs import prog


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="tiny smoke-test run")
    parser.add_argument("--repeats", type=int, default=3, help="Whitted's repeats (full run)")
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "PERFORMANCE.md")
    parser.add_argument("--notes", nargs="*", type=Path, default=[])
    parser.add_argument("--blender", default="blender", help="Blender 3.4")
    parser.add_argument("--python", default=sys.executable, help="Python with the bpy module")
    parser.add_argument("--keep", type=Path, help="keep the scene files and JSON here")
    parser.add_argument(
        "--before",
        type=Path,
        metavar="ADDON_DIR",
        help="another build of the add-on (a folder with its whitted_native*.so): raw "
        "Embree's runs are made with it too, for the efficiency before and after",
    )
    parser.add_argument(
        "--budget-minutes",
        type=float,
        help="after this long, skip the POV-Ray, Cycles and raw Embree runs not yet made "
        "(default: 40 for the full run, 3 with --quick)",
    )
    return parser.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    if args.before and not list(args.before.glob("whitted_native*.so")):
        sys.exit(f"bench_performance: no whitted_native*.so in {args.before}")
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
        suite = Suite(
            plan, args.blender, args.python, workdir.resolve(), image_dir, deadline, args.before
        )
        # The cheap figures first; the slow engines last, the large size last of all, so
        # a run past its budget loses only those.
        scenes = [measure_whitted(suite, name) for name in MAIN_SCENES]
        scaling = measure_scaling(suite)
        variants = measure_embree_variants(suite)
        for label, _ in plan.sizes:
            for results in scenes:
                measure_slow(suite, results, label)
    write_plots(suite, scaling)
    elapsed = time.perf_counter() - started
    write_page(args.out, page(suite, args, argv, scenes, scaling, variants, elapsed))
    print(f"bench_performance: {time.perf_counter() - started:.0f} s")
    # POV-Ray and Cycles may time out (the page says so); our own runs may not.
    ours = [p for p in suite.problems if not p.startswith(("POVRAY", "CYCLES"))]
    if ours:
        sys.exit("bench_performance: Whitted's own measurements failed:\n" + "\n".join(ours))
