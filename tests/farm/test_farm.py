"""The farm verb on a real Dask cluster of separate processes (a `dask scheduler` and
two `dask worker` processes over TCP on 127.0.0.1), and the failure signal Whitted
gives farms it does not drive, and the Flamenco job type that uses it
(tools/flamenco/whitted_render.js: compiled by node, its commands run here).

    .venv/bin/python -m pytest tests/farm -q

Renders with Blender 3.4 and the development install (scripts/setup.sh links it).
"""

import contextlib
import json
import os
import shlex
import shutil
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import OpenEXR
import pytest
from whitted_tools.blender import verb_in_blender
from whitted_tools.farm.render import blender_args

REPO_ROOT = Path(__file__).resolve().parents[2]
VENV_BIN = REPO_ROOT / ".venv" / "bin"
FARM = [str(VENV_BIN / "python"), "-m", "whitted_tools", "farm"]
FRAMES = range(1, 7)


def run(command, env=None, timeout=300, ok=True):
    result = subprocess.run(
        command, env=env, capture_output=True, text=True, timeout=timeout, check=False
    )
    if ok:
        assert result.returncode == 0, (
            f"{command[:4]} exited {result.returncode}\n{result.stdout[-3000:]}\n"
            f"{result.stderr[-3000:]}"
        )
    return result


def pixels(path):
    with OpenEXR.File(str(path)) as exr:
        return exr.channels()["RGBA"].pixels.copy()


