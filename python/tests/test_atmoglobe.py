"""The Python module against the CLI: the same files give the same numbers and pictures.

Run by ctest (python.pytest) with PYTHONPATH at build/python and ATMOGLOBE_CLI the `atmoglobe`
executable of the same build. Data: SYNTHETIC files written by `atmoglobe synth` into
ATMOGLOBE_TEST_OUT; the real sample data (../shared) only where a test says so, skipped without.
"""

import csv
import json
import os
import re
import subprocess
import threading
import time

import numpy as np
import pytest

import atmoglobe

CLI = os.environ.get("ATMOGLOBE_CLI", "atmoglobe")
OUT = os.environ.get("ATMOGLOBE_TEST_OUT", "/tmp/atmoglobe-python-tests")
DATA = os.environ.get("ATMOGLOBE_TEST_DATA", os.environ.get("ATMOGLOBE_TEST_DATA_DEFAULT", ""))


def run(*args):
    result = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert result.returncode == 0, f"atmoglobe {' '.join(args)}: {result.stderr}"
    return result


@pytest.fixture(scope="module")
def radar():
    os.makedirs(OUT, exist_ok=True)
    path = os.path.join(OUT, "radar.nc")
    run("synth", "--gate-spacing", "1000", "-o", path)
    return path


@pytest.fixture(scope="module")
def grid():
    os.makedirs(OUT, exist_ok=True)
    path = os.path.join(OUT, "grid.nc")
    run("synth", "--grid", "--grid-size", "20,15,6,2", "-o", path)
    return path


