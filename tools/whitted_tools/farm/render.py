"""Render a frame range, or one frame split into tiles, with Whitted on a Dask
distributed cluster.

    .venv/bin/python -m whitted_tools farm SCENE.blend --frames A-B [--tiles NxM]
        [--scheduler ADDRESS] [--workers N] [--retries K] [--blender CMD]
        [--threads T] [--timeout S] [--chunk N] [--cold] --output DIR

DIR gets one EXR per frame (`NNNN.exr`, RGBA float32) and `farm_report.json`. The
command exits 0 only when every frame was rendered (or already was).

- Without --scheduler an embedded LocalCluster runs on this machine (--workers, by
  default one per core, each Blender with --threads, default 1); with --scheduler
  the tasks go to that cluster's workers (--workers N waits for N of them). Start
  workers on other machines with `dask worker tcp://SCHEDULER:8786`, or on Slurm/PBS
  with dask-jobqueue (docs/FARM.md).
- No shared filesystem is assumed: the scene is packed (`file.pack_all`, so images
  travel inside it; linked libraries too when Blender can pack them) and scattered
  to every worker once; each worker keeps it in memory and in a file named by its
  hash in its temp folder, so a scene is sent to a worker once however many frames
  it renders. The pixels come back in the task's result.
- Blender stays warm: each worker keeps one Blender per task thread alive between
  tasks (`CMD -b scene.blend -E WHITTED --python in_blender.py -- --serve`, a
  WorkerPlugin that this run registers and removes at its end), which loads the scene
  once and renders frame after frame on request (tools/whitted_tools/farm/in_blender.py). CMD is
  Blender 3.4 by default, with the Whitted add-on of its user preferences (the
  development install or the installed package); WHITTED_EXIT_ON_ERROR=1 makes a
  failed Whitted frame end that Blender with exit 3. --cold starts a fresh Blender
  for every frame instead, for scenes whose state must not carry from frame to frame.
- Frames go out in chunks: one frame per task until a frame's time is known, then as
  many as fill about TASK_SECONDS per task (--chunk N fixes it), never more than an
  even share of what is left, so the last frames still spread over every worker.
  Each tile of a --tiles frame is an item like a frame.
- A frame fails when its Blender exits or crashes, times out, writes no image, an
  image of the wrong size, or the statistics say the engine failed; that Blender is
  gone and the chunk's next frame starts a fresh one, so a crash loses only the
  frame in flight. A failed frame is retried, preferably on another worker, up to
  --retries times, then reported failed with its reasons. A worker that dies
  mid-chunk loses nothing: the scheduler gives its task to another worker (and its
  Blenders die with it: PR_SET_PDEATHSIG).
- Frames are written atomically (NNNN.exr.partial, checked by decoding it, then
  renamed); the report, rewritten atomically after each frame, records each frame's
  key (the scene file's hash, the frame, tiles, Blender command, the Blender-side
  script) and the image's hash: a rerun skips frames whose image is there,
  unchanged, with the same key.
- --tiles NxM renders each frame as N columns x M rows through Blender's render
  border and crop (Whitted traces only the border) and stitches the tiles; a
  render is a pure function of scene and settings, so the stitched frame equals a
  single render bit for bit (tests/farm).
"""

import argparse
import collections
import hashlib
import itertools
import json
import os
import select
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import uuid

from distributed import WorkerPlugin

from whitted_tools.verbs import prog

REPORT_NAME = "farm_report.json"
# The script every farm Blender runs (its text travels to the workers).
BLENDER_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "in_blender.py")
# A chunk of frames fills about this long a task once a frame's time is known: the
# scheduler's round trip (about 13 ms, docs/FARM.md) is then under 1% of it.
TASK_SECONDS = 2.0
# Tasks kept queued per worker, so a worker never waits for the client between tasks.
QUEUED_PER_WORKER = 2
LOG_LINES = 15  # the lines of a failed Blender's log kept in its reason


