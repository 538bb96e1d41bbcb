"""docs/PERFORMANCE.md from the suite's measurements (its plots: perf.plots)."""

import subprocess

from whitted_tools.metrics import mean_absolute_difference
from whitted_tools.pages import (
    command_line,
    machine_lines,
    num,
    ratio,
    ratio_text,
    relative_link,
    scale,
    seconds_text,
    size_label,
)
from whitted_tools.perf.figures import (
    beyond_blender_mib,
    bvh_seconds,
    bytes_per_triangle,
    cell,
    export_per_million,
    mesh_triangles,
    per_ray_ns,
    rays_per_second,
    repeats_note,
    speedup,
    targets,
    verdict,
    writeback_per_hd_pass,
)
from whitted_tools.perf.measure import scene_image
from whitted_tools.perf.plan import ENGINE_NAMES, MAIN_SCENES, PHASES, RAY_TYPES
from whitted_tools.plots import plt


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
            scale(writeback_per_hd_pass(results.whitted[label]), 1000.0), 2
        ),
    }
    for ray in (*RAY_TYPES, "total"):
        rows[f"{ray} rays (M/s over the trace)"] = lambda label, ray=ray: num(
            rays_per_second(results.whitted[label], ray), 2
        )
    rows |= {
        "total rays (millions)": lambda label: num(
            scale(results.whitted[label].whitted("rays", "total"), 1e-6), 2
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
        (ENGINE_NAMES[engine], scene_image(suite, results.name, engine, plan.small))
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


def embree_variants_section(suite, variants):
    """Raw Embree on one thread and at the quality presets (measure_embree_variants)."""
    lines = [
        f"Raw Embree beyond the table above, at {size_label(suite.plan.small)}: the main "
        "scenes on one thread (Blender's render threads fixed at 1, the bare loop on one "
        "thread too), and the scenes of distributed ray tracing (perf_scenes.py: "
        "distributed, rough metal, plastic and frosted glass with an emissive panel; "
        "camera, a lens at f/1.4 and a moving ball) at the quality presets "
        "(properties/presets.py: adaptive anti-aliasing, glossy, light and emitter "
        "samples, depth), on all threads. The same script, the same rounds; rates in "
        "Mrays/s.",
        "",
        "| scene | threads | preset | camera rays per pixel | rays per camera ray | "
        "Whitted (recursion) | raw Embree | efficiency | in waves | waves gain | "
        "efficiency in waves |",
        "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    rows = [((name, None), m) for name, m in variants["one_thread"].items()]
    rows += list(variants["presets"].items())
    for (name, preset), measurement in rows:
        if not measurement.runs:
            lines.append(f"| {name} | | {preset or 'own'} | {measurement.missing} |||||||")
            continue
        run = measurement.runs[0]
        lines.append(
            f"| {name} | {run.get('threads')} | {preset or 'own'} | "
            f"{num(run.get('camera_rays_per_pixel'), 2)} | "
            f"{num(run.get('rays_per_camera_ray'), 2)} | "
            f"{num(scale(run.get('whitted_rays_per_second'), 1e-6), 2)} | "
            f"{num(scale(run.get('embree_rays_per_second'), 1e-6), 2)} | "
            f"{num(run.get('efficiency'), 2)} | "
            f"{num(scale(run.get('waves_rays_per_second'), 1e-6), 2)} | "
            f"{ratio_text(run.get('waves_gain'))} | {num(run.get('waves_efficiency'), 2)} |"
        )
    return [*lines, ""]


def comparison_section(suite, scenes, variants):
    lines = [
        "## Side by side: ratios",
        "",
        "Each row is one scene at one size, measured in the same run. Efficiency is "
        "Whitted's rays per second over raw Embree's on the same rays "
        "(whitted_tools perf-raw-embree: a bare single-ray loop over the recorded queries). "
        "POV-Ray is POV-Ray 3.7 through Blender 3.4's bundled render_povray add-on "
        "(whitted_tools perf-povray matches the settings): its end-to-end time in Blender, "
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
        *embree_variants_section(suite, variants),
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
        ours = scene_image(suite, results.name, "WHITTED", suite.plan.small)
        cells = []
        for engine in ("POVRAY", "CYCLES"):
            theirs = scene_image(suite, results.name, engine, suite.plan.small)
            if ours is None or theirs is None or not (ours.exists() and theirs.exists()):
                cells.append("no image")
                continue
            difference = mean_absolute_difference(plt.imread(ours), plt.imread(theirs))
            if difference is None:
                cells.append("sizes differ")
            elif difference > SAME_PICTURE:
                cells.append(f"**{difference:.3f}: a different picture**")
            else:
                cells.append(f"{difference:.3f}")
        lines.append(f"| {results.name} | {' | '.join(cells)} |")
    return [*lines, ""]


def embree_details(suite, scenes):
    before = suite.before is not None
    lines = [
        "Raw Embree in detail (Mrays/s, one process each, all threads). Whitted sends the "
        "camera rays of a block of pixels to Embree as one packet (at 2x2 samples 4 pixels, "
        "16 rays: CameraSampler::first_hits) where the scene suits packets: the "
        "camera packets column says whether it did, and how many pixels there are per "
        "instance in view (packets from 500 up: sampler.h, choose_packets). "
        "Whitted without packets is the same render with each camera ray its own query "
        "(Settings.packets off), in the same process: the packet gain is the ratio of the "
        "two (1x where no packets were chosen), taken round by round like the efficiency "
        "(the median of the rounds' ratios; the rates are the rounds' medians). Shading alone "
        "is the recorded pixels rendered again with every query answered from the "
        "recording instead of Embree (traversal stubbed out: RenderJob.replay()), on the "
        "rays raw Embree traces. Whitted is the recursive kernel, the reference; in waves "
        "is the same render traced in waves (Settings.waves, the default: the add-on's "
        "Trace in Waves; docs/notes/waves.md), in the same rounds: its waves gain is "
        "over the recursion, its efficiency over raw Embree, each the median of the "
        "rounds' ratios.",
        "",
    ]
    if before:
        lines += [
            f"Before: the same raw Embree runs, in the same suite run, with the add-on in "
            f"`{suite.before}`{_commit_of(suite.before)}; after: this checkout's.",
            "",
        ]
    header = (
        "| scene | size | camera packets (pixels per instance) | Whitted | Whitted without "
        "packets | packet gain | raw Embree | shading alone (traversal stubbed), Mrays/s "
        "| efficiency | in waves | waves gain | efficiency in waves | rays recorded |"
    )
    columns = 13
    if before:
        header += " efficiency before | after / before |"
        columns += 2
    lines += [header, "|---|---|" + "---:|" * (columns - 2)]
    for results in scenes:
        for label, size in suite.plan.sizes:
            embree = results.embree[label]
            if not embree.runs:
                gap = "|" * (columns - 3)
                lines.append(f"| {results.name} | {size_label(size)} | {embree.missing} {gap}")
                continue
            run = embree.runs[0]
            packets = run.get("whitted_rays_per_second")
            single = run.get("whitted_single_ray_rays_per_second")
            efficiency = run.get("efficiency")
            density = run.get("instances_per_pixel")
            chosen = "yes" if run.get("camera_packets", True) else "no"
            chosen += f" ({1 / density:,.0f})" if density else ""
            row = (
                f"| {results.name} | {size_label(size)} | {chosen} | "
                f"{num(scale(packets, 1e-6), 2)} | {num(scale(single, 1e-6), 2)} | "
                f"{ratio_text(run.get('packet_gain') or ratio(packets, single))} | "
                f"{num(scale(run.get('embree_rays_per_second'), 1e-6), 2)} | "
                f"{num(scale(run.get('stubbed_rays_per_second'), 1e-6), 2)} | "
                f"{num(efficiency, 2)} | "
                f"{num(scale(run.get('waves_rays_per_second'), 1e-6), 2)} | "
                f"{ratio_text(run.get('waves_gain'))} | {num(run.get('waves_efficiency'), 2)} | "
                f"{run.get('recorded_rays', '—')} |"
            )
            if before:
                then = results.embree_before[label]
                old = then.median(lambda r: r.get("efficiency"))
                shown = cell(then, num(old, 2) if old is not None else None)
                row += f" {shown} | {ratio_text(ratio(efficiency, old))} |"
            lines.append(row)
    return [*lines, "", *cost_per_ray(suite, scenes), *pixel_identity(suite, scenes)]


def embree_runs(suite, scenes):
    """(scene results, size label, size, runs) of every raw Embree measurement made."""
    for results in scenes:
        for label, size in suite.plan.sizes:
            runs = results.embree[label].runs
            if runs:
                yield results, label, size, runs


def pixel_identity(suite, scenes):
    """Whether the raw Embree runs' images are the same to the bit: packets on against
    off, and (with --before) this build's against the other's (SHA-256 of the float
    pixels, perf_raw_embree.py)."""
    before = suite.before is not None
    lines = [
        "Pixel identity, from the same raw Embree runs: the SHA-256 of each render's float "
        "RGBA pixels. Embree's packet and single-ray queries may pick different faces "
        "where two tie: coplanar faces, or a ray through the edge two faces share (a "
        "packet is a block of pixels fixed in the image, so never another tiling's); so a "
        "before build that chose or grouped packets otherwise differs there too. A before "
        "build older than an intended change of the image (a material fixed to match "
        "Cycles, say: `git log` between the two commits) differs for that reason.",
        "",
        "| scene | size | packets on = off |" + (" after = before |" if before else ""),
        "|---|---|---|" + ("---|" if before else ""),
    ]

    def same(a, b):
        return "—" if a is None or b is None else ("same" if a == b else "**differs**")

    for results, label, size, runs in embree_runs(suite, scenes):
        digest = runs[0].get("image_sha256")
        row = f"| {results.name} | {size_label(size)} | "
        row += f"{same(digest, runs[0].get('single_ray_image_sha256'))} |"
        if before:
            then = results.embree_before[label].runs
            row += f" {same(digest, then[0].get('image_sha256') if then else None)} |"
        lines.append(row)
    return [*lines, ""]


def cost_per_ray(suite, scenes):
    """A ray's cost split into shading and traversal, from the raw Embree runs."""
    lines = [
        "A ray's cost in nanoseconds per thread, from the same runs: Whitted's is 1 over "
        "its rate (all its rays, packets on), shading's 1 over the stubbed rate, "
        "traversal's 1 over raw Embree's (both on the recorded rays), each times the "
        "threads. Shading + traversal near Whitted's says the two account for its time.",
        "",
        "| scene | size | Whitted (ns/ray) | shading alone (ns/ray) | traversal, raw Embree "
        "(ns/ray) | shading + traversal (ns/ray) | shading's share |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for results, _, size, runs in embree_runs(suite, scenes):
        ns = {
            key: per_ray_ns(runs[0], key)
            for key in (
                "whitted_rays_per_second",
                "stubbed_rays_per_second",
                "embree_rays_per_second",
            )
        }
        shading, traversal = ns["stubbed_rays_per_second"], ns["embree_rays_per_second"]
        both = None if shading is None or traversal is None else shading + traversal
        lines.append(
            f"| {results.name} | {size_label(size)} | "
            f"{num(ns['whitted_rays_per_second'], 0)} | {num(shading, 0)} | "
            f"{num(traversal, 0)} | {num(both, 0)} | "
            f"{num(scale(ratio(shading, both), 100.0), 0, '%')} |"
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
                f"{num(scale(measurement.whitted('rays_per_second'), 1e-6), 2)} |"
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
            f"{num(scale(measurement.whitted('phases', 'writeback'), 1000.0), 2)} | "
            f"{num(scale(writeback_per_hd_pass(measurement), 1000.0), 2)} | "
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
            f"| {depth} | {num(scale(measurement.whitted('rays', 'total'), 1e-6), 2)} | "
            f"{num(scale(measurement.whitted('rays', 'reflection'), 1e-6), 2)} | "
            f"{num(scale(measurement.whitted('rays', 'refraction'), 1e-6), 2)} | "
            f"{num(measurement.whitted('depth_limited'), 0)} | "
            f"{seconds_text(measurement.whitted('phases', 'trace'))} | "
            f"{num(scale(measurement.whitted('rays_per_second'), 1e-6), 2)} |"
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


def targets_section(suite, scenes, scaling, variants):
    lines = [
        "## Targets",
        "",
        "| target | threshold | measured | where | result | margin |",
        "|---|---:|---:|---|---|---|",
    ]
    for target in targets(suite, scenes, scaling, variants):
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
        "FILE.blend --python tools/whitted_tools/__main__.py -- perf-render` process "
        "(Blender 3.4; the `bpy` rows use the Blender 5.0 module); tables give the median "
        "of the repeats: Whitted "
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
        "- **Threads**: Blender's render threads fixed at 1 (`--threads 1`) against 2 "
        "(`--threads 2`), the two runs of each repeat one after the other; the speed-up "
        "is the 1-thread trace time over the 2-thread one, the median of the repeats' "
        "ratios (engine total and end to end shown too: export is single-threaded "
        "Python); the times are the medians.",
        "- **Raw Embree**: whitted_tools perf-raw-embree (one process per scene and size, its "
        "own repeats, as rounds: a render with packets, one without, the bare Embree loop "
        "and the replay side by side; the efficiency is the median of the rounds' Whitted "
        "over Embree ratios). **Shading alone**: in the same process, the recorded pixels rendered "
        "again with every query answered from the recording (RenderJob.replay(): the "
        "kernel unchanged, traversal stubbed out), on the rays raw Embree traces. "
        "**Before** (--before ADDON_DIR): the same script run with that add-on, which "
        "Blender finds through BLENDER_USER_SCRIPTS (a folder linking it as `whitted`).",
        "- **POV-Ray**: whitted_tools perf-povray `configure(scene)` then `render(scene, "
        "image)`: end to end is its `render_seconds` (the wall time of the add-on's "
        "`bpy.ops.render.render`: export, POV-Ray, reading the image back), POV-Ray's own "
        "trace time its `povray_seconds` (the Trace Time POV-Ray reports).",
        "",
    ]


def page(suite, args, argv, scenes, scaling, variants, elapsed):
    page_dir = args.out.resolve().parent

    def image_rel(path):
        return relative_link(path, page_dir)

    versions = sorted(
        {run["blender"] for m in suite.results.values() for run in m.runs if "blender" in run}
    )
    lines = [
        "# Performance",
        "",
        "Generated by `python -m whitted_tools bench-performance` (issue 7's suite); do not "
        "edit by hand (the explanation of the misses comes from the --notes files). "
        "Command, from the repository root:",
        "",
        f"    {command_line('bench-performance', argv)}",
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
        *targets_section(suite, scenes, scaling, variants),
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
    lines += comparison_section(suite, scenes, variants)
    lines += ["## Scenes", ""]
    for results in scenes:
        lines += scene_section(suite, results, image_rel)
    lines += scaling_section(suite, scaling, image_rel)
    lines += method_lines(suite.plan)
    if suite.problems:
        lines += ["## Runs that failed, timed out or were skipped", ""]
        lines += [f"- {problem}" for problem in suite.problems]
        lines.append("")
    return lines


def _commit_of(directory):
    """ " (commit abc1234 of 2026-12-01)" when `directory` is in a git checkout, else ""."""
    described = subprocess.run(
        ["git", "-C", str(directory), "log", "-1", "--format=%h of %cs"],
        capture_output=True,
        text=True,
        check=False,
    )
    return f" (commit {described.stdout.strip()})" if described.returncode == 0 else ""
