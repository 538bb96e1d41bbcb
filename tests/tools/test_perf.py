"""The performance suite's derived figures and target checks, on hand-made runs (the
JSON perf_render.py writes), without Blender."""

from pathlib import Path

import pytest
from whitted_tools.perf.figures import (
    MIB,
    Target,
    bytes_per_triangle,
    export_per_million,
    per_ray_ns,
    speedup,
    verdict,
    worst,
    writeback_per_hd_pass,
)
from whitted_tools.perf.measure import Measurement, SceneResults, Suite
from whitted_tools.perf.page import embree_details, embree_runs, embree_variants_section
from whitted_tools.perf.plan import quick_plan


def whitted_run(rss, export=0.5, writeback=0.004, width=960, height=540, triangles=2_000_000):
    return {
        "peak_rss_mib": rss,
        "mesh_triangles": triangles,
        "width": width,
        "height": height,
        "whitted": {
            "phases": {"export": export, "writeback": writeback, "trace": 1.0},
            "passes": ["Combined", "Whitted Rays"],
        },
    }


def test_medians_skip_runs_without_the_value():
    measurement = Measurement(runs=[{"seconds": 3.0}, {"seconds": 1.0}, {}, {"seconds": 2.0}])
    assert measurement.median(lambda r: r.get("seconds")) == 2.0
    assert Measurement(missing="timed out").median(lambda r: r["seconds"]) is None
    assert Measurement(runs=[whitted_run(100)]).whitted("phases", "export") == 0.5
    assert Measurement(runs=[whitted_run(100)]).whitted("no", "such") is None


def test_memory_and_export_figures():
    whitted = Measurement(runs=[whitted_run(300.0), whitted_run(310.0)])
    null = Measurement(runs=[{"peak_rss_mib": 105.0}])
    # (305 - 105) MiB over 2M triangles.
    assert bytes_per_triangle(whitted, null, 2_000_000) == pytest.approx(200.0 * MIB / 2e6)
    assert bytes_per_triangle(whitted, Measurement(missing="failed"), 10) is None
    assert export_per_million(whitted) == pytest.approx(0.25)


def test_writeback_is_per_pass_and_scaled_to_1920x1080():
    # 4 ms for 2 passes at a quarter of 1920x1080: 2 ms per pass there, 8 ms at full size.
    measurement = Measurement(runs=[whitted_run(1.0)])
    assert writeback_per_hd_pass(measurement) == pytest.approx(0.008)


def test_thread_speedup():
    def trace(seconds):
        return Measurement(runs=[{"whitted": {"phases": {"trace": seconds}}}])

    scaling = {"threads": {"demo": {1: trace(3.0), 2: trace(1.5)}}}
    assert speedup(scaling, "demo", lambda m: m.whitted("phases", "trace")) == 2.0


def test_thread_speedup_is_taken_round_by_round():
    """Runs made in pairs (Suite.render_alternating) give the median of the pairs'
    ratios: a slow spell that slows both runs of a round leaves its ratio alone, where
    the ratio of the medians would mix runs of different rounds."""

    def traces(*seconds):
        return Measurement(runs=[{"whitted": {"phases": {"trace": s}}} for s in seconds])

    # Rounds 2 and 3 ran on a machine twice as slow; each round's ratio is 2.
    scaling = {"threads": {"demo": {1: traces(1.0, 2.0, 2.0), 2: traces(0.5, 1.0, 1.0)}}}
    assert speedup(scaling, "demo", lambda m: m.whitted("phases", "trace")) == 2.0
    # The same medians paired otherwise: ratios 1, 4 and 2.
    scaling = {"threads": {"demo": {1: traces(1.0, 2.0, 2.0), 2: traces(1.0, 0.5, 1.0)}}}
    assert speedup(scaling, "demo", lambda m: m.whitted("phases", "trace")) == 2.0
    scaling = {"threads": {"demo": {1: traces(1.0, 4.0, 2.0), 2: traces(1.0, 1.0, 2.0)}}}
    assert speedup(scaling, "demo", lambda m: m.whitted("phases", "trace")) == 1.0


@pytest.mark.parametrize(
    ("measured", "at_least", "result", "margin"),
    [
        (0.95, True, "pass", "0.05 (6% of the target) to spare"),
        (0.72, True, "**miss**", "missed by 0.18 (20% of the target)"),
        (0.5, False, "**miss**", "missed by 0.4 (400% of the target)"),
        (None, True, "not measured", "—"),
    ],
)
def test_verdict_says_pass_or_miss_and_by_how_much(measured, at_least, result, margin):
    threshold = 0.9 if at_least else 0.1
    target = Target("t", threshold, at_least, "", measured, "somewhere")
    assert verdict(target) == (result, margin)


