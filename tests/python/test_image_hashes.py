"""The image-hashes verb's comparison: every differing channel and count is named."""

from whitted_tools.check import image_hashes


def test_differences_name_every_channel_count_and_scene():
    before = {
        "demo": {"channels": {"R": "a", "G": "b"}, "stats": {"rays": 1}},
        "gone": {"channels": {}, "stats": {}},
    }
    now = {"demo": {"channels": {"R": "a", "G": "c", "B": "d"}, "stats": {"rays": 2}}}
    assert image_hashes.differences(now, before) == [
        "demo: channel B differs",
        "demo: channel G differs",
        "demo: statistics differ: {'rays': 2} against {'rays': 1}",
        "gone: only in the other",
    ]
    assert image_hashes.differences(before, before) == []
