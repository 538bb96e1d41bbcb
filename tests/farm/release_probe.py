"""whitted_tools farm's release_workers against a worker that dies while the scheduler
removes the run's plugin (test_farm.py runs this against its own small cluster).

    release_probe.py SCHEDULER_ADDRESS FOLDER

The plugin's teardown ends worker w0's process and writes FOLDER/<worker name> on the
others; release_workers must return."""

import os
import sys
from pathlib import Path

import cloudpickle
from distributed import Client, WorkerPlugin
from whitted_tools.farm import render as farm

# Send farm's functions by value, as the farm verb does: workers need not have the
# tool package.
cloudpickle.register_pickle_by_value(farm)


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
    farm.release_workers(client, "dies-on-w0")
    client.close()


if __name__ == "__main__":
    main()
