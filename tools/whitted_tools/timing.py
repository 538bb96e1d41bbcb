"""Clocks and memory of the process a benchmark runs in."""

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
