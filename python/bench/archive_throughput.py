#!/usr/bin/env python3
"""Benchmark (a program, not a test): rendering an archive of SYNTHETIC radar volumes, serially and
on a Dask LocalCluster of 1 and 2 workers, with the per-frame split and one frame's memory.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/archive_throughput.py [--count 100]
        [--size 640x360] [--out out/archive_bench] [--cli build/tools/atmoglobe]

Volumes: `atmoglobe synth --sites KTLX --steps COUNT --interval 5` (VCP 212 angles, 250 m gates to
230 km, the storm moving), written once. Frames: the volume from 300 km above KTLX looking down,
DVR at the default step. Prints Markdown tables (docs/scale-out.md).
"""

import argparse
import glob
import os
import shutil
import statistics
import subprocess
import sys
import time

import atmoglobe


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--count", type=int, default=100)
    p.add_argument("--size", default="640x360")
    p.add_argument("--out", default="out/archive_bench")
    p.add_argument("--cli", default=os.environ.get("ATMOGLOBE_CLI", "build/tools/atmoglobe"))
    p.add_argument("--split-frames", type=int, default=10)
    a = p.parse_args()
    w, h = (int(x) for x in a.size.split("x"))
    volumes_dir = os.path.join(a.out, "volumes")
    volumes = sorted(glob.glob(os.path.join(volumes_dir, "KTLX_*.nc")))
    if len(volumes) < a.count:
        shutil.rmtree(volumes_dir, ignore_errors=True)
        t0 = time.monotonic()
        subprocess.run([a.cli, "synth", "--sites", "KTLX", "--steps", str(a.count), "--interval", "5",
                        "-o", volumes_dir], check=True, capture_output=True)
        print("volumes written in %.1f s" % (time.monotonic() - t0), file=sys.stderr)
        volumes = sorted(glob.glob(os.path.join(volumes_dir, "KTLX_*.nc")))
    volumes = volumes[:a.count]
    scene = {"camera": {"lat_deg": 35.33, "lon_deg": -97.28, "height_m": 3.0e5, "heading_deg": 0,
                        "pitch_deg": -90, "roll_deg": 0},
             "fov_deg": 60, "size": [w, h], "radars": [{"path": ""}]}
    print("cores: %d; %d volumes of %.1f MB each; frames %dx%d\n"
          % (os.cpu_count(), len(volumes), os.path.getsize(volumes[0]) / 1e6, w, h))

    # The per-frame split, in this process, over the first frames.
    rows = {k: [] for k in ("read", "context", "load", "draw", "legend", "encode", "total")}
    tmp = os.path.join(a.out, "split")
    os.makedirs(tmp, exist_ok=True)
    for path in volumes[:a.split_frames]:
        t0 = time.monotonic()
        atmoglobe.read_radar(path)
        rows["read"].append((time.monotonic() - t0) * 1e3)
        t0 = time.monotonic()
        image = atmoglobe.render(atmoglobe.archive.frame_scene(scene, path))
        t1 = time.monotonic()
        image.save(os.path.join(tmp, "f.png"))
        rows["encode"].append((time.monotonic() - t1) * 1e3)
        rows["total"].append((time.monotonic() - t0) * 1e3)
        for k in ("context", "load", "draw", "legend"):
            rows[k].append(image.timings[k + "_ms"])
    med = {k: statistics.median(v) for k, v in rows.items()}
    print("| part | median ms per frame (%d frames) |" % a.split_frames)
    print("|---|---|")
    print("| read the volume (read_radar alone) | %.0f |" % med["read"])
    print("| GL context (one per frame) | %.0f |" % med["context"])
    print("| load: read, place and upload (upload = load - read) | %.0f (upload %.0f) |"
          % (med["load"], med["load"] - med["read"]))
    print("| draw: march and read back | %.0f |" % med["draw"])
    print("| legend | %.0f |" % med["legend"])
    print("| encode: PNG, atomic write | %.0f |" % med["encode"])
    print("| whole frame | %.0f |" % med["total"])

    # One frame's memory: a fresh process renders one frame; its peak RSS (VmHWM: ru_maxrss would
    # carry this process' peak across fork and exec) against the import alone.
    probe = ("import atmoglobe, sys, json; s=json.loads(sys.argv[1]); "
             "hwm=lambda: int([l for l in open('/proc/self/status') if l.startswith('VmHWM')][0].split()[1]); "
             "base=hwm(); atmoglobe.render(s); print(base, hwm())")
    import json
    out = subprocess.run([sys.executable, "-c", probe, json.dumps(atmoglobe.archive.frame_scene(scene, volumes[0]))],
                         check=True, capture_output=True, text=True).stdout.split()
    base, peak = int(out[0]) / 1024, int(out[1]) / 1024
    print("\none frame: peak RSS %.0f MiB (the interpreter with the module imported: %.0f MiB; the frame adds %.0f MiB)\n"
          % (peak, base, peak - base))

    # Throughput: the whole archive serially, then on 1 and 2 workers.
    print("| how | frames | wall s | frames/s | / serial |")
    print("|---|---|---|---|---|")
    serial_rate = None
    for label, workers in (("serial (no Dask)", 0), ("LocalCluster, 1 worker", 1), ("LocalCluster, 2 workers", 2)):
        d = os.path.join(a.out, "frames_%d" % workers)
        shutil.rmtree(d, ignore_errors=True)
        client = cluster = None
        if workers:
            import distributed
            cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                               dashboard_address=None, silence_logs=50)
            client = distributed.Client(cluster)
        t0 = time.monotonic()
        atmoglobe.render_archive(volumes, scene, d, client=client, progress=False)
        wall = time.monotonic() - t0
        if client:
            client.close()
            cluster.close()
        rate = len(volumes) / wall
        serial_rate = serial_rate or rate
        print("| %s | %d | %.1f | %.2f | %.2f |" % (label, len(volumes), wall, rate, rate / serial_rate))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
