"""Render a frame range, or one frame split into tiles, with Whitted on a Dask
distributed cluster.

    .venv/bin/python scripts/farm.py SCENE.blend --frames A-B [--tiles NxM]
        [--scheduler ADDRESS] [--workers N] [--retries K] [--blender CMD]
        [--threads T] [--timeout S] --output DIR

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
- Each task runs `CMD -b scene.blend -E WHITTED --python-expr ... -f N` (CMD:
  Blender 3.4 by default, with the Whitted add-on of its user preferences: the
  development install or the installed package) with WHITTED_STATS and
  WHITTED_EXIT_ON_ERROR=1, so a failed Whitted frame ends Blender with exit 3.
- A task fails when Blender exits non-zero or crashes, times out, writes no image,
  an image of the wrong size, or the statistics say the engine failed. A failed
  frame is retried, preferably on another worker, up to --retries times, then
  reported failed with its reasons. A worker that dies mid-frame loses nothing:
  the scheduler gives its task to another worker (and Blender dies with its
  worker: PR_SET_PDEATHSIG).
- Frames are written atomically (NNNN.exr.partial, checked by decoding it, then
  renamed); the report, rewritten atomically after each frame, records each frame's
  key (the scene file's hash, the frame, tiles, Blender command) and the image's
  hash: a rerun skips frames whose image is there, unchanged, with the same key.
- --tiles NxM renders each frame as N columns x M rows through Blender's render
  border and crop (Whitted traces only the border) and stitches the tiles; a
  render is a pure function of scene and settings, so the stitched frame equals a
  single render bit for bit (tests/farm).
"""

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile
import time

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REPORT_NAME = "farm_report.json"

# The render settings every task (and tests/farm's single-machine reference) applies
# after loading the scene: float EXR output, and the tile's border when there is one.
SETTINGS_EXPR = """
import bpy
scene = bpy.context.scene
render = scene.render
settings = render.image_settings
if hasattr(settings, "media_type"):
    settings.media_type = "IMAGE"
settings.file_format = "OPEN_EXR"
settings.color_depth = "32"
settings.exr_codec = "ZIP"
settings.color_mode = "RGBA"
render.use_file_extension = True
render.filepath = {output!r}
border = {border!r}
render.use_border = border is not None
render.use_crop_to_border = border is not None
if border is not None:
    render.border_min_x, render.border_min_y, render.border_max_x, render.border_max_y = border
"""


def blender_args(blend, output, frame, border=None, threads=0, blender="blender"):
    """The command line of one task: `frame` (an int, or "S..E" for the reference)."""
    expr = SETTINGS_EXPR.format(output=output, border=border)
    command = [*blender.split(), "-b", blend, "-E", "WHITTED", "--python-expr", expr]
    if threads:
        command += ["-t", str(threads)]
    if isinstance(frame, str) and ".." in frame:
        start, end = frame.split("..")
        return [*command, "-s", start, "-e", end, "-a"]
    return [*command, "-f", str(frame)]


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
    import ctypes
    import signal

    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