def blender_args(blend, output, frames, threads=0, blender="blender"):
    """The single-machine render (tests/farm's reference) of frames "S..E" with the
    farm's settings, one Blender: `CMD -b BLEND -E WHITTED --python in_blender.py
    -s S -e E -a -- OUTPUT`."""
    start, end = frames.split("..")
    command = [*blender.split(), "-b", blend, "-E", "WHITTED"]
    if threads:
        command += ["-t", str(threads)]
    command += ["--python-exit-code", "1", "--python", BLENDER_SCRIPT]
    return [*command, "-s", start, "-e", end, "-a", "--", output]


def tile_border(tile, tiles):
    """Border fractions (xmin, ymin, xmax, ymax) of tile (i, j) of tiles (N, M)."""
    (i, j), (n, m) = tile, tiles
    return (i / n, j / m, (i + 1) / n, (j + 1) / m)


def tile_region(border, width, height):
    """The pixels Blender renders for `border`, as Whitted computes them
    (addon/export/film.py): each edge the float32 product, truncated."""
    import numpy as np

    def edge(fraction, size):
        return int(np.float32(fraction) * np.float32(size))

    xmin, ymin = edge(border[0], width), edge(border[1], height)
    xmax, ymax = edge(border[2], width), edge(border[3], height)
    return xmin, ymin, max(xmax, xmin + 1), max(ymax, ymin + 1)


# --- on a worker ------------------------------------------------------------------


def _die_with_parent():
    # Blender must not outlive a worker that is killed: it would keep a core busy.
    # (The signal comes when the thread that started it ends: a worker's task
    # threads live as long as the worker.)
    import ctypes
    import signal

    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


class WarmBlender:
    """One `blender -b --python in_blender.py -- --serve FD` on this worker: a scene
    opened by the first request and kept, a frame per request on its stdin, a reply per
    frame on the pipe FD (in_blender.py beside this file). Its folder holds its log
    (Blender's output, emptied before each frame) and the frame being written. `command`: the
    command up to the script's arguments."""

    def __init__(self, command, parent):
        self.folder = tempfile.mkdtemp(prefix="blender-", dir=parent)
        self.log_path = os.path.join(self.folder, "blender.log")
        self.frames = 0  # requests sent
        env = dict(os.environ, WHITTED_EXIT_ON_ERROR="1")
        replies, reply_end = os.pipe()
        try:
            with open(self.log_path, "ab") as log:
                self.process = subprocess.Popen(
                    [*command, "--", "--serve", str(reply_end)],
                    stdin=subprocess.PIPE,
                    stdout=log,
                    stderr=subprocess.STDOUT,
                    env=env,
                    bufsize=0,
                    pass_fds=(reply_end,),
                    preexec_fn=_die_with_parent,
                )
        finally:
            os.close(reply_end)  # Blender holds its own copy: its end closes at its exit
        self.replies = os.fdopen(replies, "rb", buffering=0)

    def alive(self):
        return self.process.poll() is None

    def render(self, blend, frame, border, timeout):
        """One frame (or tile): a dict with ok, and either exr (bytes), stats and
        render_seconds (Blender's request to reply) or reason and log. After a
        failure this Blender has ended."""
        self.frames += 1
        for name in os.listdir(self.folder):
            if name != "blender.log":
                os.remove(os.path.join(self.folder, name))
        os.truncate(self.log_path, 0)  # Blender appends: its next line starts the file
        stats_path = os.path.join(self.folder, "stats.json")
        request = {
            "scene": blend,
            "frame": frame,
            "border": border,
            "output": os.path.join(self.folder, "frame"),
            "stats": stats_path,
        }
        try:
            self.process.stdin.write(json.dumps(request).encode() + b"\n")
        except BrokenPipeError:
            return self._failed(self._ended())
        reply, reason = self._reply(timeout)
        if reason:
            return self._failed(reason)
        stats = None
        if os.path.exists(stats_path):
            with open(stats_path, encoding="utf-8") as source:
                stats = json.load(source)
        images = [name for name in os.listdir(self.folder) if name.endswith(".exr")]
        if stats is None:
            reason = "no WHITTED_STATS file (did Whitted render at all?)"
        elif stats.get("status") != "ok":
            reason = f"Whitted failed: {stats.get('error')}"
        elif len(images) != 1:
            reason = f"Blender wrote {len(images)} images"
        if reason:
            self.close()  # not trusted with another frame
            return self._failed(reason)
        with open(os.path.join(self.folder, images[0]), "rb") as source:
            exr = source.read()
        return {"ok": True, "exr": exr, "stats": stats, "render_seconds": reply["seconds"]}

    def _reply(self, timeout):
        """(the reply, None), or (None, why none came): Blender ended or timed out."""
        ready, _, _ = select.select([self.replies], [], [], timeout)
        if not ready:
            self.process.kill()
            self.process.wait()
            return None, f"Blender timed out after {timeout} s"
        line = self.replies.readline()
        if not line.endswith(b"\n"):
            return None, self._ended()
        return json.loads(line), None

    def _ended(self):
        code = self.process.wait()
        what = f"killed by signal {-code}" if code < 0 else f"exited {code}"
        failed = [
            line for line in self._log() if "RENDER FAILED" in line or line.startswith("Error")
        ]
        return f"Blender {what}" + (f": {failed[-1]}" if failed else "")

    def _log(self):
        with open(self.log_path, encoding="utf-8", errors="replace") as source:
            return source.read().splitlines()

    def _failed(self, reason):
        return {"ok": False, "reason": reason, "log": "\n".join(self._log()[-LOG_LINES:])}

    def close(self):
        """End this Blender (its input closed ends its loop) and remove its folder."""
        if self.alive():
            self.process.stdin.close()
            try:
                self.process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.replies.close()
        shutil.rmtree(self.folder, ignore_errors=True)


