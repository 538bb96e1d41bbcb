"""Drive a real Blender 3.4 window from a script: the in-Blender half of tests/viewport
(and of the bench-viewport verb's latency scenario, bench/viewport_latency.py).

A scenario script, run as ``blender --factory-startup FILE.blend --python SCRIPT -- ARGS``
under Xvfb, imports this module (``from whitted_tools import viewport_driver as driver``)
and calls ``main(scenario)``. ``scenario(h)`` is a generator that does one step between
yields; the generator is advanced from a
``bpy.app.timers`` callback so Blender keeps drawing between steps (a script that
blocked would never see a redraw, and ``view_draw`` only runs from the event loop).
It may yield:

* a number: sleep that many seconds;
* ``h.until(condition, timeout, what)``: poll ``condition()`` until it is true, or
  fail the run with ``what`` after ``timeout`` seconds.

Everything the pytest side needs goes into a JSON result file (``--result``):
``ok``, ``error`` (a traceback), ``data`` (what the scenario recorded with
``h.record``), ``screenshots`` and ``renders``. The process then quits: exit 0
when the scenario finished, 1 when it raised or timed out.
"""

import argparse
import json
import os
import sys
import time
import traceback

import bpy
from bpy_extras.view3d_utils import location_3d_to_region_2d
from mathutils import Vector

from whitted_tools.blender import addon_problem
from whitted_tools.cli import script_args

# How often a pending wait condition is polled.
POLL_SECONDS = 0.05


class ScenarioError(Exception):
    """A scenario's own check failed (a wait timed out, the window is not as expected)."""


class Until:
    """What a scenario yields to wait for a condition."""

    def __init__(self, condition, timeout, what):
        self.condition = condition
        self.deadline = time.perf_counter() + timeout
        self.timeout = timeout
        self.what = what


class ViewportLog:
    """Reads the JSON-lines file the Whitted viewport appends to (WHITTED_VIEWPORT_LOG).

    Events are read incrementally; each gets an index, so a scenario can take a
    ``mark()`` before an edit and ask only about what was logged after it.
    """

    def __init__(self, path):
        self.path = path
        self.events = []
        self._offset = 0
        self._partial = ""

    def poll(self):
        if not self.path or not os.path.exists(self.path):
            return self.events
        with open(self.path, encoding="utf-8") as file:
            file.seek(self._offset)
            chunk = file.read()
            self._offset = file.tell()
        lines = (self._partial + chunk).split("\n")
        # The last piece has no newline yet when the writer is mid-line.
        self._partial = lines.pop()
        for line in lines:
            if line.strip():
                self.events.append(json.loads(line))
        return self.events

    def mark(self):
        return len(self.poll())

    def since(self, mark, event=None):
        return [e for e in self.poll()[mark:] if event is None or e.get("event") == event]

    def converged_since(self, mark):
        """The index of the first 'converged' that follows a 'sync' after `mark`, or None.

        Requiring a sync first means the converged image includes the edit made
        before `mark` (a converged event of the previous state does not count).
        """
        events = self.poll()
        synced = False
        for index in range(mark, len(events)):
            kind = events[index].get("event")
            if kind == "sync":
                synced = True
            elif kind == "converged" and synced:
                return index
        return None

    def drawn_after(self, index):
        """True when a 'draw' was logged after the event at `index`: it is on screen."""
        return any(e.get("event") == "draw" for e in self.poll()[index + 1 :])