def render_task(blend_bytes, blend_hash, frame, border, threads, blender, timeout):
    """Render one frame (or one tile) on this worker. Returns a dict: ok, and either
    exr (bytes), stats, seconds or reason; always worker and host."""
    import glob
    import shutil
    import socket

    try:
        from distributed import get_worker

        worker = get_worker().address
    except (ImportError, ValueError):
        worker = "local"
    started = time.perf_counter()
    result = {"worker": worker, "host": socket.gethostname(), "frame": frame}
    cache = os.path.join(tempfile.gettempdir(), "whitted-farm-cache")
    os.makedirs(cache, exist_ok=True)
    blend = os.path.join(cache, f"{blend_hash}.blend")
    if not os.path.exists(blend):
        partial = f"{blend}.{os.getpid()}.partial"
        with open(partial, "wb") as out:
            out.write(blend_bytes)
        os.replace(partial, blend)
    work = tempfile.mkdtemp(prefix="whitted-farm-task-")
    try:
        stats_path = os.path.join(work, "stats.json")
        env = dict(os.environ, WHITTED_STATS=stats_path, WHITTED_EXIT_ON_ERROR="1")
        command = blender_args(
            blend, os.path.join(work, "frame_####"), frame, border, threads, blender
        )
        try:
            process = subprocess.run(
                command,
                env=env,
                capture_output=True,
                text=True,
                timeout=timeout,
                preexec_fn=_die_with_parent,
                check=False,
            )
        except subprocess.TimeoutExpired:
            return {**result, "ok": False, "reason": f"Blender timed out after {timeout} s"}
        log = (process.stdout + process.stderr).splitlines()
        failed = [line for line in log if "RENDER FAILED" in line or line.startswith("Error")]
        images = glob.glob(os.path.join(work, "frame_*.exr"))
        stats = None
        if os.path.exists(stats_path):
            with open(stats_path, encoding="utf-8") as source:
                stats = json.load(source)
        reason = None
        if process.returncode != 0:
            code = process.returncode
            what = f"killed by signal {-code}" if code < 0 else f"exited {code}"
            reason = f"Blender {what}" + (f": {failed[-1]}" if failed else "")
        elif stats is None:
            reason = "no WHITTED_STATS file (did Whitted render at all?)"
        elif stats.get("status") != "ok":
            reason = f"Whitted failed: {stats.get('error')}"
        elif len(images) != 1:
            reason = f"Blender wrote {len(images)} images"
        if reason:
            tail = "\n".join(log[-15:])
            return {**result, "ok": False, "reason": reason, "log": tail}
        with open(images[0], "rb") as source:
            exr = source.read()
        seconds = time.perf_counter() - started
        return {**result, "ok": True, "exr": exr, "stats": stats, "seconds": seconds}
    finally:
        shutil.rmtree(work, ignore_errors=True)


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


def packed_scene(blend, blender):
    """The scene with its external files packed, as bytes (what workers receive)."""
    with tempfile.TemporaryDirectory(prefix="whitted-farm-pack-") as folder:
        packed = os.path.join(folder, "packed.blend")
        command = [*blender.split(), "-b", blend, "--python-exit-code", "1"]
        command += ["--python-expr", PACK_EXPR, "--", packed]
        process = subprocess.run(command, capture_output=True, text=True, check=False)
        if process.returncode != 0 or not os.path.exists(packed):
            sys.exit(f"farm: could not pack {blend}:\n{process.stdout[-2000:]}{process.stderr}")
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


