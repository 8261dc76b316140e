#!/usr/bin/python3
"""The side-by-side peer of `atmoglobe bench`: a radar volume resampled to a Cartesian grid
(written by the bench as raw float32 + a job JSON) rendered by VTK's volume mappers with the
bench's cameras (converted to the site's ENU frame) and transfer function.

Usage (the bench runs it): xvfb-run -a /usr/bin/python3 vtk_peer.py JOB.json RESULT.json

Per view and mapper (vtkGPUVolumeRayCastMapper, vtkFixedPointVolumeRayCastMapper,
vtkSmartVolumeMapper): one warm-up render (uploads the grid), then `frames` timed renders
(Render() + WaitForCompletion()), median in ms; the last frame written as PNG (RGB over
black) for the bench to compare with its reference. Needs Debian's python3-vtk9 and numpy.
"""
import json
import os
import resource
import statistics
import sys
import time

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk


def make_image(grid):
    nx, ny, nz = grid["dims"]
    data = np.fromfile(grid["file"], dtype="<f4")
    if data.size != nx * ny * nz:
        raise SystemExit(f"{grid['file']}: {data.size} values, expected {nx}*{ny}*{nz}")
    img = vtk.vtkImageData()
    img.SetDimensions(nx, ny, nz)
    s = grid["spacing_m"]
    img.SetSpacing(s, s, s)
    img.SetOrigin(*grid["origin_enu_m"])
    arr = numpy_to_vtk(data, deep=False, array_type=vtk.VTK_FLOAT)
    arr.SetName("value")
    img.GetPointData().SetScalars(arr)
    return img, data  # keep the numpy buffer alive


def make_property(tf):
    color = vtk.vtkColorTransferFunction()
    for v, r, g, b in tf["colors"]:
        color.AddRGBPoint(v, r, g, b)
    opacity = vtk.vtkPiecewiseFunction()
    for v, a in tf["opacity"]:
        opacity.AddPoint(v, a)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    # Same opacity correction as ours: alpha_s = 1 - (1 - alpha)^(step / unit distance).
    prop.SetScalarOpacityUnitDistance(tf["unit_distance_m"])
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    return prop


def make_ellipsoid(matrix):
    """The Earth as an opaque black ellipsoid: the unit sphere through a row-major 4x4 matrix
    (scale to the WGS84 axes, then ECEF -> the job's frame), 0.25 degree facets (chord sag ~60 m)."""
    sphere = vtk.vtkSphereSource()
    sphere.SetRadius(1.0)
    sphere.SetThetaResolution(1440)
    sphere.SetPhiResolution(720)
    m = vtk.vtkMatrix4x4()
    for r in range(4):
        for c in range(4):
            m.SetElement(r, c, matrix[4 * r + c])
    xf = vtk.vtkTransform()
    xf.SetMatrix(m)
    f = vtk.vtkTransformPolyDataFilter()
    f.SetInputConnection(sphere.GetOutputPort())
    f.SetTransform(xf)
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(f.GetOutputPort())
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    p = actor.GetProperty()
    p.SetColor(0, 0, 0)
    p.SetAmbient(0.0)
    p.SetDiffuse(0.0)
    p.SetSpecular(0.0)
    return actor


def make_mapper(name, sample_distance):
    if name == "gpu":
        m = vtk.vtkGPUVolumeRayCastMapper()
        m.SetAutoAdjustSampleDistances(0)
        m.SetSampleDistance(sample_distance)
    elif name == "fixed_point":
        m = vtk.vtkFixedPointVolumeRayCastMapper()
        m.SetAutoAdjustSampleDistances(0)
        m.SetSampleDistance(sample_distance)
        m.SetInteractiveSampleDistance(sample_distance)
        m.SetImageSampleDistance(1.0)
    else:
        m = vtk.vtkSmartVolumeMapper()
        m.SetRequestedRenderModeToDefault()
        if hasattr(m, "SetSampleDistance"):
            m.SetSampleDistance(sample_distance)
        m.SetInteractiveUpdateRate(0.00001)  # never drop to interactive quality
    return m