class Harness:
    """The window, its 3D view, the result record, and the helpers scenarios use."""

    def __init__(self, args):
        self.args = args
        self.out_dir = args.out
        os.makedirs(self.out_dir, exist_ok=True)
        self.result = {
            "ok": False,
            "error": None,
            "blender": bpy.app.version_string,
            "gpu": None,
            "data": {},
            "screenshots": {},
            "renders": {},
            "steps": [],
        }
        self.log = ViewportLog(os.environ.get("WHITTED_VIEWPORT_LOG"))
        self.window = None
        self.area = None
        self.region = None

    # --- record ---------------------------------------------------------------
    def record(self, key, value):
        self.result["data"][key] = value

    def step(self, name):
        """Note a step with its time: the pytest side shows them on failure."""
        self.result["steps"].append({"name": name, "t": time.perf_counter()})
        print(f"[driver] {name}", flush=True)

    def write_result(self):
        path = self.args.result
        tmp = path + ".tmp"
        with open(tmp, "w", encoding="utf-8") as file:
            json.dump(self.result, file, indent=1)
        os.replace(tmp, path)  # the reader never sees half a file

    # --- waiting ----------------------------------------------------------------
    @staticmethod
    def until(condition, timeout, what):
        return Until(condition, timeout, what)

    def until_converged(self, mark, timeout=90.0, first_sync_timeout=30.0):
        """Wait for the Whitted viewport to converge after `mark` and the result to be drawn.

        Fails early when not even a sync is logged: then the viewport is not
        rendering with Whitted at all, and a long wait would only hide that.
        """
        started = time.perf_counter()
        state = {}

        def done():
            if not self.log.since(mark, "sync"):
                if time.perf_counter() - started > first_sync_timeout:
                    raise ScenarioError(
                        f"no 'sync' event in {self.log.path} within {first_sync_timeout} s "
                        f"of entering Rendered mode ({len(self.log.poll())} events in all)"
                    )
                return False
            index = self.log.converged_since(mark)
            if index is None:
                return False
            state["converged"] = index
            return self.log.drawn_after(index)

        return Until(done, timeout, f"Whitted viewport converged and drawn after event {mark}")

    # --- the window and its 3D view -------------------------------------------
    def find_view3d(self):
        """Find (again) the window, its 3D view area and that area's main region."""
        self.window = bpy.context.window_manager.windows[0]
        areas = [a for a in self.window.screen.areas if a.type == "VIEW_3D"]
        if not areas:
            raise ScenarioError(
                "no 3D view in the window: " + ", ".join(a.type for a in self.window.screen.areas)
            )
        self.area = max(areas, key=lambda a: a.width * a.height)
        self.region = next(r for r in self.area.regions if r.type == "WINDOW")
        return self.area

    @property
    def space(self):
        return self.area.spaces.active

    def override(self):
        return bpy.context.temp_override(window=self.window, area=self.area, region=self.region)

    def maximise(self):
        """Make the 3D view fill the window (a new, temporary screen): one step, then wait."""
        self.find_view3d()
        with self.override():
            bpy.ops.screen.screen_full_area(use_hide_panels=True)
        # The maximised area belongs to another screen: look it up again after a redraw.
        return self.until(
            lambda: self.find_view3d().width == self.window.width,
            10.0,
            "the 3D view to fill the window after screen_full_area",
        )

    def setup_view(self, shading="SOLID"):
        """Camera view, no overlays, gizmos, header or side regions: only the scene is drawn.

        Hiding the header and toolbars makes the main region the whole area, so a
        screenshot of the area is exactly what the engine drew, pixel for pixel.
        """
        self.find_view3d()
        space = self.space
        space.overlay.show_overlays = False
        space.show_gizmo = False
        space.show_region_header = False
        space.show_region_tool_header = False
        space.show_region_toolbar = False
        space.show_region_ui = False
        space.show_region_hud = False
        space.region_3d.view_perspective = "CAMERA"
        space.shading.type = shading
        with self.override():
            # Fit the camera frame to the region, centred (offset 0).
            bpy.ops.view3d.view_center_camera()
        self.region.tag_redraw()

    def set_shading(self, shading):
        self.space.shading.type = shading
        self.region.tag_redraw()

    def camera_frame(self):
        """The camera frame as [left, top, right, bottom] in screenshot pixels (y down).

        Computed by projecting the corners of the camera's view frame into the
        region: the same projection the viewport draws with, so it holds for any
        camera zoom and offset, with or without the passepartout.
        """
        scene = bpy.context.scene
        camera = scene.camera
        corners = [camera.matrix_world @ v for v in camera.data.view_frame(scene=scene)]
        points = [self.project(c) for c in corners]
        xs = [p[0] for p in points]
        ys = [p[1] for p in points]
        return [min(xs), min(ys), max(xs), max(ys)]

    def project(self, location):
        """A world position in screenshot pixels of the area (x right, y down)."""
        rv3d = self.space.region_3d
        point = location_3d_to_region_2d(self.region, rv3d, Vector(location))
        if point is None:
            raise ScenarioError(f"{tuple(location)} is behind the view")
        # Region coordinates are from the region's bottom left; the PNG's rows go
        # down from the area's top.
        x = point.x + (self.region.x - self.area.x)
        top = self.area.y + self.area.height
        y = top - (self.region.y + point.y)
        return [x, y]

    def object_rect(self, obj):
        """An object's bounding box projected to screenshot pixels [l, t, r, b]."""
        points = [self.project(obj.matrix_world @ Vector(c)) for c in obj.bound_box]
        xs = [p[0] for p in points]
        ys = [p[1] for p in points]
        return [min(xs), min(ys), max(xs), max(ys)]

    # --- images -------------------------------------------------------------------
    def screenshot(self, name, settle=0.3):
        """Let the window redraw, then save the 3D view area as OUT/NAME.png and record it.

        A generator: ``yield from h.screenshot(name)``. The capture reads what the
        window last drew, so it waits `settle` seconds after tagging a redraw.
        (``wm.redraw_timer`` would force a draw at once, but in 3.4 the
        screenshot_area right after it saves a 1x1 image.)
        """
        path = os.path.join(self.out_dir, f"{name}.png")
        self.region.tag_redraw()
        yield settle
        with self.override():
            result = bpy.ops.screen.screenshot_area(filepath=path)
        if result != {"FINISHED"} or not os.path.exists(path):
            raise ScenarioError(f"screenshot_area returned {result} and wrote no {path}")
        self.result["screenshots"][name] = {
            "path": path,
            "t": time.perf_counter(),
            "area": [self.area.width, self.area.height],
            "region": [self.region.width, self.region.height],
            "camera_frame": self.camera_frame(),
            "shading": self.space.shading.type,
            "engine": bpy.context.scene.render.engine,
        }
        return path

    def render_still(self, name, width, height):
        """F12-render the scene's camera to OUT/NAME.png at width x height, and record it."""
        scene = bpy.context.scene
        render = scene.render
        render.resolution_x, render.resolution_y = width, height
        render.resolution_percentage = 100
        render.image_settings.file_format = "PNG"
        render.image_settings.color_mode = "RGB"
        render.filepath = os.path.join(self.out_dir, f"{name}.png")
        started = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        if not os.path.exists(render.filepath):
            raise ScenarioError(f"render.render wrote no {render.filepath}")
        self.result["renders"][name] = {
            "path": render.filepath,
            "size": [width, height],
            "engine": scene.render.engine,
            "seconds": time.perf_counter() - started,
        }
        return render.filepath


