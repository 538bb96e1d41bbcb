"""whitted_tools.timing without Blender: the paired ratios the benchmark pages quote."""

import pytest
from whitted_tools.timing import median_or_none, paired_median, paired_ratios, spread_text


def test_paired_ratios_divide_within_each_repetition_and_show_their_spread():
    # The machine slows down by half in the second repetition: each pair's ratio holds.
    ratios = paired_ratios([1.0, 1.5, 0.8], [2.0, 3.0, 1.0])
    assert ratios == pytest.approx([0.5, 0.5, 0.8])
    assert spread_text(ratios) == "0.500 [0.500..0.800]"
    with pytest.raises(ValueError):
        paired_ratios([1.0], [1.0, 2.0])


def test_paired_median_is_the_median_of_the_pairs_not_a_ratio_of_medians():
    # Medians first would give 1.5 / 2.0 = 0.75; the pairs' ratios are 0.5, 0.5, 0.8.
    assert paired_median([1.0, 1.5, 0.8], [2.0, 3.0, 1.0]) == pytest.approx(0.5)
    with pytest.raises(ValueError):
        paired_median([], [])


def test_median_or_none_skips_what_is_missing():
    assert median_or_none([3.0, None, 1.0, 2.0]) == 2.0
    assert median_or_none(value for value in (None, None)) is None