def main():
    job_path, result_path = sys.argv[1], sys.argv[2]
    with open(job_path) as f:
        job = json.load(f)
    img, _keep = make_image(job["grid"])
    prop = make_property(job["transfer"])
    frames = int(job.get("frames", 5))
    runs = []
    # One window (one X connection) for all mappers: opening a window per mapper lost the X
    # connection now and then on the third ("bad X server connection", VTK aborts).
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    for mapper_name in ("gpu", "fixed_point", "smart"):
        mapper = make_mapper(mapper_name, job["sample_distance_m"])
        mapper.SetInputData(img)
        volume = vtk.vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)
        ren = vtk.vtkRenderer()
        ren.SetBackground(0, 0, 0)
        ren.AddVolume(volume)
        if "ellipsoid_matrix" in job:  # grid views: the Earth hides what is behind it
            ren.AddActor(make_ellipsoid(job["ellipsoid_matrix"]))
        win.AddRenderer(ren)
        for view in job["views"]:
            win.SetSize(view["width"], view["height"])
            cam = ren.GetActiveCamera()
            cam.SetPosition(*view["position"])
            cam.SetFocalPoint(*view["focal_point"])
            cam.SetViewUp(*view["view_up"])
            cam.SetViewAngle(view["fov_y_deg"])  # vertical, as ours
            ren.ResetCameraClippingRange()
            note = ""
            try:
                t0 = time.perf_counter()
                win.Render()  # warm-up: uploads the grid
                win.WaitForCompletion()
                first_ms = 1e3 * (time.perf_counter() - t0)
                times = []
                n = frames if mapper_name != "fixed_point" else min(frames, 3)
                for _ in range(n):
                    t0 = time.perf_counter()
                    win.Render()
                    win.WaitForCompletion()
                    times.append(1e3 * (time.perf_counter() - t0))
                note = f"first frame {first_ms:.0f} ms"
                if mapper_name == "smart":
                    mode = mapper.GetLastUsedRenderMode()
                    note += {0: ", used the ray-cast (CPU) mapper", 2: ", used the GPU mapper"}.get(
                        mode, f", render mode {mode}")
                grab = vtk.vtkWindowToImageFilter()
                grab.SetInput(win)
                grab.SetInputBufferTypeToRGB()
                grab.ReadFrontBufferOff()
                grab.Update()
                png = f"{job['out_dir']}/{view['name']}-vtk-{mapper_name}.png"
                writer = vtk.vtkPNGWriter()
                writer.SetFileName(png)
                writer.SetInputConnection(grab.GetOutputPort())
                writer.Write()
                runs.append({"view": view["name"], "mapper": mapper_name, "median_ms": statistics.median(times),
                             "frames_ms": times, "image": png, "note": note})
            except Exception as e:  # report, keep going with the next mapper
                runs.append({"view": view["name"], "mapper": mapper_name, "median_ms": 0.0, "image": "",
                             "note": f"failed: {e}"})
            print(f"vtk_peer: {view['name']} {mapper_name}: {runs[-1]['median_ms']:.1f} ms {runs[-1]['note']}",
                  flush=True)
            write_result(result_path, job, runs)  # after every run: a later abort keeps these
        mapper.ReleaseGraphicsResources(win)
        win.RemoveRenderer(ren)
        del ren, volume, mapper
    win.Finalize()
    write_result(result_path, job, runs)


def write_result(result_path, job, runs):
    """Writes the result file atomically (temporary file, then rename)."""
    result = {
        "vtk_version": vtk.vtkVersion.GetVTKVersion(),
        "opengl": "",
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "grid_bytes": int(np.prod(job["grid"]["dims"])) * 4,
        "runs": runs,
    }
    tmp = result_path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(result, f, indent=2)
    os.replace(tmp, result_path)


if __name__ == "__main__":
    main()