def run_farm(args):
    import numpy as np
    from distributed import Client, LocalCluster, as_completed

    blend = os.path.abspath(args.scene)
    if not os.path.isfile(blend):
        sys.exit(f"farm: no such file: {blend}")
    os.makedirs(args.output, exist_ok=True)
    scene_hash = file_hash(blend)
    tiles = args.tiles
    meta = {
        "scene": blend,
        "scene_sha256": scene_hash,
        "blender": args.blender,
        "tiles": list(tiles) if tiles else None,
        "retries_allowed": args.retries,
    }
    report = Report(args.output, meta)

    def key_of(frame):
        text = json.dumps([scene_hash, frame, tiles, args.blender, SETTINGS_EXPR])
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

    cluster = None
    if args.scheduler:
        client = Client(args.scheduler)
        if args.workers:
            client.wait_for_workers(args.workers, timeout=120)
    else:
        workers = args.workers or os.cpu_count() or 1
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0"
        )
        client = Client(cluster)
    try:
        print(f"[farm] scheduler {client.scheduler.address}, dashboard {client.dashboard_link}")
        print(f"[farm] workers: {len(client.scheduler_info()['workers'])}", flush=True)
        scene_bytes = packed_scene(blend, args.blender)
        packed_hash = hashlib.sha256(scene_bytes).hexdigest()
        # One copy to every worker now; a worker that joins later fetches it from a peer.
        scene_future = client.scatter(scene_bytes, broadcast=True, hash=False)
        threads = args.threads if args.threads is not None else (0 if args.scheduler else 1)

        parts = [(i, j) for j in range(tiles[1]) for i in range(tiles[0])] if tiles else [None]
        jobs = {}  # future -> (frame, part, attempt, workers that failed it)
        ac = as_completed()

        def submit(frame, part, attempt, failed_on):
            border = tile_border(part, tiles) if part else None
            others = [w for w in client.scheduler_info()["workers"] if w not in failed_on]
            # Another worker than the ones that failed it, if any is left (loose: the
            # task still runs when those workers are gone).
            placement = (
                {"workers": others, "allow_other_workers": True} if failed_on and others else {}
            )
            future = client.submit(
                render_task,
                scene_future,
                packed_hash,
                frame,
                border,
                threads,
                args.blender,
                args.timeout,
                key=f"whitted-{frame:04d}-{part}-{attempt}-{packed_hash[:8]}",
                pure=False,
                **placement,
            )
            jobs[future] = (frame, part, attempt, failed_on)
            ac.add(future)

        for frame in todo:
            for part in parts:
                submit(frame, part, 0, ())

        pieces = {frame: {} for frame in todo}
        attempts = {frame: 0 for frame in todo}
        reasons = {frame: [] for frame in todo}
        failed_frames = []
        progress.show()
        for future in ac:
            frame, part, attempt, failed_on = jobs.pop(future)
            if frame in failed_frames:
                continue
            try:
                result = future.result()
            except Exception as error:  # noqa: BLE001 (KilledWorker, a lost scene copy: retry)
                result = {"ok": False, "reason": f"{type(error).__name__}: {error}", "worker": "?"}
            if result["ok"]:
                try:
                    pixels, _ = read_exr(result["exr"])
                    width, height = frame_size(result["stats"])
                    expected = (height, width)
                    if part:
                        xmin, ymin, xmax, ymax = tile_region(
                            tile_border(part, tiles), width, height
                        )
                        expected = (ymax - ymin, xmax - xmin)
                    if pixels.shape[:2] != expected:
                        raise ValueError(f"image {pixels.shape[:2]} instead of {expected}")
                except Exception as error:  # noqa: BLE001 (any damage: retry the frame)
                    result = {**result, "ok": False, "reason": f"bad image: {error}"}
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
                    submit(frame, part, attempt + 1, (*failed_on, result["worker"]))
                progress.show()
                continue
            pieces[frame][part] = (pixels, result)
            if len(pieces[frame]) < len(parts):
                continue
            name = f"{frame:04d}"
            image = os.path.join(args.output, f"{name}.exr")
            results = [r for _, r in pieces[frame].values()]
            if part is None:
                write_atomic(image, data=result["exr"])
            else:
                write_atomic(image, pixels=stitch(pieces[frame], tiles, results[0]["stats"]))
            report.frames[name] = {
                "status": "done",
                "key": key_of(frame),
                "sha256": file_hash(image),
                "seconds": round(sum(r["seconds"] for r in results), 3),
                "rays": sum(r["stats"]["rays"]["total"] for r in results),
                "workers": sorted({r["worker"] for r in results}),
                "attempts": attempts[frame] + 1,
                "retry_reasons": reasons[frame],
            }
            del pieces[frame]
            progress.done += 1
            report.save("running")
            progress.show()
        progress.show(final=True)
        status = "failed" if failed_frames else "done"
        rendered = len(todo) - len(failed_frames)
        report.save(status, {"rendered": rendered, "skipped": progress.skipped})
        print_table(report.frames, failed_frames)
        np.seterr(all="ignore")
        return 1 if failed_frames else 0
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def frame_size(stats):
    settings = stats["settings"]
    return settings["width"], settings["height"]


def stitch(pieces, tiles, stats):
    """The frame from its tiles: {(i, j): (pixels top row first, result)}."""
    import numpy as np

    width, height = frame_size(stats)
    frame = np.zeros((height, width, 4), np.float32)
    for part, (pixels, _) in pieces.items():
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


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Render frames (or tiles of a frame) with Whitted on a Dask cluster."
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
    parser.add_argument("--timeout", type=float, default=3600, help="seconds per task")
    args = parser.parse_args(argv)
    args.output = os.path.abspath(args.output)
    return run_farm(args)


if __name__ == "__main__":
    sys.exit(main())