def rss_mb():
    """This process's resident memory (VmRSS) in MB."""
    with open("/proc/self/status", encoding="ascii") as file:
        for line in file:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise ScenarioError("no VmRSS line in /proc/self/status")


def parse_args(add_arguments=None):
    parser = argparse.ArgumentParser(description="A tests/viewport scenario.")
    parser.add_argument("--result", required=True, help="JSON file to write")
    parser.add_argument("--out", required=True, help="directory for screenshots and renders")
    parser.add_argument("--timeout", type=float, default=300.0, help="whole-scenario limit, s")
    if add_arguments:
        add_arguments(parser)
    return parser.parse_args(script_args())


def main(scenario, add_arguments=None):
    """Run `scenario(harness)` from timers, write the result file, quit Blender."""
    args = parse_args(add_arguments)
    harness = Harness(args)
    import gpu

    harness.result["gpu"] = gpu.platform.renderer_get()
    # --factory-startup ignores the user preferences, so enable the add-on here; the
    # link in the user add-on folder is made by scripts/setup.sh.
    problem = addon_problem()
    if problem:
        harness.result["error"] = problem
        _finish(harness, ok=False)
        return
    steps = scenario(harness)
    deadline = time.perf_counter() + args.timeout
    pending = [None]  # the Until being waited for, if any

    def tick():
        # The guard of the whole run: any exception from a step is recorded with its
        # traceback and ends the run with exit code 1. Without it, Blender would print
        # an exception raised in a timer and carry on, and the test would only see a
        # missing screenshot or a timeout.
        try:
            return _advance(steps, pending, deadline, harness)
        except StopIteration:
            _finish(harness, ok=True)
        except Exception:  # noqa: BLE001 - the run-level guard described above
            harness.result["error"] = traceback.format_exc()
            print(harness.result["error"], file=sys.stderr, flush=True)
            _finish(harness, ok=False)
        return None

    # The first tick after the window has drawn once.
    bpy.app.timers.register(tick, first_interval=0.5)


def _advance(steps, pending, deadline, harness):
    now = time.perf_counter()
    if now > deadline:
        raise ScenarioError(f"the scenario ran past its {harness.args.timeout} s limit")
    wait = pending[0]
    if wait is not None:
        if not wait.condition():
            if now > wait.deadline:
                raise ScenarioError(f"timed out after {wait.timeout} s waiting for {wait.what}")
            return POLL_SECONDS
        pending[0] = None
    request = next(steps)
    if isinstance(request, Until):
        pending[0] = request
        return POLL_SECONDS
    if request is None:
        return POLL_SECONDS
    return float(request)


def _finish(harness, ok):
    harness.result["ok"] = ok
    harness.write_result()
    sys.stdout.flush()
    sys.stderr.flush()
    if ok:
        bpy.ops.wm.quit_blender()
    else:
        # quit_blender() always exits 0; the pytest side also reads "ok" and "error",
        # but a non-zero status makes a failed run visible to anyone running it by hand.
        os._exit(1)
