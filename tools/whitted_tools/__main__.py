"""The tools' one command: `python -m whitted_tools VERB [ARGS]` (`--help` lists the verbs).

Inside Blender 3.4, which imports the package through the add-on modules link that
scripts/install_addon.py makes, this file is the entry:

    blender -b --factory-startup --python-exit-code 1 \\
        --python tools/whitted_tools/__main__.py -- VERB [ARGS]
"""

import sys

from whitted_tools.cli import script_args
from whitted_tools.verbs import run

if __name__ == "__main__":
    status = run(script_args())
    if status is not None:
        sys.exit(status)
