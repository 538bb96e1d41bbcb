"""IES photometric files (IESNA LM-63) as the IES Texture's profile table.

Read as Cycles reads them (its IESFile): everything before the TILT line is ignored,
commas count as spaces, a TILT=INCLUDE block is skipped, and the numbers are read in
the file's order; type C files (photometric type 1) and type B files (type 2) are
completed to the full sphere of their symmetries; type A files, and any file Cycles
refuses, give no table. The table is the one native shader/ies.h interpolates:

    [h_count, v_count, *h_angles, *v_angles, *intensities (h_count rows of v_count)]

angles in radians, intensities in Cycles' lamp units. Pure functions of the text:
nothing here reads Blender."""

import math
import re
from dataclasses import dataclass

import numpy as np

# IES intensities are photometric (candela, lumen per steradian). Cycles turns them into
# its lamp units with the luminous efficacy of D65 light, 177.83 lm/W, times 4 pi, the
# solid angle its lamp strengths are spread over: 4 pi / 177.83 per candela.
CANDELA_TO_LAMP = 0.0706650768394

_TYPE_C, _TYPE_B = 1, 2
_F32 = np.float32
_DEGREES = _F32(_F32(math.pi) / _F32(180.0))  # Cycles converts in float

# strtod's and strtol's numbers (after leading white space).
_DOUBLE = re.compile(
    r"\s*([+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf(?:inity)?|nan))", re.IGNORECASE
)
_LONG = re.compile(r"\s*([+-]?\d+)")


class _Numbers:
    """The numbers of a text, read one at a time as C's strtod and strtol read them
    (an integer read stops at a decimal point; the next read starts there)."""

    def __init__(self, text, at):
        self.text = text
        self.at = at
        self.failed = False

    def _read(self, pattern, convert):
        match = pattern.match(self.text, self.at) if not self.failed else None
        if match is None:
            self.failed = True
            return 0
        self.at = match.end()
        return convert(match.group(1))

    def double(self):
        return self._read(_DOUBLE, float)

    def long(self):
        return self._read(_LONG, int)


@dataclass(frozen=True)
class Profile:
    table: list  # the floats native shader/ies.h reads
    type_b: bool  # a type B file (turned into type C's layout)


def parse(text):
    """The Profile of IES file text, or None where Cycles reads no profile from it."""
    text = text.replace(",", " ")
    tilt = text.find("\nTILT=")
    if tilt < 0:
        return None
    if text.startswith("\nTILT=INCLUDE", tilt):
        numbers = _Numbers(text, tilt + len("\nTILT=INCLUDE"))
        numbers.double()  # lamp-to-luminaire geometry
        for _ in range(2 * numbers.long()):  # the tilt angles and their factors
            numbers.double()
        at = numbers.at
    else:
        at = text.find("\n", tilt + 1)  # the rest of the TILT line
        if at < 0:
            return None
    numbers = _Numbers(text, at + 1)
    numbers.long()  # number of lamps
    numbers.double()  # lumens per lamp
    factor = numbers.double()  # candela multiplier
    v_count = numbers.long()
    h_count = numbers.long()
    kind = numbers.long()  # photometric type
    if kind not in (_TYPE_B, _TYPE_C) or numbers.failed:
        return None
    numbers.long()  # units of the dimensions
    for _ in range(3):  # width, length, height
        numbers.double()
    factor *= numbers.double()  # ballast factor
    factor *= numbers.double()  # ballast-lamp photometric factor
    numbers.double()  # input watts
    factor *= CANDELA_TO_LAMP
    if v_count <= 0 or h_count <= 0:
        return None
    v = [_F32(numbers.double()) for _ in range(v_count)]
    h = [_F32(numbers.double()) for _ in range(h_count)]
    rows = [[_F32(factor * numbers.double()) for _ in range(v_count)] for _ in range(h_count)]
    if numbers.failed:
        return None
    done = _type_b(h, v, rows) if kind == _TYPE_B else _type_c(h, v, rows)
    if done is None:
        return None
    h, v, rows = done
    table = [float(len(h)), float(len(v))]
    table += [float(_F32(a) * _DEGREES) for a in h]
    table += [float(_F32(a) * _DEGREES) for a in v]
    for row in rows:
        table += [float(x) for x in row]
    return Profile(table, kind == _TYPE_B)


def _mirror_half(angles, centre):
    """Angles [centre, ...] mirrored about `centre` into [2 centre - last, ..., last]:
    the order in which a half measured from the centre is completed."""
    return [_F32(centre - a) for a in reversed(angles[1:])] + [_F32(centre + a) for a in angles]


def _type_b(h, v, rows):
    """A type B file's angles turned into type C's layout (its horizontal angles become
    the vertical ones, as Cycles does), each half completed by symmetry; None where
    Cycles refuses it."""
    # Swap the axes: each of the file's vertical angles becomes a row.
    rows = [[rows[j][i] for j in range(len(h))] for i in range(len(v))]
    h, v = v, h
    if h[-1] != 90.0:
        return None
    if h[0] == 0.0:  # 0..90 stands for 90..180: mirror it about 90
        order = list(range(len(h) - 1, 0, -1)) + list(range(len(h)))
        h = _mirror_half(h, _F32(90.0))
        rows = [rows[i] for i in order]
    elif h[0] == -90.0:
        h = [_F32(a + _F32(90.0)) for a in h]
    # The full circle, 360 repeating 0, for the interpolation to wrap.
    h = [*h, _F32(360.0)]
    rows = [*rows, rows[0]]
    if v[-1] != 90.0:
        return None
    if v[0] == 0.0:
        v = _mirror_half(v, _F32(90.0))
        # Cycles pairs the mirrored angles with the intensities one entry further on
        # (the first mirrored angle, 0, takes the value at the last angle but one):
        # followed, so that a type B file lights as in Cycles.
        rows = [list(reversed(row[:-1])) + list(row) for row in rows]
    elif v[0] == -90.0:
        v = [_F32(a + _F32(90.0)) for a in v]
    return h, v, rows


def _mirrored_past_last(h, rows):
    """Angles `h` and their `rows` continued past the last angle by their mirror image
    about it (2 last - a, in Cycles' float)."""
    turn = _F32(2.0 * h[-1])
    return h + [_F32(turn - a) for a in reversed(h[:-1])], rows + list(reversed(rows[:-1]))


def _type_c(h, v, rows):
    """A type C file's horizontal angles completed to the full circle by its symmetry
    (one angle: round; a quadrant; a half), as Cycles does; None where it refuses it."""
    if h[0] == 90.0:  # stored from 90 to 270: the same as 0 to 180
        h = [_F32(a - _F32(90.0)) for a in h]
    if h[0] != 0.0:
        return None
    if len(h) == 1:
        h, rows = [*h, _F32(360.0)], [*rows, rows[0]]
    if h[-1] == 90.0:  # one quadrant: mirrored to a half
        h, rows = _mirrored_past_last(h, rows)
    if h[-1] == 180.0:  # a half: mirrored to the full circle
        h, rows = _mirrored_past_last(h, rows)
    if h[-1] != 360.0:
        # A file that leaves out 360 (as the first angle) is mended where its spacing shows
        # the gap is one step.
        gap = _F32(_F32(360.0) - h[-1])
        if len(h) < 2 or gap not in (_F32(h[-1] - h[-2]), _F32(h[1] - h[0])):
            return None
        h, rows = [*h, _F32(360.0)], [*rows, rows[0]]
    if v[0] == 90.0:
        if v[-1] != 180.0:
            return None
    elif v[0] != 0.0:
        return None
    return h, v, rows