def test_gates_equal_the_cli_csv(radar):
    csv_path = os.path.join(OUT, "gates.csv")
    run("gates", radar, "--sweep", "1", "-o", csv_path)
    g = atmoglobe.gates(radar, sweep=1)
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(g["lat_deg"]) > 1000
    step = max(1, len(rows) // 5000)  # every 5000th: the whole file is checked by the counts
    for i in range(0, len(rows), step):
        row = rows[i]
        assert int(row["sweep"]) == g["sweep"][i] == 1
        assert int(row["ray"]) == g["ray"][i] and int(row["gate"]) == g["gate"][i]
        # Positions: the CSV prints latitude and longitude with 10 decimals and metres with 4.
        assert abs(float(row["lat_deg"]) - g["lat_deg"][i]) <= 5.1e-11
        assert abs(float(row["lon_deg"]) - g["lon_deg"][i]) <= 5.1e-11
        assert abs(float(row["height_m"]) - g["height_m"][i]) <= 5.1e-5
        assert abs(float(row["ecef_x"]) - g["ecef_x"][i]) <= 5.1e-5
        # Values: the shortest text that reads back to the same float, so bit for bit.
        v = row["value"]
        if v == "":
            assert np.isnan(g["value"][i])
        elif v == "-inf":
            assert g["value"][i] == -np.inf
        else:
            assert np.float32(v) == g["value"][i]


def test_read_radar_holds_the_sweeps_gates_reads(radar):
    r = atmoglobe.read_radar(radar)
    assert r["field"] == "DBZ" and r["units"] == "dBZ" and r["format"].startswith("CfRadial")
    assert r["site"]["name"] == "KTLX"
    assert len(r["sweeps"]) == 14
    s = r["sweeps"][1]
    g = atmoglobe.gates(radar, sweep=1)
    assert s["values"].shape == (len(s["azimuth_deg"]), len(s["range_m"]))
    # The same values in the same order (ray-major), bit for bit (NaN where both are NaN).
    flat = s["values"].reshape(-1)
    same = (flat == g["value"]) | (np.isnan(flat) & np.isnan(g["value"]))
    assert same.all()
    assert np.nanmax(flat) > 40.0  # the storm is there


def test_read_grid_equals_the_file(grid):
    g = atmoglobe.read_grid(grid, time="1")
    assert g["values"].shape == (6, 15, 20) and g["height_m"].shape == (6, 15, 20)
    assert g["units"] == "dBZ" and g["valid_time"] == "2020-05-01T19:00:00Z"
    # ncdump prints the stored shorts; the reader unpacks them (scale_factor 0.01f) to float.
    dump = subprocess.run(["ncdump", "-v", "dbz", grid], capture_output=True, text=True, check=True).stdout
    numbers = re.sub(r"\s+", "", dump.split("dbz =")[-1]).rstrip("};").split(",")
    packed = np.array([int(x) for x in numbers], dtype=np.int32).reshape(2, 6, 15, 20)[1]
    expected = (packed.astype(np.float64) * np.float64(np.float32(0.01))).astype(np.float32)
    # The file's rows run north to south; the grid's run south to north (GridVolume.h).
    assert g["lat_deg"][0] < g["lat_deg"][-1]
    assert np.array_equal(g["values"], expected[:, ::-1, :])
    assert np.all(np.diff(g["height_m"], axis=0) > 0)  # heights increase upwards in every column


def read_nrrd(path):
    """A raw (uncompressed) little-endian float NRRD as `atmoglobe convert --raw` writes it."""
    data = open(path, "rb").read()
    header, _, body = data.partition(b"\n\n")
    fields = dict(line.split(b": ", 1) for line in header.split(b"\n")[1:] if b": " in line)
    assert fields[b"type"] == b"float" and fields[b"encoding"] == b"raw" and fields[b"endian"] == b"little"
    sizes = [int(x) for x in fields[b"sizes"].split()]
    return np.frombuffer(body, dtype="<f4").reshape(sizes[::-1])


def test_convert_equals_the_cli(grid, radar, tmp_path):
    for path, args, kwargs in (
            (grid, ["--time", "1", "--size", "12,9,5"], dict(time="1", size=(12, 9, 5))),
            (radar, ["--crop", "34.5,35.5,-98,-97", "--heights", "1000,9000", "--size", "20,16,9"],
             dict(crop=(34.5, 35.5, -98, -97), heights=(1000, 9000), size=(20, 16, 9))),
            (radar, ["--grid", "cartesian", "--size", "16,16,6", "--interpolation", "nearest"],
             dict(grid="cartesian", size=(16, 16, 6), interpolation="nearest"))):
        nrrd = tmp_path / "out.nrrd"
        run("convert", path, *args, "--raw", "-o", str(nrrd))
        cli = read_nrrd(nrrd)
        mine = atmoglobe.convert(path, **kwargs)["values"]
        assert mine.shape == cli.shape
        # Bit for bit: the same resampling, NaN where the CLI wrote NaN.
        assert np.array_equal(mine, cli, equal_nan=True), (path, args)
        assert np.isfinite(mine).sum() > 5  # values, not only NaN (the storm is small in a 16 x 16 box)
    with pytest.raises(atmoglobe.Error, match="datum: msl or ellipsoid"):
        atmoglobe.convert(grid, datum="geoid")


def test_render_equals_the_cli(radar, tmp_path):
    scene = {"camera": {"lat_deg": 34.35, "lon_deg": -97.0, "height_m": 45000, "heading_deg": 330,
                        "pitch_deg": -28, "roll_deg": 0},
             "fov_deg": 45, "size": [160, 90],
             "radars": [{"path": radar, "step_m": 1000}]}
    scene_path = tmp_path / "scene.json"
    scene_path.write_text(json.dumps(scene))
    png = tmp_path / "cli.png"
    run("render", str(scene_path), "-o", str(png))
    cli = atmoglobe.read_png(str(png))
    image = atmoglobe.render(scene)
    assert image.shape == (90, 160, 4)
    # The same program on the same machine: within 1 of 255 per channel (rounding of the blend).
    assert np.abs(image.pixels.astype(int) - cli.astype(int)).max() <= 1
    coloured = (image.pixels[..., :3].max(axis=2).astype(int) - image.pixels[..., :3].min(axis=2)) > 60
    assert coloured.sum() > 50  # the storm is drawn
    # Where the time went, in ms: every part measured, the frame's drawing included.
    assert set(image.timings) == {"context_ms", "load_ms", "draw_ms", "legend_ms"}
    assert image.timings["draw_ms"] > 0 and image.timings["load_ms"] > 0
    # A path renders the same.
    assert np.array_equal(atmoglobe.render(str(scene_path)).pixels, image.pixels)
    # Jupyter: the image shows itself as a PNG.
    assert image._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"
    saved = tmp_path / "saved.png"
    image.save(saved)
    assert np.array_equal(atmoglobe.read_png(str(saved)), image.pixels)


def test_errors_are_the_cli_messages(tmp_path, radar, grid):
    missing = str(tmp_path / "missing.nc")
    with pytest.raises(atmoglobe.Error, match="missing.nc"):
        atmoglobe.read_radar(missing)
    with pytest.raises(atmoglobe.Error, match="no field 'VEL'"):
        atmoglobe.read_radar(radar, field="VEL")
    with pytest.raises(atmoglobe.Error, match="sweep 99 out of range"):
        atmoglobe.gates(radar, sweep=99)
    with pytest.raises(atmoglobe.Error, match="expected mean, spread"):
        atmoglobe.read_grid(grid, ensemble="median")
    with pytest.raises(atmoglobe.Error, match="unknown key"):
        atmoglobe.render({"camera": {"lat_deg": 1, "hieght_m": 10}})
    with pytest.raises(atmoglobe.Error, match="file not found"):
        atmoglobe.render({"radars": [{"path": missing}], "size": [32, 32]})
    assert issubclass(atmoglobe.Error, RuntimeError)


def test_the_gil_is_released_while_reading(radar):
    # A Python thread counts while the main thread reads: with the GIL held for the whole read it
    # could not run at all.
    counts = []
    done = threading.Event()

    def count():
        n = 0
        while not done.is_set():
            n += 1
            time.sleep(0.001)
        counts.append(n)

    t = threading.Thread(target=count)
    t.start()
    start = time.monotonic()
    for _ in range(3):
        atmoglobe.gates(radar)
    elapsed = time.monotonic() - start
    done.set()
    t.join()
    assert elapsed > 0.05
    assert counts[0] >= 10


def test_to_xarray_when_installed(grid):
    xr = pytest.importorskip("xarray")
    ds = atmoglobe.to_xarray(atmoglobe.read_grid(grid))
    assert ds["dbz"].attrs["units"] == "dBZ"
    assert ds["dbz"].shape == (6, 15, 20)
    assert isinstance(ds, xr.Dataset)


@pytest.mark.skipif(not DATA or not os.path.exists(os.path.join(DATA, "radar_odim/bewid.pvol.hdf")),
                    reason="../shared sample data not present")
def test_real_odim_volume():
    r = atmoglobe.read_radar(os.path.join(DATA, "radar_odim/bewid.pvol.hdf"))
    assert r["format"].startswith("ODIM")
    assert len(r["sweeps"]) == 11
    assert abs(r["site"]["lat_deg"] - 49.914) < 0.01
