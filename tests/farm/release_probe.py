"""The farm verb's release_workers against a worker that dies while the scheduler
removes the run's plugin (test_farm.py runs this against its own small cluster).

    release_probe.py SCHEDULER_ADDRESS FOLDER

The plugin's teardown ends worker w0's process and writes FOLDER/<worker name> on the
others; release_workers must return."""

import os
import runpy
import sys
from pathlib import Path

from distributed import Client, WorkerPlugin

# The farm module as the farm verb runs it: as __main__, so that its functions travel
# to the workers by value.
farm = runpy.run_module("whitted_tools.farm.render", run_name="__main__")


class DiesOnW0(WorkerPlugin):
    def __init__(self, folder):
        self.folder = folder

    def teardown(self, worker):
        if worker.name == "w0":
            os._exit(1)
        Path(self.folder, worker.name).write_text("torn down")


def main():
    client = Client(sys.argv[1])
    client.wait_for_workers(2, timeout=60)
    client.register_plugin(DiesOnW0(sys.argv[2]), "dies-on-w0")
    farm["release_workers"](client, "dies-on-w0")
    client.close()


if __name__ == "__main__":
    main()