class WarmBlenders(WorkerPlugin):
    """The Blenders a worker keeps between the tasks of one farm run (at most one idle
    per task thread), all with that run's scene. The run registers it on every worker
    (and on workers that join later) and removes it at its end, which ends them."""

    def __init__(self, script, blender, threads, warm):
        self.script_text = script
        self.blender = blender
        self.threads = threads
        self.warm = warm

    def setup(self, worker):
        self.folder = tempfile.mkdtemp(prefix="whitted-farm-")
        self.script = os.path.join(self.folder, "in_blender.py")
        with open(self.script, "w", encoding="utf-8") as out:
            out.write(self.script_text)
        self.lock = threading.Lock()
        # Blender starts now, while the scene is still being packed and sent.
        self.idle = [self.start()] if self.warm else []

    def teardown(self, worker):
        with self.lock:
            idle, self.idle = self.idle, []
        for blender in idle:
            blender.close()
        shutil.rmtree(self.folder, ignore_errors=True)

    def start(self):
        command = [*self.blender.split(), "-b"]
        if self.threads:
            command += ["-t", str(self.threads)]
        command += ["--python-exit-code", "1", "--python", self.script]
        return WarmBlender(command, self.folder)

    def take(self):
        """An idle Blender (with the scene open once it has rendered), or a new one."""
        with self.lock:
            if self.idle:
                return self.idle.pop()
        return self.start()

    def give_back(self, blender):
        if self.warm and blender.alive():
            with self.lock:
                self.idle.append(blender)
        else:
            blender.close()


def scene_file(blend_bytes, blend_hash):
    """The scene in this machine's temp folder, written once (named by its hash)."""
    cache = os.path.join(tempfile.gettempdir(), "whitted-farm-cache")
    os.makedirs(cache, exist_ok=True)
    blend = os.path.join(cache, f"{blend_hash}.blend")
    if not os.path.exists(blend):
        partial = f"{blend}.{os.getpid()}.{threading.get_ident()}.partial"
        with open(partial, "wb") as out:
            out.write(blend_bytes)
        os.replace(partial, blend)
    return blend


