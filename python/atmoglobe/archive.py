"""Rendering an archive: one frame per input, serially or on a Dask cluster (docs/scale-out.md).

Each frame is one task: the scene with the input in place (a radar volume, a grid file or step, a
network time), drawn headless and written atomically (a temporary beside the frame, renamed into
place; a temporary left by a killed worker is removed by the next write of that frame). Frame names
are deterministic (``frame_00007.png``: the input's index), so a rerun renders only the frames that
are missing, and a task retried after its worker died writes the same file once.
"""

import copy
import os
import sys
import time

from . import _atmoglobe


def frame_name(index):
    """The file name of frame ``index`` of an archive: ``frame_00007.png``."""
    return "frame_%05d.png" % index


def frame_scene(scene, item):
    """The scene of one frame: ``scene`` (a dict with the scene JSON's keys) with ``item`` in place.

    ``item`` is a path (the first radar layer's path; the first grid's where the scene has no
    radar) or a dict of keys merged into the scene: ``{"grids": [{"path": p, "time": t}]}`` for a
    grid step, ``{"radars": [{"path": "dir", "window_minutes": 10}], "time": ...}`` and so on.
    """
    s = copy.deepcopy(scene)
    if isinstance(item, dict):
        for key, value in item.items():
            if isinstance(value, list) and isinstance(s.get(key), list) and value and isinstance(value[0], dict):
                layers = s[key]
                for i, layer in enumerate(value):
                    if i < len(layers):
                        layers[i].update(layer)
                    else:
                        layers.append(layer)
            else:
                s[key] = value
        return s
    path = os.fspath(item)
    if s.get("radars"):
        s["radars"][0]["path"] = path
    elif s.get("grids"):
        s["grids"][0]["path"] = path
    else:
        s["radars"] = [{"path": path}]
    return s


def render_frame(scene, out_path):
    """Renders one frame's scene to ``out_path`` (atomically) unless it is there; returns the path.

    A module-level function, so that Dask workers import it by name.
    """
    if os.path.exists(out_path):
        return out_path
    import json
    pixels, _ = _atmoglobe._render(json.dumps(scene), "", True, True)
    _atmoglobe.write_png(out_path, pixels)
    return out_path


def render_archive(inputs, scene, out_dir, client=None, retries=3, progress=True):
    """Renders one frame per input into ``out_dir`` and returns the frames' paths, in input order.

    ``client``: a ``dask.distributed.Client`` (a ``LocalCluster``'s or a scheduler's address');
    each frame is a task, retried up to ``retries`` times (a worker that dies mid-frame loses
    nothing: the task runs again elsewhere and writes the same file). Without a client the frames
    are drawn here, one after the other. Frames already in ``out_dir`` are not drawn again.
    Progress goes to stderr. Errors (a bad input, a failed task) raise ``atmoglobe.Error`` naming
    the frame and its input.
    """
    os.makedirs(out_dir, exist_ok=True)
    inputs = list(inputs)
    paths = [os.path.join(out_dir, frame_name(i)) for i in range(len(inputs))]
    todo = [i for i, p in enumerate(paths) if not os.path.exists(p)]
    start = time.monotonic()

    def say(done):
        if progress:
            sys.stderr.write("atmoglobe render_archive: %d of %d frames (%d were there), %.1f s\n"
                             % (done + len(inputs) - len(todo), len(inputs), len(inputs) - len(todo),
                                time.monotonic() - start))

    if client is None:
        for n, i in enumerate(todo):
            try:
                render_frame(frame_scene(scene, inputs[i]), paths[i])
            except _atmoglobe.Error as e:
                raise _atmoglobe.Error("frame %d (%s): %s" % (i, inputs[i], e)) from e
            say(n + 1)
        return paths

    from distributed import as_completed
    futures = {}
    for i in todo:
        future = client.submit(render_frame, frame_scene(scene, inputs[i]), paths[i], retries=retries, pure=False)
        futures[future] = i
    done = 0
    for future in as_completed(list(futures)):
        i = futures[future]
        try:
            future.result()
        except Exception as e:  # the task's own error, as the worker raised it
            raise _atmoglobe.Error("frame %d (%s): %s" % (i, inputs[i], e)) from e
        done += 1
        say(done)
    return paths


def write_animation(frames, path, fps=4.0):
    """Assembles frames (PNG paths, in order) into ``path``: an animated GIF (``.gif``) or an
    H.264 MP4 (``.mp4``, through ffmpeg), as ``render --animation`` does."""
    frames = [os.fspath(f) for f in frames]
    if not frames:
        raise _atmoglobe.Error("%s: no frames to assemble" % path)
    _atmoglobe._write_animation(frames, os.fspath(path), float(fps))
