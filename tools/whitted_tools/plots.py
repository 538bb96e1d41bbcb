"""matplotlib for the pages: files only (no display), and the look the plots share."""

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt

DPI = 90


def save(figure, path, dpi=DPI):
    figure.tight_layout()
    figure.savefig(path, dpi=dpi)
    plt.close(figure)


def plot_series(axis, xs, ys, positive=False, **style):
    """Plot the (x, y) pairs whose y is known (and above 0 when positive: log axes)."""
    points = [(x, y) for x, y in zip(xs, ys, strict=True) if y is not None]
    points = [(x, y) for x, y in points if y > 0.0 or not positive]
    if points:
        axis.plot(*zip(*points, strict=True), **style)


def dress(axis, title, xlabel, ylabel, log=True):
    """Title, axis labels, log scales (when log) and the legend of one plot."""
    if log:
        axis.set_xscale("log")
        axis.set_yscale("log")
    axis.set_xlabel(xlabel)
    axis.set_ylabel(ylabel)
    axis.set_title(title)
    axis.legend(fontsize=8)
