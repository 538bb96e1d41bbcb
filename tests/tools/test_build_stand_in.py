"""whitted_tools.builds without a native module: another build standing in for the
add-on's own."""

import sys
import types

from whitted_tools.builds import stand_in_for_addon


def test_the_addon_loads_the_stand_in_where_it_would_load_its_own(tmp_path, monkeypatch):
    package = tmp_path / "fake_addon"
    package.mkdir()
    # As addon/native.py's load_native imports the module beside it.
    (package / "__init__.py").write_text(
        "def load_native():\n    from . import whitted_native\n\n    return whitted_native\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    other_build = types.ModuleType("whitted_native")
    monkeypatch.delitem(sys.modules, "fake_addon.whitted_native", raising=False)
    stand_in_for_addon(other_build, addon="fake_addon")
    import fake_addon

    assert fake_addon.load_native() is other_build
    monkeypatch.delitem(sys.modules, "fake_addon.whitted_native")
    monkeypatch.delitem(sys.modules, "fake_addon")
