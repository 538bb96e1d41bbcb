"""The viewport's event log: one JSON object a line, appended to the file named
by the environment variable WHITTED_VIEWPORT_LOG (unset: nothing is written).

Events (each with "t", time.perf_counter() of this process):
  sync       after each sync: its SyncReport fields
  frame      a new pass uploaded to the GPU: frame, pass, passes, pixel_size, samples
  draw       a view_draw that drew: the frame it showed
  converged  the last pass of the current view is shown
  stop       the session's job stopped (Rendered mode left, engine freed)
Tests (tests/viewport) and the viewport benchmark read it.
"""

import json
import os
import time


class ViewportLog:
    def __init__(self, path):
        self._path = path

    @classmethod
    def from_environment(cls):
        return cls(os.environ.get("WHITTED_VIEWPORT_LOG") or None)

    def write(self, event, **fields):
        if self._path is None:
            return
        record = {"event": event, "t": time.perf_counter(), **fields}
        with open(self._path, "a", encoding="utf-8") as out:
            out.write(json.dumps(record) + "\n")
