"""The ParaView scene of a report's time series, built by ParaView's own Python (pvpython).

Not imported by flexbearing: `flexbearing report --series` (flexbearing.analysis.paraview_state) runs

    [xvfb-run -a] pvpython paraview_scene.py SETTINGS.json

where SETTINGS.json says {"folder": the series folder, "state": the .pvsm to write, "png": a
screenshot or null, "movie": a movie file or null, "time": s or null, "size": [w, h]}. It opens
series_cage.xdmf (the cage, placed and deformed), series_points.xdmf (the balls and the cage
centre) and series_rings.xdmf (the rings) with ParaView's XDMF 3 reader and builds:

  - the cage warped by displacement_scaled (the elastic displacement times series.json's
    displacement_scale: Scale Factor 1) and coloured by its von Mises stress in MPa (a Calculator
    von_mises_MPa = 1e-6 von_mises: the files stay SI), colour bar "von Mises stress (MPa)" over
    [0, the largest maximum the run recorded in the window] (series.json);
  - the balls as spheres of their diameter (Glyph, scale by "diameter");
  - the rings, the outer one cut away on the camera's side (Clip) so the cage and balls show;
  - a camera outside the bearing at the azimuth of the window's stress maximum (the loaded
    pocket), 30° off the radial direction towards the bearing axis, at the time of the
    maximum (or "time");

then saves the state (.pvsm: File > Load State in ParaView, "Search files under specified
directory" to open it from another folder), and on request a screenshot and a movie of the whole
window (SaveAnimation: .avi through FFMPEG, .ogv through Ogg Theora, as ParaView was built with).
It prints one JSON line of facts (time shown, colour range in MPa, files), which the tests read.
Only paraview and the standard library are imported: pvpython runs its own Python.
"""
import json
import math
import os
import sys
from paraview import servermanager, simple as pv

# run as a script, this folder is sys.path[0]: its modules must not shadow ParaView's (paraview_state)
sys.path[:] = [p for p in sys.path if os.path.abspath(p or ".") != os.path.dirname(os.path.abspath(__file__))]


