"""The codebase verb's measures, on sources whose sizes are known, and on this checkout."""

from pathlib import Path

from whitted_tools.check.codebase import LAYERS, cpp_classes, layer_rows, python_classes, table

REPO = Path(__file__).resolve().parents[2]

CPP = """
template <class T>
class Kernel {
 public:
  Kernel() = default;
  int trace(int x) const {
    return x + 1;
  }

 private:
  struct Inner {
    int a;
  };
  int depth_ = 0;
};
struct Forward;
"""

PYTHON = """
class Sync:
    kind = "scene"

    def apply(self):
        return 1

    def report(self):
        return 2
"""


def test_a_cpp_class_counts_its_lines_and_its_own_members():
    found = {name: (lines, members) for name, lines, members in cpp_classes(CPP)}
    # Kernel: the constructor, trace, Inner and depth_ (Inner's own member is Inner's).
    assert found["Kernel"] == (13, 4)
    assert found["Inner"] == (3, 1)
    assert "Forward" not in found  # a declaration is no class


def test_a_python_class_counts_its_lines_and_members():
    assert list(python_classes(PYTHON)) == [("Sync", 8, 3)]


def test_every_layer_of_this_checkout_is_measured():
    rows = layer_rows(REPO)
    assert [row["layer"] for row in rows] == list(LAYERS)
    native = rows[list(LAYERS).index("native core")]
    assert native["files"] > 10 and native["lines"] > 1000
    assert native["largest_class"] is not None
    lines = table(rows)
    assert len(lines) == 2 + len(LAYERS)