def identical(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def assert_reference_frames(out, scenes, frames=FRAMES):
    """Each of `frames` in `out` is the single-machine reference frame, bit for bit."""
    for frame in frames:
        got = pixels(out / f"{frame:04d}.exr")
        assert identical(got, pixels(scenes / "reference" / f"{frame:04d}.exr")), frame


@pytest.fixture(scope="module")
def scenes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("scenes")
    for name, extra in (("anim", []), ("broken", ["--fail"])):
        run(verb_in_blender("farm-scene", folder / f"{name}.blend", *extra))
    # The single-machine reference: all six frames in one Blender, no farm.
    reference = folder / "reference"
    reference.mkdir()
    run(blender_args(str(folder / "anim.blend"), str(reference / "####"), "1..6"))
    # The camera moves: a background render reads it as evaluated at each frame.
    first, last = (pixels(reference / f"{frame:04d}.exr") for frame in (1, 6))
    assert not identical(first, last)
    return folder


@contextlib.contextmanager
def dask_cluster(folder):
    """A scheduler and two workers (w0, w1), each its own process (no nanny: killing
    a worker's process kills the worker), logging into `folder`."""
    scheduler_file = folder / "scheduler.json"
    processes = [
        subprocess.Popen(
            [
                str(VENV_BIN / "dask"),
                "scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                "0",
                "--no-dashboard",
                "--scheduler-file",
                str(scheduler_file),
            ],
            stdout=subprocess.DEVNULL,
            stderr=open(folder / "scheduler.log", "w"),  # noqa: SIM115
        )
    ]
    deadline = time.time() + 60
    while not scheduler_file.exists() and time.time() < deadline:
        time.sleep(0.1)
    address = json.loads(scheduler_file.read_text())["address"]
    workers = []
    for index in range(2):
        worker = subprocess.Popen(
            [
                str(VENV_BIN / "dask"),
                "worker",
                address,
                "--nthreads",
                "1",
                "--no-nanny",
                "--no-dashboard",
                "--host",
                "127.0.0.1",
                "--name",
                f"w{index}",
            ],
            stdout=subprocess.DEVNULL,
            stderr=open(folder / f"worker{index}.log", "w"),  # noqa: SIM115
        )
        workers.append(worker)
    processes += workers
    try:
        yield {"address": address, "workers": workers}
    finally:
        for process in processes:
            if process.poll() is None:
                process.terminate()
        for process in processes:
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    with dask_cluster(tmp_path_factory.mktemp("cluster")) as running:
        yield running


def children(pid):
    """Pids of the direct children of `pid` (from /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                found.append(int(entry.name))
    return found


def rendering_blenders(pid):
    """Pids of the farm Blenders, children of worker `pid`, that are rendering a frame
    (whitted_tools farm keeps each one's log, emptied before each frame, beside it)."""
    found = []
    for child in children(pid):
        try:
            argv = (Path("/proc") / str(child) / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if b"--serve" not in argv:
            continue
        script = Path(argv[argv.index(b"--python") + 1].decode())
        for log in script.parent.glob("blender-*/blender.log"):
            if "Fra:" in log.read_text(errors="replace"):
                found.append(child)
                break
    return found


def kill_when_rendering(farm, pid, kill_worker):
    """SIGKILL worker `pid` (kill_worker) or its Blender as soon as that Blender is
    rendering; True when it happened before the farm ended."""
    deadline = time.time() + 120
    while farm.poll() is None and time.time() < deadline:
        blenders = rendering_blenders(pid)
        if blenders:
            os.kill(pid if kill_worker else blenders[0], signal.SIGKILL)
            return True
        time.sleep(0.01)
    return False


def report(folder):
    return json.loads((folder / "farm_report.json").read_text())


def test_frames_survive_a_killed_worker_and_a_rerun_renders_nothing(scenes, cluster, tmp_path):
    out = tmp_path / "frames"
    command = [
        *FARM,
        str(scenes / "anim.blend"),
        "--frames",
        "1-6",
        "--scheduler",
        cluster["address"],
        "--workers",
        "2",
        "--output",
        str(out),
    ]
    farm = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    victim = cluster["workers"][0]
    # Kill worker 0 with SIGKILL while its Blender is rendering a frame of a task.
    killed_mid_frame = kill_when_rendering(farm, victim.pid, kill_worker=True)
    output, _ = farm.communicate(timeout=300)
    print(output)
    assert killed_mid_frame, "worker 0's Blender never rendered while the farm ran"
    assert victim.wait(timeout=10) == -signal.SIGKILL
    assert farm.returncode == 0, output
    assert_reference_frames(out, scenes)
    assert not list(out.glob("*.partial"))
    first = report(out)
    assert first["status"] == "done" and first["rendered"] == 6
    assert "dashboard http://" in output
    # Blender stayed warm: each worker's first frame started its Blender, no other did.
    assert sum(f["started_blender"] for f in first["frames"].values()) <= 2, first["frames"]

    # The same command again: everything is there, nothing is rendered.
    mtimes = {p.name: p.stat().st_mtime_ns for p in out.glob("*.exr")}
    again = run(command)
    assert "6 frames, 0 to render" in again.stdout, again.stdout
    assert {p.name: p.stat().st_mtime_ns for p in out.glob("*.exr")} == mtimes
    assert report(out)["rendered"] == 0 and report(out)["skipped"] == 6


def test_a_worker_dying_as_the_run_ends_does_not_fail_it(tmp_path):
    """The end of a run removes its plugin from every worker. A worker that dies then,
    before the scheduler notices, makes the scheduler's removal fail and drop the
    farm's connection (a CI run lost a finished farm to this): the live workers are
    still released, one by one, and nothing is raised."""
    torn_down = tmp_path / "torn_down"
    torn_down.mkdir()
    with dask_cluster(tmp_path) as running:
        result = run(
            [
                *FARM[:1],
                str(Path(__file__).with_name("release_probe.py")),
                running["address"],
                str(torn_down),
            ]
        )
        assert running["workers"][0].wait(timeout=30) == 1  # w0 died in the removal
    assert "the scheduler could not end the warm Blenders" in result.stdout, result.stdout
    assert sorted(p.name for p in torn_down.iterdir()) == ["w1"], result.stdout


def test_a_crashed_blender_loses_only_its_frame(scenes, cluster, tmp_path):
    """A warm Blender killed mid-chunk: the frame it was rendering is retried, the
    chunk's next frames start a fresh Blender on the same worker."""
    out = tmp_path / "crash"
    command = [*FARM, str(scenes / "anim.blend"), "--frames", "1-6", "--chunk", "3"]
    command += ["--scheduler", cluster["address"], "--output", str(out)]
    farm = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    worker = cluster["workers"][1]
    killed = kill_when_rendering(farm, worker.pid, kill_worker=False)
    output, _ = farm.communicate(timeout=300)
    print(output)
    assert killed, "the worker's Blender never rendered while the farm ran"
    assert farm.returncode == 0, output
    assert worker.poll() is None
    assert_reference_frames(out, scenes)
    frames = report(out)["frames"].values()
    retried = [f for f in frames if f["attempts"] > 1]
    assert len(retried) == 1, frames
    assert "Blender killed by signal 9" in retried[0]["retry_reasons"][0], retried


def test_tiles_stitch_into_the_single_machine_frame(scenes, cluster, tmp_path):
    out = tmp_path / "tiles"
    run(
        [
            *FARM,
            str(scenes / "anim.blend"),
            "--frames",
            "1-1",
            "--tiles",
            "2x2",
            "--scheduler",
            cluster["address"],
            "--output",
            str(out),
        ]
    )
    assert identical(pixels(out / "0001.exr"), pixels(scenes / "reference" / "0001.exr"))
    # Each tile rendered only its share of the frame's camera rays (4 per pixel).
    entry = report(out)["frames"]["0001"]
    assert entry["status"] == "done"


def test_a_failing_scene_is_retried_then_reported_failed(scenes, cluster, tmp_path):
    out = tmp_path / "broken"
    result = run(
        [
            *FARM,
            str(scenes / "broken.blend"),
            "--frames",
            "1-1",
            "--retries",
            "1",
            "--scheduler",
            cluster["address"],
            "--output",
            str(out),
        ],
        ok=False,
    )
    print(result.stdout, result.stderr[-2000:])
    assert result.returncode != 0
    entry = report(out)["frames"]["0001"]
    assert entry["status"] == "failed" and entry["attempts"] == 2, entry
    assert all("zero scale" in reason for reason in entry["reasons"]), entry
    assert "exited 3" in entry["reasons"][0]
    assert not (out / "0001.exr").exists()
    assert "FAILED frame 1" in result.stdout


@pytest.mark.parametrize("cold", [False, True], ids=["warm", "cold"])
def test_local_cluster_by_default(scenes, tmp_path, cold):
    out = tmp_path / "local"
    command = [*FARM, str(scenes / "anim.blend"), "--frames", "2-5", "--workers", "2"]
    run([*command, "--output", str(out), *(["--cold"] if cold else [])])
    assert_reference_frames(out, scenes, (2, 3, 4, 5))
    # Warm: a Blender per worker; cold: a Blender per frame.
    started = sum(f["started_blender"] for f in report(out)["frames"].values())
    assert started == 4 if cold else started <= 2


def test_farms_we_do_not_drive_see_a_failed_frame(scenes, tmp_path):
    """`blender -b FILE -E WHITTED -f N`: with WHITTED_EXIT_ON_ERROR=1 a failed frame
    exits 3 with one clear log line and no image; WHITTED_STATS says why either way."""
    stats = tmp_path / "stats.json"
    command = [
        "blender",
        "-b",
        str(scenes / "broken.blend"),
        "-E",
        "WHITTED",
        "-o",
        str(tmp_path / "frame_####"),
        "-f",
        "1",
    ]
    env = dict(os.environ, WHITTED_STATS=str(stats))
    # Blender's own exit code after an engine error is no signal: 0 when the engine
    # had begun a result (the guide's probe), 1 here where it had not.
    run(command, env=env, ok=False)
    assert json.loads(stats.read_text())["status"] == "failed"
    stats.unlink()
    strict = run(command, env={**env, "WHITTED_EXIT_ON_ERROR": "1"}, ok=False)
    assert strict.returncode == 3, strict.stdout
    assert "Whitted: RENDER FAILED: frame 1: camera 'Camera' has a zero scale" in strict.stderr
    failure = json.loads(stats.read_text())
    assert failure == {**failure, "status": "failed", "frame": 1}
    assert not list(tmp_path.glob("frame_*"))
    # A good frame: exit 0 and status ok.
    good = [
        "blender",
        "-b",
        str(scenes / "anim.blend"),
        "-E",
        "WHITTED",
        "-o",
        str(tmp_path / "good_####"),
        "-f",
        "1",
    ]
    assert run(good, env={**env, "WHITTED_EXIT_ON_ERROR": "1"}).returncode == 0
    assert json.loads(stats.read_text())["status"] == "ok"


def flamenco_tasks(settings):
    """The tasks tools/flamenco/whitted_render.js makes of a job with `settings`
    (compiled by node, tests/farm/flamenco_compile.js)."""
    compiler = Path(__file__).with_name("flamenco_compile.js")
    job_type = REPO_ROOT / "tools" / "flamenco" / "whitted_render.js"
    result = run(["node", str(compiler), str(job_type), json.dumps(settings)])
    return json.loads(result.stdout)["tasks"]


def flamenco_command(command, blender="blender", blender_args="-b -y"):
    """The command line a Flamenco worker runs for a blender-render command: the
    executable, its arguments ({blenderArgs}, shell-split), argsBefore, the blend
    file, args (Flamenco's internal/worker/command_blender.go)."""
    parameters = command["parameters"]
    assert command["name"] == "blender-render"
    assert (parameters["exe"], parameters["exeArgs"]) == ("{blender}", "{blenderArgs}")
    return [
        blender,
        *shlex.split(blender_args),
        *parameters["argsBefore"],
        parameters["blendfile"],
        *parameters["args"],
    ]


@pytest.mark.skipif(shutil.which("node") is None, reason="needs node to run the job type")
def test_the_flamenco_job_type_renders_chunks_and_fails_a_broken_frame(scenes, tmp_path):
    settings = {
        "frames": "1-6",
        "chunk_size": 4,
        "render_output_path": str(tmp_path / "out" / "{timestamp}" / "######"),
        "blendfile": str(scenes / "anim.blend"),
        "format": "OPEN_EXR",
    }
    tasks = flamenco_tasks(settings)
    assert [task["name"] for task in tasks] == ["render-1-4", "render-5,6"]
    for task in tasks:
        (command,) = task["commands"]
        run(flamenco_command(command))
    out = tmp_path / "out" / "2024-01-02_030405"
    assert sorted(p.name for p in out.iterdir()) == [f"{f:06d}.exr" for f in FRAMES]
    for frame in FRAMES:
        # The scene's EXR is half float: the reference's float frame, rounded.
        got = pixels(out / f"{frame:06d}.exr")
        reference = pixels(scenes / "reference" / f"{frame:04d}.exr")
        assert np.allclose(got, reference, rtol=2e-3, atol=2e-3), frame

    broken = flamenco_tasks({**settings, "blendfile": str(scenes / "broken.blend")})
    failed = run(flamenco_command(broken[0]["commands"][0]), ok=False)
    assert failed.returncode == 3, failed.stdout[-2000:]
    assert "Whitted: RENDER FAILED: frame 1:" in failed.stderr
