"""whitted_tools.timing without Blender: the paired ratios the benchmark pages quote."""

import pytest
from whitted_tools.timing import paired_ratios, spread_text


def test_paired_ratios_divide_within_each_repetition_and_show_their_spread():
    # The machine slows down by half in the second repetition: each pair's ratio holds.
    ratios = paired_ratios([1.0, 1.5, 0.8], [2.0, 3.0, 1.0])
    assert ratios == pytest.approx([0.5, 0.5, 0.8])
    assert spread_text(ratios) == "0.500 [0.500..0.800]"
    with pytest.raises(ValueError):
        paired_ratios([1.0], [1.0, 2.0])