def render_chunk(plugin, blend_bytes, blend_hash, items, timeout):
    """Render a chunk of frames (or tiles), each an (frame, border) pair, with this
    worker's warm Blenders of the plugin named `plugin`. Returns one dict per item
    (WarmBlender.render's, with worker, host, frame, seconds: the item's wall time
    on this worker, and started_blender)."""
    import socket

    from distributed import get_worker

    worker = get_worker()
    blenders = worker.plugins[plugin]
    blend = scene_file(blend_bytes, blend_hash)
    results = []
    for frame, border in items:
        started = time.perf_counter()
        blender = blenders.take()
        started_blender = blender.frames == 0
        result = blender.render(blend, frame, border, timeout)
        blenders.give_back(blender)
        results.append(
            {
                **result,
                "worker": worker.address,
                "host": socket.gethostname(),
                "frame": frame,
                "seconds": time.perf_counter() - started,
                "started_blender": started_blender,
            }
        )
    return results


# --- on the client ----------------------------------------------------------------


def parse_frames(text):
    start, _, end = text.partition("-")
    first, last = int(start), int(end or start)
    if last < first:
        raise argparse.ArgumentTypeError(f"empty frame range {text}")
    return list(range(first, last + 1))


def parse_tiles(text):
    columns, _, rows = text.lower().partition("x")
    tiles = (int(columns), int(rows or columns))
    if min(tiles) < 1:
        raise argparse.ArgumentTypeError(f"bad tiles {text}")
    return tiles


