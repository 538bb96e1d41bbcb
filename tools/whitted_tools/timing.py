"""Clocks and memory of the process a benchmark runs in, and the statistics every
benchmark page takes of its repeats: medians and paired ratios, each defined here once."""

import resource
import statistics
import time


def progress(text):
    """A progress line with the time of day, flushed at once (a long run's log)."""
    print(f"[{time.strftime('%H:%M:%S')}] {text}", flush=True)


def peak_rss_mib():
    """Peak resident memory of this process so far, MiB (ru_maxrss is KiB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def timed(function, *args, **kwargs):
    """(function's result, wall seconds it took)."""
    started = time.perf_counter()
    result = function(*args, **kwargs)
    return result, time.perf_counter() - started


def median_or_none(values):
    """The median of the values that are not None; None when there are none."""
    known = [value for value in values if value is not None]
    return statistics.median(known) if known else None


def paired_ratios(numerators, denominators):
    """Ratios of timings taken in pairs (the same repetition of an interleaved run), so a
    machine whose speed drifts between repetitions moves both sides of each ratio alike."""
    numerators, denominators = list(numerators), list(denominators)
    if len(numerators) != len(denominators) or not numerators:
        raise ValueError("paired ratios need the same number of timings on each side, not 0")
    return [n / d for n, d in zip(numerators, denominators, strict=True)]


def paired_median(numerators, denominators):
    """The median of the paired ratios: the one figure a benchmark quotes for them."""
    return statistics.median(paired_ratios(numerators, denominators))


def spread_text(values):
    """'median [min..max]' of the values, three decimals: a figure with its spread."""
    values = sorted(values)
    return f"{statistics.median(values):.3f} [{values[0]:.3f}..{values[-1]:.3f}]"
