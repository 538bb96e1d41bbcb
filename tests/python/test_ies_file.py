"""IES files read as Cycles reads them (addon/export/ies.py), without Blender: the
header, the tilt block, the units, and the symmetries completed to the full circle. The
table is what native shader/ies.h interpolates (tests/native/ies_test.cpp); the light
against Cycles' is tests/blender/test_ies.py."""

import importlib.util
import math
from pathlib import Path

import pytest

PATH = Path(__file__).parents[2] / "addon" / "export" / "ies.py"
SPEC = importlib.util.spec_from_file_location("whitted_ies", PATH)
ies = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(ies)


def lm63(kind, v, h, candela, tilt="TILT=NONE", factors="1.0 1.0 100", multiplier=1.0):
    lines = [
        "IESNA:LM-63-2002",
        "[TEST] a profile",
        tilt,
        f"1 1000 {multiplier:g} {len(v)} {len(h)} {kind} 2 0.1 0.1 0",
        factors,
        " ".join(map(str, v)),
        " ".join(map(str, h)),
        *(" ".join(map(str, row)) for row in candela),
    ]
    return "\n".join(lines) + "\n"


def split(profile):
    """(h in degrees, v in degrees, rows) of a profile's table."""
    table = profile.table
    h_count, v_count = int(table[0]), int(table[1])
    h = [math.degrees(a) for a in table[2 : 2 + h_count]]
    v = [math.degrees(a) for a in table[2 + h_count : 2 + h_count + v_count]]
    values = table[2 + h_count + v_count :]
    rows = [values[i * v_count : (i + 1) * v_count] for i in range(h_count)]
    assert len(values) == h_count * v_count
    return h, v, rows


def test_a_round_profile_becomes_a_full_circle_of_one_row():
    h, v, rows = split(ies.parse(lm63(1, [0, 45, 90], [0], [[100, 50, 0]])))
    assert h == pytest.approx([0, 360])
    assert v == pytest.approx([0, 45, 90])
    assert rows[0] == rows[1]
    # Candela in Cycles' lamp units: 4 pi / 177.83 a candela.
    assert rows[0] == pytest.approx([100 * 0.0706650768394, 50 * 0.0706650768394, 0], rel=1e-6)


def test_the_multipliers_scale_every_value():
    text = lm63(1, [0, 90], [0], [[10, 10]], factors="0.5 2.0 100", multiplier=3.0)
    _, _, rows = split(ies.parse(text))
    assert rows[0][0] == pytest.approx(10 * 3.0 * 0.5 * 2.0 * ies.CANDELA_TO_LAMP, rel=1e-6)


def test_a_quadrant_is_mirrored_to_a_half_then_to_the_circle():
    h_in = [0, 30, 60, 90]
    h, _, rows = split(ies.parse(lm63(1, [0, 90], h_in, [[i, i] for i in range(4)])))
    assert h == pytest.approx(list(range(0, 361, 30)))
    # h and 360 - h, and h and 180 - h, carry the same row.
    firsts = [r[0] / ies.CANDELA_TO_LAMP for r in rows]
    assert firsts == pytest.approx([0, 1, 2, 3, 2, 1, 0, 1, 2, 3, 2, 1, 0], abs=1e-5)


def test_a_half_stored_from_90_to_270_is_turned_then_mirrored():
    h, _, rows = split(ies.parse(lm63(1, [0, 90], [90, 180, 270], [[1, 1], [2, 2], [3, 3]])))
    assert h == pytest.approx([0, 90, 180, 270, 360])
    firsts = [r[0] / ies.CANDELA_TO_LAMP for r in rows]
    assert firsts == pytest.approx([1, 2, 3, 2, 1], abs=1e-5)


def test_a_circle_without_its_360_entry_is_closed():
    h, _, rows = split(ies.parse(lm63(1, [0, 90], [0, 120, 240], [[1, 1], [2, 2], [3, 3]])))
    assert h == pytest.approx([0, 120, 240, 360])
    assert rows[-1] == rows[0]


def test_a_type_b_file_is_read_in_type_c_layout():
    v_in, h_in = [-90, 0, 90], [0, 45, 90]
    candela = [[1, 2, 3], [4, 5, 6], [7, 8, 9]]
    profile = ies.parse(lm63(2, v_in, h_in, candela))
    assert profile.type_b
    h, v, rows = split(profile)
    # The file's vertical angles -90..90 become 0..180 horizontal, closed at 360; its
    # horizontal 0..90 are mirrored to 0..180 vertical.
    assert h == pytest.approx([0, 90, 180, 360])
    assert v == pytest.approx([0, 45, 90, 135, 180])
    assert len(rows) == 4 and all(len(r) == 5 for r in rows)


def test_commas_and_an_included_tilt_block_are_read_as_cycles_reads_them():
    text = lm63(1, [0, 90], [0], [[7, 3]], tilt="TILT=INCLUDE\n1\n2\n0 90\n1.0 0.5")
    _, _, rows = split(ies.parse(text.replace(" 3\n", ", 3\n")))
    assert [r / ies.CANDELA_TO_LAMP for r in rows[0]] == pytest.approx([7, 3], rel=1e-6)


@pytest.mark.parametrize(
    "text",
    [
        "",
        "no tilt line at all",
        lm63(3, [0, 90], [0], [[1, 1]]),  # type A: Cycles reads none
        lm63(1, [0, 90], [0], [[1]]),  # cut short
        lm63(1, [5, 90], [0], [[1, 1]]),  # vertical angles from 5
        lm63(1, [0, 90], [10, 20], [[1, 1], [1, 1]]),  # horizontal from 10
    ],
)
def test_what_cycles_refuses_gives_no_table(text):
    assert ies.parse(text) is None
