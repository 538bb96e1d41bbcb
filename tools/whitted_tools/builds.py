"""Two builds of whitted_native side by side: their trace times in alternating rounds.

Two builds of whitted_native side by side: each build's module loaded from its folder,
and the order in which the rounds of a comparison run them, so that every ratio between
the builds is taken within a round (timing.paired_ratios) and neither build always goes
first. bench_effects.py (--compare-native) measures its kernels this way; the perf
suite's --before reaches another build through Blender's user scripts instead
(blender.addon_env), as its raw Embree runs need that build's whole add-on.

Run as a module, it traces one scene of constant materials with each build: the
issue-12 cost clause ("a scene whose materials are constants traces no slower than
today") against a build from before shader programs, and issue 13's (no pass enabled,
trace time unchanged) against a build from before passes (docs/PASSES.md):

    .venv/bin/python -m whitted_tools.builds OLD_ADDON_DIR NEW_ADDON_DIR [--rounds 8] \\
        [--json FILE --old-label TEXT --new-label TEXT]
    valgrind --tool=callgrind .venv/bin/python -m whitted_tools.builds --small ADDON_DIR

--json writes the figures, the command and the machine to FILE for a page's generator
(whitted_tools passes-page reads docs/images/passes/builds.json), the labels saying what
each build is (its commit). Each build's module is loaded in a process of its own (one
whitted_native per process), the two in turns for --rounds rounds; each process renders
the scene (binding_scenes.constant_spheres: 480x270, 3x3 samples per pixel, 2 threads)
three times and keeps its best trace time. Prints each build's best and median trace
seconds, its rays and the image mean (the same scene must give the same image), the
ratio new / old of the best times and the rounds' paired ratios (median [min..max]) of
the best trace and of the best CPU seconds (every thread of the process), and the load.

--small renders the scene once on one thread at 160x90 with 2x2 samples, for callgrind:
`callgrind_annotate --inclusive=yes` then gives RenderJob::trace's instructions (a build
with symbols: -DCMAKE_CXX_FLAGS=-g -DCMAKE_STRIP=/bin/true).
"""

import argparse
import importlib.util
import json
import math
import statistics
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

from whitted_tools.binding_scenes import constant_spheres
from whitted_tools.blender import run_for_json
from whitted_tools.native_job import run_job
from whitted_tools.pages import command_line, load_text, machine_lines
from whitted_tools.timing import paired_ratios, spread_text
from whitted_tools.verbs import prog

REPEATS = 3
TIMED = {"width": 480, "height": 270, "aa_samples": 3, "threads": 2}
SMALL = {"width": 160, "height": 90, "aa_samples": 2, "threads": 1}
CHILD_TIMEOUT = 600  # seconds one process's renders may take


