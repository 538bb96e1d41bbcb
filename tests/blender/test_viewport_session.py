"""The Rendered viewport's session (addon/viewport/session.py) against a job whose last
pass is published before its workers end (native RenderJob: frame() counts a pass once
its tiles are done, wait() turns true only when every worker has returned): the
session must still see the job converge, and so start its denoise and stop polling.

Found by whitted_tools bench-viewport-clean: with Viewport > Denoise on, the last pass
was shown while the job was still finishing, no later draw came, and the viewport
never logged 'converged' nor denoised."""

from types import SimpleNamespace

import numpy as np
from whitted.denoise import Denoising
from whitted.viewport.session import ViewportSession

PASSES = 3


class Engine:
    def __init__(self):
        self.redraws = 0

    def tag_redraw(self):
        self.redraws += 1

    def update_stats(self, stats, info):
        pass


class Job:
    """The last pass done; wait() true from the second call on (the workers ended)."""

    def __init__(self):
        self.frame = PASSES
        self.waits = 0

    def wait(self, seconds):
        self.waits += 1
        return self.waits > 1

    def display(self, kind, first=0):
        return np.zeros((2, 2, 4), np.float32)

    def pass_info(self):
        return {"pass": PASSES, "passes": PASSES, "pixel_size": 1, "samples": 4}

    def stats(self):
        return {"trace_seconds": 0.5, "samples": 16, "waves": True, "threads": 1}


class Display:
    def __init__(self):
        self.uploads = 0

    def upload(self, pixels):
        self.uploads += 1


def test_a_job_that_ends_after_its_last_pass_was_shown_converges(native):
    engine = Engine()
    session = ViewportSession(engine, native)
    session._display = Display()
    session._denoising = Denoising(False, "Denoise off")
    session._setup = SimpleNamespace(border=None, width=2, height=2)
    session._job = Job()
    session._show_new_pass()  # a draw: the last pass, the workers not yet ended
    assert session._display.uploads == 1 and not session._converged
    # The timer sees the job end and asks for a draw; that draw takes it in.
    assert session._on_timer() is not None and engine.redraws == 1
    session._show_new_pass()
    assert session._converged and session._display.uploads == 1
    # Converged: the timer stops without asking for more draws.
    assert session._on_timer() is None and engine.redraws == 1
