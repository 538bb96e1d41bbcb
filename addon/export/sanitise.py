"""Bad geometry repaired or dropped before it reaches the native module (which refuses
non-finite arrays): triangles with a NaN or infinite vertex, or one beyond
MAX_COORDINATE, or of zero area are dropped; zero-length or NaN corner normals become
the face normal. The per-triangle arithmetic runs in blocks of _BLOCK triangles, so its
temporaries stay a few megabytes however large the mesh."""

from dataclasses import dataclass

import numpy as np

from ..native import load_native

# Object-space coordinates beyond this magnitude are dropped with their triangles.
# The core works in float32: there the spacing of representable values at 1e7 is
# 1 unit (a metre-scale detail is gone), and the triangle normal it computes is a
# cross product of edges, |e|^2, whose squared length |e|^4 must stay below
# FLT_MAX (3.4e38): at 1e7 it is 1e28, ten orders of magnitude of margin for the
# instance's own scale. No sane model needs more than 10,000 km from its origin.
# (native/src/core/limits.h lists it with the core's own bounds.)
MAX_COORDINATE = 1.0e7


# Triangles per block of `sanitise`'s arithmetic: about 150 bytes of temporaries a
# triangle, so 10 MB a block.
_BLOCK = 1 << 16


@dataclass(frozen=True)
class Sanitised:
    """What `sanitise` removed or repaired in one mesh."""

    nonfinite: int = 0  # triangles dropped: a vertex is NaN or infinite
    distant: int = 0  # triangles dropped: a vertex is beyond MAX_COORDINATE
    zero_area: int = 0  # triangles dropped: their edges' cross product is 0 (float64)
    normals: int = 0  # corner normals of zero length or non-finite, set to the face normal

    def __add__(self, other):
        return Sanitised(
            self.nonfinite + other.nonfinite,
            self.distant + other.distant,
            self.zero_area + other.zero_area,
            self.normals + other.normals,
        )

    def __bool__(self):
        return any((self.nonfinite, self.distant, self.zero_area, self.normals))

    def describe(self):
        """The counts as a phrase, e.g. '3 triangles with NaN/Inf vertices skipped'."""
        dropped = [
            f"{count} {what if count == 1 else what.replace('triangle', 'triangles')}"
            for count, what in (
                (self.nonfinite, "triangle with NaN/Inf vertices"),
                (self.distant, f"triangle with vertices beyond {MAX_COORDINATE:g}"),
                (self.zero_area, "zero-area triangle"),
            )
            if count
        ]
        parts = [f"{', '.join(dropped)} skipped"] if dropped else []
        if self.normals:
            parts.append(f"{self.normals} zero-length or NaN normal(s) set to the face normal")
        return "; ".join(parts)


def sanitise(positions, corners, normals):
    """Which triangles to keep, and what was wrong; repairs `normals` in place.

    Dropped: triangles with a vertex that is NaN/Inf or beyond MAX_COORDINATE, and
    those of zero area (the cross product of two edges, in float64, is exactly 0:
    collinear or repeated corners; they cannot be hit, and have no normal). Slivers
    of non-zero area are kept: the core's watertight intersection handles them.
    A corner normal of zero length or with NaN/Inf is replaced by the face normal.
    """
    count = len(corners)
    nonfinite_vertex = ~np.isfinite(positions).all(axis=1)
    # NaN compares False, so a NaN vertex is only "non-finite", never "distant".
    distant_vertex = (np.abs(positions) > MAX_COORDINATE).any(axis=1)
    if nonfinite_vertex.any() or distant_vertex.any():  # rare: per triangle only then
        nonfinite = nonfinite_vertex[corners].any(axis=1)
        distant = distant_vertex[corners].any(axis=1) & ~nonfinite
        keep = ~(nonfinite | distant)
    else:
        nonfinite = distant = np.zeros(0, dtype=bool)
        keep = np.ones(count, dtype=bool)
    del nonfinite_vertex, distant_vertex
    zero_area = repaired = 0
    # Triangles with a NaN/Inf vertex (already dropped) give NaN products: not zero.
    with np.errstate(invalid="ignore", over="ignore"):
        for start in range(0, count, _BLOCK):
            block = slice(start, start + _BLOCK)
            zero = _zero_area(positions, corners[block]) & keep[block]
            zero_area += int(np.count_nonzero(zero))
            keep[block] &= ~zero
            if normals is not None:
                repaired += _repair(normals[block], positions, corners[block], keep[block])
    sanitised = Sanitised(
        nonfinite=int(np.count_nonzero(nonfinite)),
        distant=int(np.count_nonzero(distant)),
        zero_area=zero_area,
        normals=repaired,
    )
    return keep, sanitised


def _zero_area(positions, corners):
    """bool[k]: whether the cross product of each triangle's edges (p1 - p0, p2 - p0),
    in float64, is exactly 0 (in the native core: numpy's temporaries took 0.12 s a
    million triangles)."""
    return load_native().zero_area_triangles(positions, corners)


def usable(normals):
    """bool[...]: which normals (last axis xyz) have a finite, non-zero float32 length."""
    squared = np.einsum("...k,...k->...", normals, normals)
    # NaN fails both comparisons; an infinite component (or overflow) the second.
    return (squared > 0.0) & (squared < np.inf)


def _repair(normals, positions, corners, keep):
    """Set the unusable corner normals of kept triangles (which have non-zero area) to
    their face normal; how many."""
    rows, columns = np.nonzero(~usable(normals) & keep[:, None])
    if len(rows) == 0:
        return 0
    points = positions[corners[rows]].astype(np.float64)
    face = np.cross(points[:, 1] - points[:, 0], points[:, 2] - points[:, 0])
    normals[rows, columns] = face / np.linalg.norm(face, axis=1)[:, None]
    return len(rows)


def compact(positions, corners):
    """Only the vertices `corners` uses (so no NaN vertex stays), renumbered, and the
    mask of the vertices kept."""
    used = np.zeros(len(positions), dtype=bool)
    used[corners] = True
    # Unused vertices get -1, never read: every corner's vertex is used.
    renumber = np.cumsum(used, dtype=np.int64) - 1
    return (
        np.ascontiguousarray(positions[used]),
        np.ascontiguousarray(renumber[corners], dtype=np.uint32),
        used,
    )