def build(settings: dict) -> dict:
    folder = settings["folder"]
    meta = json.load(open(os.path.join(folder, "series.json")))
    frames = meta["cage"]["frames"] if "cage" in meta else []
    times = meta["times"]
    pv._DisableFirstRenderCameraReset()       # keep the camera set below at the first render
    view = pv.GetActiveViewOrCreate("RenderView")
    w, h = settings.get("size") or [1600, 1000]
    view.ViewSize = [w, h]
    view.OrientationAxesVisibility = 1
    view.Background = [1.0, 1.0, 1.0]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    facts = {"folder": folder}
    k = None
    peak = None
    if frames:
        recorded = [f["recorded_von_mises_max"] if f.get("recorded_von_mises_max") is not None
                    else f["field_max_von_mises"] for f in frames]
        k = max(range(len(recorded)), key=recorded.__getitem__)
        vmax_mpa = recorded[k] * 1e-6
        cage = pv.Xdmf3ReaderS(registrationName="cage", FileName=[os.path.join(folder, meta["cage"]["file"])])
        warp = pv.WarpByVector(registrationName="cage warped", Input=cage,
                               Vectors=["POINTS", "displacement_scaled"], ScaleFactor=1.0)
        mpa = pv.Calculator(registrationName="cage (MPa)", Input=warp, ResultArrayName="von_mises_MPa",
                            Function="von_mises*1e-6")
        disp = pv.Show(mpa, view)
        pv.ColorBy(disp, ("POINTS", "von_mises_MPa"))
        lut = pv.GetColorTransferFunction("von_mises_MPa")
        lut.ApplyPreset("Turbo", True)
        lut.AutomaticRescaleRangeMode = "Never"
        lut.RescaleTransferFunction(0.0, vmax_mpa)
        pv.GetOpacityTransferFunction("von_mises_MPa").RescaleTransferFunction(0.0, vmax_mpa)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = "von Mises stress (MPa)"
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
        bar.RangeLabelFormat = "%.0f"
        disp.SetScalarBarVisibility(view, True)
        xs = list(lut.RGBPoints[0::4])
        facts["colour_range_mpa"] = [xs[0], xs[-1]]
        facts["recorded_max_mpa"] = vmax_mpa
        t_peak = times[k]
        cage.UpdatePipeline(t_peak)
        data = servermanager.Fetch(cage)
        arr = data.GetPointData().GetArray("von_mises")
        n_max = max(range(arr.GetNumberOfTuples()), key=arr.GetValue)
        peak = data.GetPoint(n_max)
    points_file = os.path.join(folder, "series_points.xdmf")
    if os.path.isfile(points_file):
        pts = pv.Xdmf3ReaderS(registrationName="balls and cage centre", FileName=[points_file])
        balls = pv.Glyph(registrationName="balls", Input=pts, GlyphType="Sphere")
        balls.ScaleArray = ["POINTS", "diameter"]
        balls.ScaleFactor = 1.0
        balls.GlyphMode = "All Points"
        balls.GlyphType.Radius = 0.5            # unit diameter, scaled by the ball's
        balls.GlyphType.ThetaResolution = 32
        balls.GlyphType.PhiResolution = 16
        bd = pv.Show(balls, view)
        pv.ColorBy(bd, None)
        bd.DiffuseColor = [0.80, 0.80, 0.84]
        bd.Specular = 0.4
    # the camera's azimuth: the stress maximum's (the loaded pocket), else the radial load's (-z)
    az = math.atan2(peak[2], peak[1]) if peak else -0.5 * math.pi
    ry, rz = math.cos(az), math.sin(az)
    rings_file = os.path.join(folder, "series_rings.xdmf")
    if os.path.isfile(rings_file):
        rings = pv.Xdmf3ReaderS(registrationName="rings", FileName=[rings_file])
        outer = pv.Threshold(registrationName="outer ring", Input=rings, Scalars=["POINTS", "ring"])
        inner = pv.Threshold(registrationName="inner ring", Input=rings, Scalars=["POINTS", "ring"])
        _between(outer, 0.5, 1.5)
        _between(inner, 1.5, 2.5)
        cut = pv.Clip(registrationName="outer ring, cut away towards the camera", Input=outer)
        cut.ClipType = "Plane"
        cut.ClipType.Origin = [0.0, 0.0, 0.0]
        cut.ClipType.Normal = [0.0, ry, rz]
        cut.Invert = 1                           # keep the far half
        for src, colour, opacity in ((cut, [0.62, 0.64, 0.68], 1.0), (inner, [0.55, 0.57, 0.62], 1.0)):
            rd = pv.Show(src, view)
            pv.ColorBy(rd, None)
            rd.DiffuseColor = colour
            rd.Opacity = opacity
            rd.Specular = 0.3
    t_show = settings.get("time")
    if t_show is None:
        t_show = times[k] if k is not None else times[0]
    scene = pv.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = t_show
    view.ViewTime = t_show
    # outside the bearing at the loaded pocket's azimuth, 30° towards the axis, looking at the pocket
    # (focal point between the pocket and the axis: the loaded pockets beside it stay in the picture)
    target = (0.0, 0.05 * ry, 0.05 * rz)
    cam = view.GetActiveCamera()
    dist = 0.24
    el = math.radians(30.0)
    cam.SetFocalPoint(*target)
    cam.SetPosition(target[0] + dist * math.sin(el), target[1] + dist * math.cos(el) * ry,
                    target[2] + dist * math.cos(el) * rz)
    cam.SetViewUp(1.0, 0.0, 0.0)
    cam.SetViewAngle(30.0)
    pv.Render(view)
    facts.update({"time": t_show, "camera_azimuth_deg": math.degrees(az)})
    state = settings.get("state")
    if state:
        pv.SaveState(state)
        facts["state"] = state
    if settings.get("png"):
        pv.SaveScreenshot(settings["png"], view, ImageResolution=[w, h])
        facts["png"] = settings["png"]
    if settings.get("movie"):
        pv.SaveAnimation(settings["movie"], view, ImageResolution=[w - w % 16, h - h % 16],
                         FrameRate=settings.get("frame_rate", 10))
        facts["movie"] = settings["movie"]
    return facts


def _between(threshold, lo: float, hi: float) -> None:
    """Threshold range across ParaView versions (5.10+: LowerThreshold/UpperThreshold)."""
    try:
        threshold.LowerThreshold, threshold.UpperThreshold = lo, hi
    except AttributeError:
        threshold.ThresholdRange = [lo, hi]


if __name__ == "__main__":
    facts = build(json.load(open(sys.argv[1])))
    print("FLEXBEARING_PARAVIEW " + json.dumps(facts))
    sys.stdout.flush()
    # leave without tearing down the render window: under xvfb-run, ParaView 5.11's exit-time
    # GLX cleanup fails (X error GLXBadContext) and would turn success into status 1
    os._exit(0)
