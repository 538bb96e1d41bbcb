"""scripts/image_hashes.py's comparison: every differing channel and count is named."""

import importlib.util
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "image_hashes.py"


def load():
    spec = importlib.util.spec_from_file_location("image_hashes", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_differences_name_every_channel_count_and_scene():
    image_hashes = load()
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
