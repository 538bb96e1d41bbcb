"""The native tables the add-on builds its controls and passes from (whitted_native.LIMITS,
FILM_PASSES, Settings()'s defaults) are the ones the renderer itself holds to: a range
validate() checks, a pass's buffer, the Light's samples."""

import numpy as np
import pytest
import whitted_native as wn
from test_scene import finish, lit_floor_scene

SETTING_LIMITS = {name: bounds for name, bounds in wn.LIMITS.items() if name != "light_samples"}


def _set(settings, name, value):
    """Set field `name` as its own type; False when the field's C++ type cannot hold
    `value` (pybind refuses it before validate() could)."""
    kind = type(getattr(settings, name))
    try:
        setattr(settings, name, kind(value))
    except TypeError:
        return False
    return True


@pytest.mark.parametrize("name", sorted(SETTING_LIMITS))
def test_each_limit_is_the_range_validate_holds_the_setting_to(name):
    low, high = SETTING_LIMITS[name]
    step = 1 if isinstance(getattr(wn.Settings(), name), int) else 1e-3
    for inside in (low, high):
        settings = wn.Settings()
        assert _set(settings, name, inside)
        settings.validate()
    for outside in (low - step, high + step):
        settings = wn.Settings()
        if _set(settings, name, outside):
            with pytest.raises(ValueError, match=name):
                settings.validate()


def test_the_defaults_lie_within_the_limits():
    defaults = wn.Settings()
    defaults.validate()
    for name, (low, high) in SETTING_LIMITS.items():
        assert low <= getattr(defaults, name) <= high, name


def test_light_samples_limit_is_the_lights_own():
    low, high = wn.LIMITS["light_samples"]
    for inside in (low, high):
        assert wn.Light(samples=int(inside)).samples == inside
    for outside in (low - 1, high + 1):
        with pytest.raises(ValueError, match="light samples must be between"):
            wn.Light(samples=int(outside))


def test_each_film_pass_keeps_the_channels_the_table_says():
    depth = 2
    settings = wn.Settings(width=6, height=4, passes=list(wn.FILM_PASSES), contribution_depth=depth)
    job = wn.RenderJob(lit_floor_scene(), settings)
    finish(job)
    for name, channels in wn.FILM_PASSES.items():
        bins = depth + 1 if name == "contributions" else 1
        tile = job.pass_tile(name, 0, 0, 6, 4)
        assert tile.shape == (24, channels * bins), name
        assert np.isfinite(tile).all(), name
