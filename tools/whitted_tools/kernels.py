"""The two kernels compared on files we did not make (whitted_tools compare-kernels writes
one JSON per file and configuration): a Markdown table per configuration, for
docs/notes/waves.md (whitted_tools compare-kernels-table prints it)."""

import statistics

from whitted_tools.pages import num


def configuration(result):
    """How a file was rendered: its preset (or its own controls) and the passes kept."""
    preset = result.get("preset") or "the file's own controls"
    passes = ", ".join(result.get("passes") or []) or "none"
    return f"{preset}, passes: {passes}"


def kernel_table(results):
    """One row per configuration: files, whether the rays were equal on all, the largest
    difference, the pixels over 1e-4, and the spread of the recursion / waves time
    ratios (above 1: the waves are faster)."""
    lines = [
        "| configuration | files | rays by type equal | largest difference (relative) | "
        "pixels over 1e-4 | recursion / waves time: min, median, max | faster in waves |",
        "|---|---:|---|---:|---:|---|---:|",
    ]
    groups = {}
    for result in results:
        groups.setdefault(configuration(result), []).append(result)
    for name, group in groups.items():
        ratios = [r["speed_ratio"] for r in group]
        equal = sum(r["rays_equal"] for r in group)
        worst = max(group, key=lambda r: r["max_relative"])
        lines.append(
            f"| {name} | {len(group)} | {equal} of {len(group)} | "
            f"{worst['max_relative']:.2g} ({worst['file']}) | "
            f"{sum(r['pixels_over_1e-4'] for r in group)} | "
            f"{num(min(ratios), 3)}, {num(statistics.median(ratios), 3)}, "
            f"{num(max(ratios), 3)} | {sum(x > 1.0 for x in ratios)} of {len(group)} |"
        )
    return [*lines, ""]