def file_hash(path):
    digest = hashlib.sha256()
    with open(path, "rb") as source:
        for block in iter(lambda: source.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


PACK_EXPR = """
import bpy, sys
for pack in ("pack_all", "pack_libraries"):
    try:
        getattr(bpy.ops.file, pack)()
    except (AttributeError, RuntimeError) as error:
        print(f"farm: {pack}: {error}")
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[-1], copy=True, compress=True)
"""


def start_packing(blend, blender, folder):
    """Start the Blender that packs the scene's external files into a copy in
    `folder` (what workers receive); finish_packing waits for it."""
    packed = os.path.join(folder, "packed.blend")
    command = [*blender.split(), "-b", blend, "--python-exit-code", "1"]
    command += ["--python-expr", PACK_EXPR, "--", packed]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return process, packed


def finish_packing(packing, blend):
    """The packed scene's bytes, once its Blender has finished."""
    process, packed = packing
    output, _ = process.communicate()
    if process.returncode != 0 or not os.path.exists(packed):
        sys.exit(f"farm: could not pack {blend}:\n{output[-2000:]}")
    with open(packed, "rb") as source:
        return source.read()


def read_exr(data):
    """(pixels float32[H, W, 4] top row first, header) of EXR bytes; raises on damage."""
    import OpenEXR

    with tempfile.NamedTemporaryFile(suffix=".exr") as file:
        file.write(data)
        file.flush()
        with OpenEXR.File(file.name) as exr:
            channels = exr.channels()
            if "RGBA" not in channels:
                raise ValueError(f"no RGBA channels, only {sorted(channels)}")
            return channels["RGBA"].pixels.copy(), exr.header()


def write_exr(path, pixels):
    import OpenEXR

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGBA": pixels}) as exr:
        exr.write(path)


def write_atomic(path, data=None, pixels=None):
    """Write a frame to a temporary name, decode it again, then rename it in place."""
    partial = f"{path}.partial"
    if pixels is not None:
        write_exr(partial, pixels)
    else:
        with open(partial, "wb") as out:
            out.write(data)
            out.flush()
            os.fsync(out.fileno())
    with open(partial, "rb") as source:
        read_exr(source.read())  # a damaged file raises here, before it is taken
    os.replace(partial, path)


class Report:
    """farm_report.json: the farm's state while it runs (frames done, with their keys
    and image hashes, so a rerun resumes) and its report at the end."""

    def __init__(self, folder, meta):
        self.path = os.path.join(folder, REPORT_NAME)
        self.meta = meta
        self.frames = {}
        self.previous = {}
        if os.path.exists(self.path):
            with open(self.path, encoding="utf-8") as source:
                try:
                    self.previous = json.load(source).get("frames", {})
                except json.JSONDecodeError:
                    self.previous = {}

    def done_before(self, name, key, image):
        entry = self.previous.get(name)
        if not entry or entry.get("status") != "done" or entry.get("key") != key:
            return False
        return os.path.exists(image) and file_hash(image) == entry.get("sha256")

    def save(self, status, extra=None):
        data = {"status": status, **self.meta, **(extra or {}), "frames": self.frames}
        partial = f"{self.path}.partial"
        with open(partial, "w", encoding="utf-8") as out:
            json.dump(data, out, indent=1, sort_keys=True)
        os.replace(partial, self.path)


class Progress:
    def __init__(self, total, out=sys.stderr):
        self.total, self.out, self.started = total, out, time.perf_counter()
        self.done = self.failed = self.retries = self.skipped = 0

    def show(self, final=False):
        elapsed = time.perf_counter() - self.started
        finished = self.done + self.failed
        rendered = self.done - self.skipped
        left = self.total - finished
        eta = "?" if rendered == 0 else f"{elapsed / max(rendered, 1) * left:.0f} s"
        width = 30
        filled = int(width * finished / max(self.total, 1))
        bar = "#" * filled + "." * (width - filled)
        line = (
            f"[farm] [{bar}] {self.done}/{self.total} frames done, {self.failed} failed, "
            f"{self.retries} retries, {elapsed:.0f} s, ETA {eta if left else '0 s'}"
        )
        end = "\n" if final or not self.out.isatty() else "\r"
        print(line, end=end, file=self.out, flush=True)


class Chunks:
    """The items still to render, each (frame, tile or None) with the workers that
    failed it, and how many of them the next task takes: one until an item's time is
    known, then as many as fill about TASK_SECONDS (or `size` when fixed), never more
    than an even share of what is left among the tasks queued on the workers. A retry
    goes first, alone."""

    def __init__(self, items, size=None):
        self.queue = collections.deque((item, ()) for item in items)
        self.size = size
        self.seconds = []  # per item, as workers measured them

    def __bool__(self):
        return bool(self.queue)

    def measured(self, results):
        # A frame that had to start its Blender says little about the frames after it.
        ok = [r for r in results if r["ok"]]
        warm = [r["seconds"] for r in ok if not r["started_blender"]]
        self.seconds += warm or [r["seconds"] for r in ok]

    def retry(self, item, failed_on):
        self.queue.appendleft((item, failed_on))

    def next(self, workers):
        """(items, workers that failed them) of the next task."""
        if self.queue[0][1]:
            item, failed_on = self.queue.popleft()
            return [item], failed_on
        size = self.size or self.auto_size(workers)
        chunk = []
        while self.queue and len(chunk) < size and not self.queue[0][1]:
            chunk.append(self.queue.popleft()[0])
        return chunk, ()

    def auto_size(self, workers):
        if not self.seconds:
            return 1
        recent = sorted(self.seconds[-20:])
        per_item = max(recent[len(recent) // 2], 1e-3)
        fill = max(1, int(TASK_SECONDS / per_item))
        share = max(1, len(self.queue) // (max(workers, 1) * QUEUED_PER_WORKER))
        return min(fill, share)


def run_farm(args):
    blend = os.path.abspath(args.scene)
    if not os.path.isfile(blend):
        sys.exit(f"farm: no such file: {blend}")
    os.makedirs(args.output, exist_ok=True)
    scene_hash = file_hash(blend)
    tiles = args.tiles
    with open(BLENDER_SCRIPT, encoding="utf-8") as source:
        script = source.read()
    meta = {
        "scene": blend,
        "scene_sha256": scene_hash,
        "blender": args.blender,
        "tiles": list(tiles) if tiles else None,
        "retries_allowed": args.retries,
        "warm": not args.cold,
    }
    report = Report(args.output, meta)

    def key_of(frame):
        text = json.dumps([scene_hash, frame, tiles, args.blender, script])
        return hashlib.sha256(text.encode()).hexdigest()

    todo = []
    progress = Progress(len(args.frames))
    for frame in args.frames:
        name = f"{frame:04d}"
        image = os.path.join(args.output, f"{name}.exr")
        if report.done_before(name, key_of(frame), image):
            report.frames[name] = {**report.previous[name], "skipped": True}
            progress.done += 1
            progress.skipped += 1
        else:
            todo.append(frame)
    print(
        f"[farm] {len(args.frames)} frames, {len(todo)} to render, "
        f"{len(args.frames) - len(todo)} already rendered with this scene and settings",
        flush=True,
    )
    if not todo:
        report.save("done", {"rendered": 0, "skipped": len(args.frames)})
        progress.show(final=True)
        print_table(report.frames, [])
        return 0

    plugin = f"whitted-warm-blenders-{uuid.uuid4().hex[:12]}"
    threads = args.threads if args.threads is not None else (0 if args.scheduler else 1)
    with tempfile.TemporaryDirectory(prefix="whitted-farm-pack-") as folder:
        # Blender packs the scene while the cluster starts and the workers start theirs.
        packing = start_packing(blend, args.blender, folder)
        client, cluster = connect(args)
        try:
            print(f"[farm] scheduler {client.scheduler.address}, dashboard {client.dashboard_link}")
            print(f"[farm] workers: {len(client.scheduler_info()['workers'])}", flush=True)
            blenders = WarmBlenders(script, args.blender, threads, not args.cold)
            client.register_plugin(blenders, plugin)
            scene_bytes = finish_packing(packing, blend)
            packed_hash = hashlib.sha256(scene_bytes).hexdigest()
            # One copy to every worker now; a worker that joins later fetches it from a peer.
            scene_future = client.scatter(scene_bytes, broadcast=True, hash=False)
            failed_frames = render_frames(
                client, plugin, scene_future, packed_hash, todo, args, report, key_of, progress
            )
            progress.show(final=True)
            status = "failed" if failed_frames else "done"
            rendered = len(todo) - len(failed_frames)
            report.save(status, {"rendered": rendered, "skipped": progress.skipped})
            print_table(report.frames, failed_frames)
            return 1 if failed_frames else 0
        finally:
            release_workers(client, plugin)
            client.close()
            if cluster is not None:
                cluster.close()


def release_workers(client, plugin):
    """Remove the run's plugin from every worker, which ends their warm Blenders.

    The scheduler sends the removal to all the workers it knows. When one of them has
    died and the scheduler has not noticed yet (a worker killed near the run's end),
    the scheduler's send fails and it drops our connection. The frames and the report
    are written by then, so that must not fail the run: the workers are then asked
    one by one, and a worker that cannot answer is named, not raised."""
    try:
        client.unregister_worker_plugin(plugin)
        return
    except OSError as error:  # distributed's CommClosedError is an OSError
        print(f"[farm] the scheduler could not end the warm Blenders ({error})", flush=True)
    answers = client.run(remove_plugin, plugin, on_error="return")
    for worker, answer in sorted(answers.items()):
        if isinstance(answer, Exception):
            print(f"[farm] {worker} did not answer ({answer}); its Blenders end with it")
        else:
            print(f"[farm] {worker}: warm Blenders ended")


async def remove_plugin(name, dask_worker):
    """On a worker: tear down plugin `name` if the worker still has it."""
    if name in dask_worker.plugins:
        await dask_worker.plugin_remove(name)


def connect(args):
    """(client, the LocalCluster it runs on or None): the cluster at --scheduler, or
    a LocalCluster of --workers processes on this machine."""
    from distributed import Client, LocalCluster

    if args.scheduler:
        client = Client(args.scheduler)
        if args.workers:
            client.wait_for_workers(args.workers, timeout=120)
        return client, None
    workers = args.workers or os.cpu_count() or 1
    cluster = LocalCluster(
        n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0"
    )
    return Client(cluster), cluster


def render_frames(client, plugin, scene_future, packed_hash, todo, args, report, key_of, progress):
    """Render the frames `todo` in chunks, keeping QUEUED_PER_WORKER tasks queued per
    worker, retrying failed items; writes each frame and the report as it completes.
    Returns the frames that failed."""
    from distributed import as_completed

    tiles = args.tiles
    parts = [(i, j) for j in range(tiles[1]) for i in range(tiles[0])] if tiles else [None]
    chunks = Chunks([(frame, part) for frame in todo for part in parts], args.chunk)
    jobs = {}  # future -> (items, workers that failed them)
    ac = as_completed()
    tasks = itertools.count()

    def workers():
        return list(client.scheduler_info()["workers"])

    def fill():
        while chunks and len(jobs) < QUEUED_PER_WORKER * max(len(workers()), 1):
            items, failed_on = chunks.next(len(workers()))
            others = [w for w in workers() if w not in failed_on]
            # Another worker than the ones that failed it, if any is left (loose: the
            # task still runs when those workers are gone).
            placement = (
                {"workers": others, "allow_other_workers": True} if failed_on and others else {}
            )
            borders = [(f, tile_border(part, tiles) if part else None) for f, part in items]
            future = client.submit(
                render_chunk,
                plugin,
                scene_future,
                packed_hash,
                borders,
                args.timeout,
                key=f"whitted-{items[0][0]:04d}-{len(items)}-{next(tasks)}-{packed_hash[:8]}",
                pure=False,
                **placement,
            )
            jobs[future] = (items, failed_on)
            ac.add(future)

    pieces = {frame: {} for frame in todo}
    attempts = {frame: 0 for frame in todo}
    reasons = {frame: [] for frame in todo}
    failed_frames = []
    fill()
    progress.show()
    for future in ac:
        items, failed_on = jobs.pop(future)
        try:
            results = future.result()
        except Exception as error:  # noqa: BLE001 (KilledWorker, a lost scene copy: retry)
            reason = f"{type(error).__name__}: {error}"
            results = [{"ok": False, "reason": reason, "worker": "?"} for _ in items]
        chunks.measured(results)
        for (frame, part), result in zip(items, results, strict=True):
            if frame in failed_frames:
                continue
            if result["ok"]:
                result = checked(result, part, tiles)
            if not result["ok"]:
                attempts[frame] += 1
                reasons[frame].append(f"{result['worker']}: {result['reason']}")
                if attempts[frame] > args.retries:
                    failed_frames.append(frame)
                    progress.failed += 1
                    report.frames[f"{frame:04d}"] = {
                        "status": "failed",
                        "attempts": attempts[frame],
                        "reasons": reasons[frame],
                    }
                    report.save("running")
                else:
                    progress.retries += 1
                    chunks.retry((frame, part), (*failed_on, result["worker"]))
                progress.show()
                continue
            pieces[frame][part] = result
            if len(pieces[frame]) == len(parts):
                write_frame(frame, pieces.pop(frame), tiles, args.output, report, key_of)
                report.frames[f"{frame:04d}"]["attempts"] = attempts[frame] + 1
                report.frames[f"{frame:04d}"]["retry_reasons"] = reasons[frame]
                progress.done += 1
                report.save("running")
                progress.show()
        fill()
    return failed_frames


def checked(result, part, tiles):
    """The result with its decoded pixels, or failed if its image is damaged or of
    the wrong size."""
    try:
        pixels, _ = read_exr(result["exr"])
        width, height = frame_size(result["stats"])
        expected = (height, width)
        if part:
            xmin, ymin, xmax, ymax = tile_region(tile_border(part, tiles), width, height)
            expected = (ymax - ymin, xmax - xmin)
        if pixels.shape[:2] != expected:
            raise ValueError(f"image {pixels.shape[:2]} instead of {expected}")
    except Exception as error:  # noqa: BLE001 (any damage: retry the frame)
        return {**result, "ok": False, "reason": f"bad image: {error}"}
    return {**result, "pixels": pixels}


def write_frame(frame, pieces, tiles, output, report, key_of):
    """Write a frame whose items are all rendered ({part: result}) and record it."""
    name = f"{frame:04d}"
    image = os.path.join(output, f"{name}.exr")
    results = list(pieces.values())
    if tiles:
        write_atomic(image, pixels=stitch(pieces, tiles, results[0]["stats"]))
    else:
        write_atomic(image, data=results[0]["exr"])
    report.frames[name] = {
        "status": "done",
        "key": key_of(frame),
        "sha256": file_hash(image),
        # On the workers: the frame's whole time, its Blender's request to reply, and
        # Whitted's render() call (the engine's statistics).
        "seconds": round(sum(r["seconds"] for r in results), 3),
        "blender_seconds": round(sum(r["render_seconds"] for r in results), 3),
        "whitted_seconds": round(sum(r["stats"]["phases"]["total"] for r in results), 3),
        "started_blender": any(r["started_blender"] for r in results),
        "rays": sum(r["stats"]["rays"]["total"] for r in results),
        "workers": sorted({r["worker"] for r in results}),
    }


def frame_size(stats):
    settings = stats["settings"]
    return settings["width"], settings["height"]


def stitch(pieces, tiles, stats):
    """The frame from its tiles: {(i, j): result with its pixels, top row first}."""
    import numpy as np

    width, height = frame_size(stats)
    frame = np.zeros((height, width, 4), np.float32)
    for part, result in pieces.items():
        pixels = result["pixels"]
        xmin, ymin, xmax, ymax = tile_region(tile_border(part, tiles), width, height)
        frame[height - ymax : height - ymin, xmin:xmax] = pixels
    return frame


def print_table(frames, failed):
    done = {name: f for name, f in frames.items() if f.get("status") == "done"}
    print(f"\n{'frame':>6} {'status':>8} {'seconds':>8} {'rays':>10} {'tries':>5}  workers")
    for name in sorted(frames):
        entry = frames[name]
        status = "skipped" if entry.get("skipped") else entry["status"]
        seconds = f"{entry['seconds']:.2f}" if "seconds" in entry else "-"
        rays = entry.get("rays", "-")
        workers = ", ".join(entry.get("workers", [])) or "; ".join(entry.get("reasons", []))
        print(f"{name:>6} {status:>8} {seconds:>8} {rays!s:>10} {entry['attempts']:>5}  {workers}")
    slowest = sorted(done, key=lambda name: -done[name].get("seconds", 0))[:3]
    if slowest:
        print("slowest: " + ", ".join(f"{n} ({done[n]['seconds']:.2f} s)" for n in slowest))
    for frame in failed:
        reasons = frames[f"{frame:04d}"]["reasons"]
        print(f"FAILED frame {frame} after {len(reasons)} attempts: {reasons[-1]}")


def main(argv):
    parser = argparse.ArgumentParser(
        prog=prog("whitted_tools.farm.command"),
        description="Render frames (or tiles of a frame) with Whitted on a Dask cluster.",
    )
    parser.add_argument("scene", help="the .blend file")
    parser.add_argument("--frames", type=parse_frames, required=True, help="A-B (or A)")
    parser.add_argument("--tiles", type=parse_tiles, help="NxM tiles per frame")
    parser.add_argument("--scheduler", help="address of an existing Dask scheduler")
    parser.add_argument("--workers", type=int, help="local workers, or workers to wait for")
    parser.add_argument("--output", required=True, help="folder for NNNN.exr and the report")
    parser.add_argument("--retries", type=int, default=2, help="retries of a failed frame")
    parser.add_argument("--blender", default="blender", help="the Blender command on workers")
    parser.add_argument("--threads", type=int, help="Blender threads per task (0: all)")
    parser.add_argument("--timeout", type=float, default=3600, help="seconds per frame")
    parser.add_argument("--chunk", type=int, help="frames per task (default: from their time)")
    parser.add_argument(
        "--cold", action="store_true", help="a fresh Blender for every frame (none kept warm)"
    )
    args = parser.parse_args(argv)
    args.output = os.path.abspath(args.output)
    return run_farm(args)