def native_module(folder):
    """whitted_native from `folder` (a build of the add-on, or any folder holding its
    module): the module built for this Python, a build holding one per CPython."""
    path = Path(folder) / f"whitted_native{sysconfig.get_config_var('EXT_SUFFIX')}"
    if not path.exists():
        raise FileNotFoundError(f"no whitted_native module for this Python: {path}")
    spec = importlib.util.spec_from_file_location("whitted_native", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def stand_in_for_addon(module, addon="whitted"):
    """Make the add-on `addon` use `module` (another build's whitted_native) wherever it
    loads its own, as its export helpers do: a process can hold only one build, a second
    module's types clashing with the first's (pybind11: "already registered"). Call it
    before anything has loaded the add-on's module."""
    sys.modules[f"{addon}.whitted_native"] = module


def round_order(round_index, count):
    """The indices of `count` builds in the order round `round_index` runs them: forward
    in even rounds, backward in odd ones."""
    order = list(range(count))
    return order if round_index % 2 == 0 else order[::-1]


def interleaved(rounds, builds, run):
    """[round][build] -> run(build index, round index): each of `builds` builds once a
    round, in round_order."""
    table = []
    for index in range(rounds):
        done = {build: run(build, index) for build in round_order(index, builds)}
        table.append([done[build] for build in range(builds)])
    return table


def trace_best(module_dir, size=TIMED, repeats=REPEATS):
    """Inside one process: render the scene `repeats` times with the module in module_dir;
    its best trace and CPU seconds, its rays and its image's mean."""
    wn = native_module(module_dir)
    scene = constant_spheres(wn)
    best, best_cpu = math.inf, math.inf
    for _ in range(repeats):
        job = wn.RenderJob(scene, wn.Settings(**size))
        started = time.process_time()
        run_job(job)
        # CPU seconds of every thread of the process: they move less than the wall clock
        # when other work shares the cores.
        best_cpu = min(best_cpu, time.process_time() - started)
        best = min(best, job.stats()["trace_seconds"])
    mean = float(job.image()[..., :3].mean())
    return {"trace": best, "cpu": best_cpu, "rays": job.stats()["rays"]["total"], "mean": mean}


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.split("\n\n")[0])
    parser.add_argument("old", help="the folder holding the old build's whitted_native")
    parser.add_argument("new", help="the folder holding the new build's whitted_native")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--json", type=Path, help="write the figures to this file")
    parser.add_argument("--old-label", default="old", help="what the old build is")
    parser.add_argument("--new-label", default="new", help="what the new build is")
    return parser.parse_args(argv)


def compare(args, folder):
    """Each build's runs, round by round: {"old": [figures], "new": [figures]}."""

    folders = (args.old, args.new)

    def run(build, index):
        out = Path(folder) / f"{index}-{build}.json"
        command = [sys.executable, "-m", "whitted_tools.builds", "--trace", folders[build], out]
        figures, problem = run_for_json(command, out, CHILD_TIMEOUT)
        if problem:
            sys.exit(f"whitted_tools.builds: {folders[build]}: {problem}")
        return figures

    table = interleaved(args.rounds, len(folders), run)
    return {"old": [row[0] for row in table], "new": [row[1] for row in table]}


def main(argv):
    if len(argv) == 3 and argv[0] == "--trace":
        Path(argv[2]).write_text(json.dumps(trace_best(argv[1])), encoding="utf-8")
        return
    if len(argv) == 2 and argv[0] == "--small":
        print(json.dumps(trace_best(argv[1], SMALL, repeats=1)))
        return
    args = parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="whitted-builds-") as folder:
        runs = compare(args, folder)
    figures = {}
    for name, results in runs.items():
        times = [r["trace"] for r in results]
        figures[name] = {
            "label": getattr(args, f"{name}_label"),
            "best": min(times),
            "median": statistics.median(times),
            "rays": results[0]["rays"],
            "image_mean": results[0]["mean"],
        }
        print(
            f"{name} ({getattr(args, name)}): best {min(times):.3f} s, median "
            f"{statistics.median(times):.3f} s, rays {results[0]['rays']}, image mean "
            f"{results[0]['mean']:.6f}"
        )
    paired = paired_ratios([r["trace"] for r in runs["new"]], [r["trace"] for r in runs["old"]])
    paired_cpu = paired_ratios([r["cpu"] for r in runs["new"]], [r["cpu"] for r in runs["old"]])
    best = figures["new"]["best"] / figures["old"]["best"]
    print(
        f"new / old: best {best:.3f}, paired rounds {spread_text(paired)}, CPU seconds "
        f"paired {spread_text(paired_cpu)}"
    )
    print(f"load average (1, 5, 15 min): {load_text()}")
    if args.json:
        record = {
            "command": command_line("compare-builds", argv, ".venv/bin/python"),
            "rounds": args.rounds,
            "builds": figures,
            "best_ratio": best,
            "paired_ratios": paired,
            "paired_text": spread_text(paired),
            "paired_cpu_ratios": paired_cpu,
            "paired_cpu_text": spread_text(paired_cpu),
            "machine": machine_lines(),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(record, indent=2) + "\n")
        print(f"wrote {args.json}")
