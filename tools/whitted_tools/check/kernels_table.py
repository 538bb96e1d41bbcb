"""compare-kernels' results as a table, one row per configuration.

.venv/bin/python -m whitted_tools compare-kernels-table RESULT.json ...
"""

import argparse
import json
from pathlib import Path

from whitted_tools.kernels import kernel_table
from whitted_tools.verbs import prog


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="+", type=Path)
    args = parser.parse_args(argv)
    results = [json.loads(path.read_text()) for path in args.results]
    print("\n".join(kernel_table(results)))
