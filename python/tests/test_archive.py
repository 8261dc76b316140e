"""Archive rendering (atmoglobe.render_archive): serially, on a 2-worker Dask LocalCluster with a
worker killed mid-run, and again with frames already there (docs/scale-out.md)."""

import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import atmoglobe

CLI = os.environ.get("ATMOGLOBE_CLI", "atmoglobe")
OUT = os.environ.get("ATMOGLOBE_TEST_OUT", "/tmp/atmoglobe-python-tests")
FRAMES = 6

SCENE = {"camera": {"lat_deg": 34.6, "lon_deg": -97.6, "height_m": 3.0e5, "heading_deg": 0, "pitch_deg": -90,
                    "roll_deg": 0},
         "fov_deg": 45, "size": [96, 64], "radars": [{"path": "", "step_m": 1000}]}


@pytest.fixture(scope="module")
def volumes():
    """Six SYNTHETIC volumes of a storm moving east, 5 minutes apart."""
    d = os.path.join(OUT, "archive_volumes")
    os.makedirs(d, exist_ok=True)
    paths = []
    for i in range(FRAMES):
        p = os.path.join(d, "v%d.nc" % i)
        if not os.path.exists(p):
            subprocess.run([CLI, "synth", "--gate-spacing", "1000", "--storm-east", str(-60 + 12 * i),
                            "--time", "2020-05-01T21:%02d:00Z" % (5 * i), "-o", p], check=True, capture_output=True)
        paths.append(p)
    return paths


def load(paths):
    return [atmoglobe.read_png(p) for p in paths]


def test_serial_then_dask_with_a_worker_killed(volumes, tmp_path):
    serial = atmoglobe.render_archive(volumes, SCENE, tmp_path / "serial", progress=False)
    assert [os.path.basename(p) for p in serial] == [atmoglobe.frame_name(i) for i in range(FRAMES)]
    reference = load(serial)
    assert not np.array_equal(reference[0], reference[-1]), "the storm moves between frames"

    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                       silence_logs=50)
    client = distributed.Client(cluster)
    try:
        out = tmp_path / "dask"
        killed = []

        def kill_a_worker_once_a_frame_is_done():
            # When the first frame is written, the other worker is inside a frame: kill it (SIGKILL,
            # as the OOM killer or a lost node would). Its nanny starts a new worker and the task
            # runs again.
            deadline = time.monotonic() + 120
            while time.monotonic() < deadline and not list(out.glob("frame_*.png")):
                time.sleep(0.02)
            pids = client.run(os.getpid)
            victim = sorted(pids.values())[0]
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

        killer = threading.Thread(target=kill_a_worker_once_a_frame_is_done)
        killer.start()
        frames = atmoglobe.render_archive(volumes, SCENE, out, client=client, progress=False)
        killer.join()
        assert killed, "a worker was killed"
        names = sorted(os.listdir(out))
        # Every frame once, nothing else (no temporary of the killed worker left behind).
        assert names == [atmoglobe.frame_name(i) for i in range(FRAMES)], names
        for a, b in zip(load(frames), reference):
            assert np.abs(a.astype(int) - b.astype(int)).max() <= 1
        # A rerun renders only what is missing.
        os.remove(frames[2])
        before = {p: os.stat(p).st_mtime_ns for p in frames if os.path.exists(p)}
        again = atmoglobe.render_archive(volumes, SCENE, out, client=client, progress=False)
        assert again == frames
        for p, t in before.items():
            assert os.stat(p).st_mtime_ns == t, "an existing frame was drawn again"
        assert np.abs(atmoglobe.read_png(frames[2]).astype(int) - reference[2].astype(int)).max() <= 1
    finally:
        client.close()
        cluster.close()


def test_animation_and_errors(volumes, tmp_path):
    frames = atmoglobe.render_archive(volumes[:3], SCENE, tmp_path / "frames", progress=False)
    gif = tmp_path / "loop.gif"
    atmoglobe.write_animation(frames, gif, fps=2)
    assert gif.read_bytes()[:6] == b"GIF89a"
    with pytest.raises(atmoglobe.Error, match="must end in .gif or .mp4"):
        atmoglobe.write_animation(frames, tmp_path / "loop.avi")
    with pytest.raises(atmoglobe.Error, match=r"frame 1 \(.*missing.nc\).*file not found"):
        atmoglobe.render_archive([volumes[0], str(tmp_path / "missing.nc")], SCENE, tmp_path / "bad", progress=False)