def test_worst_is_the_minimum_of_at_least_targets_and_the_maximum_of_others():
    pairs = [(2.0, "a"), (None, "b"), (1.0, "c")]
    assert worst(pairs, at_least=True) == (1.0, "c")
    assert worst(pairs, at_least=False) == (2.0, "a")
    assert worst([(None, "b")], at_least=True) == (None, "not measured")


def embree_run(efficiency, stubbed=None, waves=None):
    run = {
        "threads": 2,
        "whitted_rays_per_second": 4e6,
        "whitted_single_ray_rays_per_second": 3e6,
        "embree_rays_per_second": 8e6,
        "efficiency": efficiency,
        "recorded_rays": 1000,
        "camera_packets": True,
        "instances_per_pixel": 0.0004,
    }
    if waves:  # the same render in waves: its rate, gain and efficiency
        run |= {"waves_rays_per_second": waves, "waves_gain": waves / 4e6}
        run |= {"waves_efficiency": waves / 8e6}
    return run | ({"stubbed_rays_per_second": stubbed} if stubbed else {})


def test_a_ray_costs_its_threads_over_the_rate():
    assert per_ray_ns(embree_run(0.5), "embree_rays_per_second") == 250.0
    assert per_ray_ns(embree_run(0.5), "stubbed_rays_per_second") is None


@pytest.mark.parametrize("before", [None, Path("/old/addon")])
def test_raw_embree_details_show_shading_alone_and_the_efficiency_before(before):
    suite = Suite(quick_plan(), "blender", "python", Path("/tmp"), Path("/tmp"), 0.0, before)
    results = SceneResults("demo")
    results.embree["tiny"] = Measurement(runs=[embree_run(0.5, stubbed=8e6, waves=5e6)])
    results.embree_before["tiny"] = Measurement(runs=[embree_run(0.25)])
    lines = embree_details(suite, [results])
    header = next(line for line in lines if line.startswith("| scene | size | camera packets"))
    row = next(line for line in lines if line.startswith("| demo | 96x54 | yes (2,500) | 4.00 |"))
    assert "shading alone (traversal stubbed), Mrays/s" in header
    assert row.count("|") == header.count("|")
    assert "| 8.00 | 8.00 | 0.50 | 5.00 | 1.25x | 0.62 | 1000 |" in row
    assert ("| 0.25 | 2.00x |" in row) == (before is not None)
    # Shading 250 ns and traversal 250 ns a ray (2 threads at 8 Mrays/s each), Whitted 500.
    assert "| demo | 96x54 | 500 | 250 | 250 | 500 | 50% |" in lines


def test_embree_runs_walk_only_the_measurements_made():
    suite = Suite(quick_plan(), "blender", "python", Path("/tmp"), Path("/tmp"), 0.0)
    made, missing = SceneResults("demo"), SceneResults("glass8")
    made.embree["tiny"] = Measurement(runs=[embree_run(0.5)])
    missing.embree["tiny"] = Measurement(missing="timed out")
    walked = list(embree_runs(suite, [made, missing]))
    assert walked == [(made, "tiny", (96, 54), made.embree["tiny"].runs)]


def test_one_thread_and_preset_runs_have_their_table_rows():
    suite = Suite(quick_plan(), "blender", "python", Path("/tmp"), Path("/tmp"), 0.0)
    preset_run = embree_run(0.4, waves=2e6) | {"camera_rays_per_pixel": 5.5}
    preset_run |= {"rays_per_camera_ray": 12.25}
    variants = {
        "one_thread": {"demo": Measurement(runs=[embree_run(0.5, waves=6e6) | {"threads": 1}])},
        "presets": {
            ("distributed", "PREVIEW"): Measurement(runs=[preset_run]),
            ("camera", "FINAL"): Measurement(missing="timed out"),
        },
    }
    lines = embree_variants_section(suite, variants)
    header = next(line for line in lines if line.startswith("| scene | threads | preset"))
    one = next(line for line in lines if line.startswith("| demo | 1 | own |"))
    preset = next(line for line in lines if line.startswith("| distributed | 2 | PREVIEW |"))
    assert one.count("|") == header.count("|") == preset.count("|")
    assert "| 4.00 | 8.00 | 0.50 | 6.00 | 1.50x | 0.75 |" in one
    assert "| 5.50 | 12.25 | 4.00 | 8.00 | 0.40 | 2.00 | 0.50x | 0.25 |" in preset
    assert any(line.startswith("| camera | | FINAL | timed out |") for line in lines)
