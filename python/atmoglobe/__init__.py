"""atmoglobe: radar volumes and forecast grids on an ellipsoidal (WGS84) globe.

The compiled part (``_atmoglobe``) reads radar volumes and grid variables into numpy arrays with
their metadata and renders scenes headless; this file adds the Python-side conveniences:
``render`` takes a scene as a dict (the scene JSON's keys) or a path, images show themselves in
Jupyter, and ``to_xarray`` turns a grid into an ``xarray.Dataset`` when xarray is installed.
Every error is ``atmoglobe.Error`` (a RuntimeError) carrying the CLI's message.
"""

import json as _json
import os as _os

from ._atmoglobe import Error, convert, data_directory, gates, read_grid, read_png, read_radar, write_png
from . import _atmoglobe
from .archive import frame_name, render_archive, write_animation

__all__ = ["Error", "Image", "convert", "data_directory", "frame_name", "gates", "read_grid", "read_png", "read_radar",
           "render", "render_archive", "to_xarray", "write_animation", "write_png"]


class Image:
    """An RGBA frame (``pixels``: H x W x 4 uint8 numpy array) that shows itself in Jupyter.

    ``timings`` (from ``render``): milliseconds spent on the GL context, loading the scene's files
    (read, placed, uploaded), drawing the frame and its legend.
    """

    def __init__(self, pixels):
        self.pixels = pixels
        self.timings = {}

    @property
    def shape(self):
        return self.pixels.shape

    def save(self, path):
        """Writes the frame as a PNG (atomically: a temporary beside it, then renamed)."""
        write_png(_os.fspath(path), self.pixels)

    def _repr_png_(self):
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            p = _os.path.join(d, "frame.png")
            write_png(p, self.pixels)
            with open(p, "rb") as f:
                return f.read()

    def __array__(self, dtype=None):
        return self.pixels if dtype is None else self.pixels.astype(dtype)


def render(scene, legend=True, strict=True):
    """Renders a scene headless (EGL, no display) and returns an ``Image``.

    ``scene`` is a dict with the scene JSON's keys (docs/scenes.md; relative paths from the current
    directory, ``@data/`` the build's data directory) or the path of a scene file. With ``strict``
    (default) an input that cannot be loaded raises; otherwise it is left out, as ``render`` without
    ``--strict`` does. The GIL is released while the frame is drawn.
    """
    if isinstance(scene, dict):
        pixels, timings = _atmoglobe._render(_json.dumps(scene), "", legend, strict)
    else:
        pixels, timings = _atmoglobe._render("", _os.fspath(scene), legend, strict)
    image = Image(pixels)
    image.timings = timings
    return image


def to_xarray(grid):
    """A grid from ``read_grid`` as an ``xarray.Dataset`` (CF names and units); needs xarray."""
    try:
        import xarray as xr
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise ImportError("to_xarray needs xarray (Debian: python3-xarray)") from e
    name = grid["variable"].lstrip("/").split(":")[0]
    dims = ("level", "y", "x") if grid["curvilinear"] else ("level", "latitude", "longitude")
    coords = {}
    if grid["curvilinear"]:
        coords["latitude"] = (("y", "x"), grid["lat_deg"], {"units": "degrees_north", "standard_name": "latitude"})
        coords["longitude"] = (("y", "x"), grid["lon_deg"], {"units": "degrees_east", "standard_name": "longitude"})
    else:
        coords["latitude"] = ("latitude", grid["lat_deg"], {"units": "degrees_north", "standard_name": "latitude"})
        coords["longitude"] = ("longitude", grid["lon_deg"], {"units": "degrees_east", "standard_name": "longitude"})
    coords["level"] = ("level", grid["level_values"], {"units": grid["level_units"]})
    attrs = {"units": grid["units"]}
    if grid["standard_name"]:
        attrs["standard_name"] = grid["standard_name"]
    if grid["long_name"]:
        attrs["long_name"] = grid["long_name"]
    height = xr.DataArray(grid["height_m"], dims=dims,
                          attrs={"units": "m", "standard_name": "height_above_reference_ellipsoid"})
    return xr.Dataset({name: xr.DataArray(grid["values"], dims=dims, attrs=attrs), "height": height},
                      coords=coords, attrs={"source": grid["path"], "valid_time": grid["valid_time"]})
