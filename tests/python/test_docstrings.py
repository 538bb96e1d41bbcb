"""The binding API is documented by the module's own docstrings (docs/ARCHITECTURE.md
sends readers to help(whitted_native)): every public class, function, method and
property says what it is."""

import inspect

import whitted_native as wn


def _described(doc):
    """Whether a pybind11 docstring says more than its generated signature lines."""
    if not doc:
        return False
    lines = [line.strip() for line in doc.strip().splitlines()]
    # pybind11 puts "name(args) -> result" first (one line per overload, with
    # "Overloaded function." and numbered signatures for several).
    text = [
        line
        for line in lines
        if line
        and line != "Overloaded function."
        and not (line.split("(")[0].lstrip("0123456789. ").isidentifier() and "->" in line)
    ]
    return bool(text)


def _public(names):
    return [name for name in names if not name.startswith("_")]


def _undocumented():
    missing = []
    for name in _public(dir(wn)):
        value = getattr(wn, name)
        if inspect.isclass(value):
            if not _described(value.__doc__):
                missing.append(name)
            if issubclass(value, int) or hasattr(value, "__members__"):
                continue  # an enum: its items are its documentation
            for member in _public(vars(value)):
                attribute = vars(value)[member]
                if isinstance(attribute, property) or callable(attribute):
                    doc = attribute.__doc__
                    if not _described(doc):
                        missing.append(f"{name}.{member}")
        elif callable(value) and not _described(value.__doc__):
            missing.append(name)
    return missing


def test_every_public_name_of_the_module_has_a_docstring():
    assert _undocumented() == []


def test_the_check_sees_a_bare_signature_as_undocumented():
    assert not _described("run(self: whitted_native.Program, x: int) -> None\n")
    assert _described("run(self: whitted_native.Program, x: int) -> None\n\nRuns it.\n")
    assert not _described(None)
