"""Helpers shared by Canopy's Catalyst pipeline scripts (ParaView 5.9+ format).

Canopy's in-situ driver puts this folder on the Python path before it imports
any script, so a script starts with ``import canopy_catalyst``. A script reads
its settings with ``settings(...)``: defaults given by the script, overridden by
environment variables the user set (``CANOPY_FREQUENCY=5``), overridden by what
the driver's options say (output_directory, channel, live), overridden by the
arguments the simulation gave this script (``--frequency=5``). Names use
underscores in Python and in variables, dashes or underscores in arguments.

Run by Canopy's driver, this module learns from the driver through its built-in
module ``_canopy`` (the run's settings, the script's arguments, reductions over
ranks; adaptor/insitu/CanopyModule.h) and imports the driver's side of Python
(``_canopy_driver``), never the reverse. Elsewhere (pvbatch, pvpython) neither
exists: settings come from the defaults, the environment and nothing else, and
reductions go over ParaView's controller.

Longer than the project's usual file (about 900 lines) on purpose: it is the one
module a user's script imports, so what scripts share (settings, the plugin,
ImageScript and its view, legend and time label, the extractors and their
disk-space agreement) stays behind one import that works the same from
Catalyst and from pvbatch, where a package of modules would have to be found on
the path too.
"""
import os

COMMON_DEFAULTS = {
    "output_directory": "canopy-output",
    "channel": "grid",
    "frequency": 1,
    "start": 0,
    "fields": "",
    "live": "",
    "trigger": "",
    "trigger_mode": "",
}
"""Settings every script has: where its files go, the channel it reads, when it runs
(steps start, start + frequency, ...), the fields it asks for, and live: 'host:port'
where a Catalyst Live viewer listens ('' : no Live; docs/insitu.md). trigger and
trigger_mode are the driver's: a condition on queries that must also hold for the
script to run, and when it fires (docs/queries.md); the driver reads them from the
script's arguments, the script only accepts them."""


def _door():
    """Canopy's in-situ driver's built-in module ``_canopy``, or None when not run
    by the driver (pvbatch, pvpython: the module exists only in its process)."""
    try:
        import _canopy
    except ImportError:
        return None
    return _canopy


def _driver():
    """The driver's side of Python (_canopy_driver: measures, the disk-space
    agreement), or None when not run by Canopy's driver."""
    if _door() is None:
        return None
    import _canopy_driver
    return _canopy_driver


def _script_arguments():
    door = _door()
    if door is None:
        return []
    from paraview import catalyst
    name = catalyst.get_script_filename()
    return door.script_arguments(name) if name else []


def _run_settings():
    """The settings the driver's options give every script ({} outside the driver):
    output_directory and channel, and live when the options name a Live address."""
    door = _door()
    if door is None:
        return {}
    run = door.run_settings()
    given = {"output_directory": run.output_directory, "channel": run.channel}
    if run.live:
        given["live"] = run.live
    return given


def query_values():
    """The step's query values by their text ({"max(density)": 1.5, ...}): the queries of
    the scripts' triggers and the driver's InSituOptions::queries (docs/queries.md), the
    same on every rank; {} outside the driver or when no query ran this step."""
    door = _door()
    return dict(door.query_values()) if door is not None else {}


def plugin_path():
    """The Canopy ParaView plugin's library: the driver's (CANOPY_PLUGIN if the user
    set it, else the one next to Canopy's library); outside the driver, CANOPY_PLUGIN."""
    door = _door()
    return door.run_settings().plugin if door is not None else os.environ["CANOPY_PLUGIN"]


class Settings(dict):
    """A script's settings; read them as attributes (settings.frequency)."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError("no setting named %r" % name) from None

    def list(self, name, convert=str):
        """A comma-separated setting as a list ('' -> [])."""
        text = str(self[name]).strip()
        return [convert(item.strip()) for item in text.split(",") if item.strip()] if text else []


TRUE_WORDS = ("1", "true", "yes", "on")
FALSE_WORDS = ("0", "false", "no", "off", "")


def _converted(text, default, name=None):
    """`text` as the type of the setting's default; an unreadable value is a ValueError
    naming the setting (a typo such as --contour-opacity=0,5 must not pass as something
    else)."""
    kind = ("true or false (1/0, yes/no, on/off)" if isinstance(default, bool)
            else "an integer" if isinstance(default, int) else "a number")
    try:
        if isinstance(default, bool):
            word = str(text).strip().lower()
            if word not in TRUE_WORDS + FALSE_WORDS:
                raise ValueError(word)
            return word in TRUE_WORDS
        if isinstance(default, int):
            return int(text)
        if isinstance(default, float):
            return float(text)
    except ValueError:
        raise ValueError("setting %s: %s expected (got %r)" % (name, kind, text)) from None
    return str(text)


def settings(**defaults):
    """The script's settings: COMMON_DEFAULTS and `defaults`, then CANOPY_<NAME>
    environment variables, then the driver's options (_run_settings), then the
    script's --name=value arguments. An argument naming no known setting is an
    error (a typo must not go unnoticed)."""
    merged = dict(COMMON_DEFAULTS)
    merged.update(defaults)
    values = Settings(merged)
    for name, default in merged.items():
        text = os.environ.get("CANOPY_" + name.upper())
        if text is not None:
            values[name] = _converted(text, default, "CANOPY_" + name.upper())
    for name, text in _run_settings().items():
        values[name] = _converted(text, merged[name], name)
    for argument in _script_arguments():
        if not argument.startswith("--") or "=" not in argument:
            raise ValueError("script argument %r is not of the form --name=value" % argument)
        name, text = argument[2:].split("=", 1)
        name = name.replace("-", "_")
        if name not in merged:
            raise ValueError("script argument %r: no setting named %r (known: %s)"
                             % (argument, name, ", ".join(sorted(merged))))
        values[name] = _converted(text, merged[name], argument.split("=", 1)[0])
    return values


def catalyst_options(values, cinema=None):
    """Catalyst options for a script: where extracts go and how often the script runs.
    With `cinema` (a folder name ending in .cdb), the script's extracts go into that
    Cinema database inside the output directory, indexed by data.csv at the end."""
    from paraview import catalyst
    options = catalyst.Options()
    options.ExtractsOutputDirectory = values.output_directory
    options.GlobalTrigger.Frequency = int(values.frequency)
    if int(values.start) > 0:
        options.GlobalTrigger.UseStartTimeStep = 1
        options.GlobalTrigger.StartTimeStep = int(values.start)
    if values.get("live"):
        # Canopy's driver takes Live over from ParaView (adaptor/insitu/LiveConnection.h).
        # A script with Live on also runs at its Live trigger's steps: the same as its own.
        options.EnableCatalystLive = 1
        options.CatalystLiveURL = str(values.live)
        options.CatalystLiveTrigger.Frequency = int(values.frequency)
        if int(values.start) > 0:
            options.CatalystLiveTrigger.UseStartTimeStep = 1
            options.CatalystLiveTrigger.StartTimeStep = int(values.start)
    if cinema:
        # A Cinema database is a folder named *.cdb holding the images and data.csv.
        options.ExtractsOutputDirectory = os.path.join(values.output_directory, cinema)
        options.GenerateCinemaSpecification = 1
    return options


def load_canopy_plugin(namespace=None):
    """Loads the Canopy ParaView plugin: its filters become functions of
    paraview.simple (simple.CanopyAdaptiveSurface, ...) and, given a namespace (the
    script's globals()), names in it too. Only the plugin's own functions are added
    to the namespace: LoadPlugin(..., ns=globals()) would make one there for each of
    ParaView's ~480 proxies, about 1 s per script on the first step
    (tests/bench/canopy_bench_image_step --first-step, docs/benchmarks.md)."""
    from paraview import simple
    simple.LoadPlugin(plugin_path(), remote=False)
    if namespace is not None:
        for name in dir(simple):
            if name.startswith("Canopy"):
                namespace[name] = getattr(simple, name)


def simulation_grid(values):
    """The hypertree grid the simulation passes to Catalyst this step."""
    from paraview.simple import TrivialProducer
    # A Catalyst Live viewer that pulls it gets it packed (VTK 9.2 cannot send a
    # hypertree grid; docs/insitu.md, "Catalyst Live").
    return TrivialProducer(registrationName=values.channel)


def request_fields(data_description, values, extra=(), every_field_when_empty=True):
    """For a script's RequestDataDescription: ask Canopy for the grid with only the
    fields in the 'fields' setting plus `extra` (fields the script itself reads).
    When the setting is empty: every field, or, with every_field_when_empty=False,
    only `extra` (a script that draws one field need not wrap the others)."""
    from paraview.vtk import vtkDataObject
    source = data_description.GetInputDescriptionByName(values.channel)
    if source is None:
        return
    source.GenerateMeshOn()
    names = values.list("fields")
    if names or not every_field_when_empty:
        names = names + [name for name in extra if name]
    if not names:
        source.AllFieldsOn()
        return
    for name in names:
        source.AddField(name, vtkDataObject.CELL)


def set_trigger(extractor, values):
    extractor.Trigger.Frequency = int(values.frequency)
    if int(values.start) > 0:
        extractor.Trigger.UseStartTimeStep = 1
        extractor.Trigger.StartTimeStep = int(values.start)


FAIL_SAFE_EXTRACT_WRITERS = {"VTP": "CanopyVTP", "VTU": "CanopyVTU"}


def data_extractor(writer, source, name, file_name, values):
    """A data extractor ('VTU', 'VTP', 'HTG') writing `file_name` (a parallel
    file: .pvtu/.pvtp/.phtg listing one piece per rank in a folder of the same
    name) every `frequency` steps. Pieces are written inline (base64): VTK 9.2's
    appended mode writes files its own reader rejects. 'VTP' and 'VTU' use the
    plugin's CanopyVTP/CanopyVTU: ParaView's own crash the simulation when a write
    fails in the middle of a piece (vtkCanopyXMLPPolyDataWriter.h); needs
    load_canopy_plugin first."""
    from paraview.simple import CreateExtractor
    writer = FAIL_SAFE_EXTRACT_WRITERS.get(writer, writer)
    extractor = CreateExtractor(writer, source, registrationName=name)
    extractor.Writer.FileName = file_name
    if "DataMode" in extractor.Writer.ListProperties():
        extractor.Writer.DataMode = "Binary"
    set_trigger(extractor, values)
    return extractor


def image_size(values):
    width, height = (int(n) for n in str(values.image_size).lower().split("x"))
    return [width, height]


def render_view(values):
    """An off-screen render view of the requested image size."""
    from paraview.simple import CreateView
    view = CreateView("RenderView")
    view.ViewSize = image_size(values)
    view.OrientationAxesVisibility = 0
    view.Background = [1.0, 1.0, 1.0]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    # FXAA smooths each rank's image before compositing: pixels where ranks' parts
    # meet would depend on the number of ranks. Images are the same on any number.
    view.UseFXAA = 0
    return view


def follow_view(surface, view):
    """Gives the adaptive surface the view's camera and viewport size, so that it
    builds only what this view shows, nothing finer than a pixel. Call it in
    catalyst_execute after the camera is set for the step (frame_grid or your own
    code): moving the camera changes what is culled. (The VTK filter can also read
    a vtkRenderer directly; from Python in ParaView 5.11 the filter's class is not
    wrapped, so the helper copies the camera through the proxy's properties.)"""
    surface.CameraPosition = list(view.CameraPosition)
    surface.CameraFocalPoint = list(view.CameraFocalPoint)
    surface.CameraViewUp = list(view.CameraViewUp)
    surface.ParallelProjection = int(view.CameraParallelProjection)
    surface.ParallelScale = float(view.CameraParallelScale)
    surface.ViewAngle = float(view.CameraViewAngle)
    surface.ViewportSize = list(view.ViewSize)


def frame_grid(view, grid, values):
    """Points the view's camera at the whole grid (the same on every rank: the
    bounds are gathered over ranks), unless the settings give a camera."""
    if not camera_given(values):
        frame_bounds(view, grid_bounds(grid), values)
    else:
        frame_bounds(view, None, values)


def camera_given(values):
    return bool(values.get("camera_position"))


def frame_bounds(view, bounds, values):
    """Points the view's camera at `bounds` (xmin, xmax, ... the same on every
    rank), unless the settings give a camera (then `bounds` is not used)."""
    position = values.list("camera_position", float) if camera_given(values) else []
    if position:
        view.CameraPosition = position
        view.CameraFocalPoint = values.list("camera_focal_point", float)
        view.CameraViewUp = values.list("camera_view_up", float) or [0, 1, 0]
        if values.get("parallel_scale", 0.0) > 0.0:
            view.CameraParallelProjection = 1
            view.CameraParallelScale = values.parallel_scale
        return
    lengths = [bounds[2 * axis + 1] - bounds[2 * axis] for axis in range(3)]
    center = [0.5 * (bounds[2 * axis] + bounds[2 * axis + 1]) for axis in range(3)]
    flat = [axis for axis in range(3) if lengths[axis] == 0.0]
    width, height = image_size(values)
    if flat:
        # A 2D grid: look along its flat axis with a parallel projection, from the
        # side that keeps the in-plane axes right-handed on screen (x right, y up
        # for XY, x right and z up for XZ, z right and y up for YZ).
        normal = flat[0]
        up_axis = 1 if normal != 1 else 2
        across = [axis for axis in range(3) if axis not in (normal, up_axis)][0]
        view.CameraParallelProjection = 1
        view.CameraFocalPoint = center
        position = list(center)
        position[normal] += (max(lengths) + 1.0) * (1.0 if normal == 2 else -1.0)
        view.CameraPosition = position
        up = [0.0, 0.0, 0.0]
        up[up_axis] = 1.0
        view.CameraViewUp = up
        view.CameraParallelScale = 0.5 * max(lengths[up_axis], lengths[across] * height / width)
    else:
        view.CameraParallelProjection = 0
        view.CameraFocalPoint = center
        diagonal = sum(length * length for length in lengths) ** 0.5
        view.CameraPosition = [center[0] + 1.2 * diagonal, center[1] + 0.9 * diagonal,
                               center[2] + 1.5 * diagonal]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.CameraViewAngle = 30.0


def color_by(display, view, grid, field, fixed_range=None):
    """Colors the display by a cell field over its global range this step, or over
    `fixed_range` ((low, high)) when given. Returns the range used (None without a
    field or any value)."""
    from paraview.simple import GetColorTransferFunction
    if not field:
        return None
    # Not ColorBy(): it rescales to this rank's data, and warns on a rank without any.
    display.ColorArrayName = ["CELLS", field]
    lut = GetColorTransferFunction(field)
    # The range is set below, every step; left to ParaView ("Grow and update on
    # 'Apply'"), each render would also gather the shown data's information
    # (every array's range over every cell) to see whether it should grow.
    lut.AutomaticRescaleRangeMode = "Never"
    display.LookupTable = lut
    if fixed_range is not None:
        low, high = fixed_range
    else:
        low, high = field_range(grid, field)
    if not low <= high:
        return None
    low, high = zero_to_rounding(low, high)
    high = high if high > low else low + 1
    GetColorTransferFunction(field).RescaleTransferFunction(low, high)
    return (low, high)


def has_cell_field(grid, field):
    """Whether some rank's grid has the cell field `field`. Collective."""
    data = _local_data(grid)
    return _any_rank(data is not None and data.GetCellData().GetArray(field) is not None)


def field_range(grid, field):
    """The range of a cell field of the grid (its magnitude for vectors) over
    every rank, this step: (inf, -inf) where no rank has a value. Collective."""
    data = _local_data(grid)
    array = data.GetCellData().GetArray(field) if data is not None else None
    local = (array.GetRange(-1 if array.GetNumberOfComponents() > 1 else 0)
             if array is not None and array.GetNumberOfTuples() > 0
             else (float("inf"), float("-inf")))
    # Each rank has its own part: agree on the range, or each rank would use its own.
    return _reduce([local[0]], "MIN_OP")[0], _reduce([local[1]], "MAX_OP")[0]


EDGE_COLOR = [0.15, 0.15, 0.15]


def edge_overlay(canopy_filter, view, values):
    """The mesh lines drawn over a flat Canopy filter output (show_edges; a 2D
    grid's surface, slices): the edges of the same filter at a pixel threshold of
    twice edge_spacing, as a wireframe, and its display. Level of detail at
    threshold T draws nodes between T/2 and T pixels wide, so cells at least
    edge_spacing pixels wide show their own edges and a region refined finer
    the edges of its ancestors, edge_spacing to twice that apart: a denser mesh
    than the coarse cells around it, never lines one or two pixels apart that
    paint it dark (docs/insitu.md, "Edges")."""
    from paraview import simple
    make = getattr(simple, canopy_filter.GetXMLName())
    # Only one small field: the lines are drawn in a single colour.
    fields = [values.color_by] if values.color_by else []
    overlay = make(Input=canopy_filter.Input, PixelThreshold=2 * values.edge_spacing,
                   Fields=fields or ["OriginalCellId"])
    copy_pieces(canopy_filter, overlay)
    shown = simple.Show(overlay, view)
    shown.SetRepresentationType("Wireframe")
    shown.ColorArrayName = [None, ""]
    shown.AmbientColor = shown.DiffuseColor = EDGE_COLOR
    shown.Ambient, shown.Diffuse, shown.Specular = 1.0, 0.0, 0.0
    return overlay, shown


LIFT = 1e-3
"""How far mesh lines are drawn toward the camera, times the drawn bounds' diagonal."""


def lift_toward_camera(display, view, bounds):
    """Moves a display of lines on flat pieces toward the camera by LIFT times the
    bounds' diagonal: seen obliquely, lines and faces in one plane fight over
    depth and the lines break up. (Offsetting the faces instead, ParaView's
    polygon offset, grows with their slope and reorders faces of different ranks
    when the images are composited by depth.) In perspective the lines move at most
    about 0.2 pixel across the image; face-on nothing changes."""
    position, focal = list(view.CameraPosition), list(view.CameraFocalPoint)
    toward = [position[axis] - focal[axis] for axis in range(3)]
    length = sum(t * t for t in toward) ** 0.5
    diagonal = sum((bounds[2 * a + 1] - bounds[2 * a]) ** 2 for a in range(3)) ** 0.5
    if length > 0:
        display.Position = [LIFT * diagonal * t / length for t in toward]


def copy_pieces(canopy_filter, overlay):
    """What decides which pieces a Canopy filter draws, copied to its edge
    overlay: a slice's planes, a surface's back-face setting."""
    for name in ("XPlanes", "YPlanes", "ZPlanes", "SkipBackFaces"):
        if canopy_filter.GetProperty(name) is not None:
            value = canopy_filter.GetPropertyValue(name)
            if overlay.GetPropertyValue(name) != value:
                overlay.SetPropertyWithName(name, value)


def draw_filtered_colors(canopy_filter, display, field):
    """Draws a Canopy view-dependent filter's output with the colours the filter
    computes ("Colors") instead of mapping `field` in the renderer: a node drawn
    for level of detail then shows the average colour of the leaves it stands
    for, and a face-on quad covering one pixel that pixel's average (the image is
    then closer to every leaf's exact average than drawing every leaf;
    docs/filters.md, "Colours"). Call after color_by: the filter maps through the
    display's lookup table, ranged; the legend still shows that table."""
    canopy_filter.ColorMap = display.LookupTable
    canopy_filter.ColorField = field
    display.ColorArrayName = ["CELLS", "Colors"]
    display.MapScalars = 0
    force_opaque(display)


def force_opaque(display):
    """Tells the renderer that `display` is opaque. ParaView 5.11 treats any
    display drawn with direct colours (MapScalars = 0) as possibly translucent
    and, on several ranks, then redistributes its geometry for ordered
    compositing, which drops flat pieces lying on the partition planes (a
    slice's quads vanish from the image). Canopy's colours are opaque RGB."""
    representation = display.GetClientSideObject()
    active = getattr(representation, "GetActiveRepresentation", None)
    if active is not None and active() is not None:
        active().GetActor().SetForceOpaque(True)


ROUNDING = 1e-9
"""A range end this small relative to the range's magnitude is zero to rounding."""


def zero_to_rounding(low, high):
    """(low, high) with an end that is zero to rounding (e.g. 1.2e-21 where the
    field is 0 up to a solver's rounding, against a maximum of 1) set to 0, so
    that the legend says 0."""
    magnitude = max(abs(low), abs(high))
    return tuple(0.0 if abs(end) <= ROUNDING * magnitude else end for end in (low, high))


def label_format(low, high):
    """A printf format for the legend's range labels fit for [low, high]: enough
    significant digits to tell the ends apart (3 at least), no trailing zeros
    (0 prints as 0, 0.99 as 0.99, 1.2341 and 1.2343 as 1.2341 and 1.2343)."""
    import math
    magnitude = max(abs(low), abs(high))
    width = high - low
    digits = 3
    if magnitude > 0 and width > 0:
        digits += max(0, int(math.ceil(math.log10(magnitude / width))))
    return "%%.%dg" % min(digits, 15)


def color_legend(view, field):
    """A colour legend for `field` (title: the field's name; labels: its range as
    color_by sets it), dark on the view's white background. None without a field."""
    from paraview.simple import GetColorTransferFunction, GetScalarBar
    if not field:
        return None
    bar = GetScalarBar(GetColorTransferFunction(field), view)
    bar.Title = field
    bar.ComponentTitle = ""
    bar.TitleColor = [0.1, 0.1, 0.1]
    bar.LabelColor = [0.1, 0.1, 0.1]
    bar.WindowLocation = "Lower Right Corner"
    bar.Visibility = 1
    return bar


# ---- what the image scripts (surface_image.py, slice_image.py) share ----

IMAGE_DEFAULTS = dict(
    image_size="800x600", color_by="", pixel_threshold=1.0, camera_position="",
    camera_focal_point="", camera_view_up="", parallel_scale=0.0, show_edges=False, legend=True,
    time_label=True, color_range="", png_compression=3, skip_back_faces=False,
    select_field="", select_range="", cut_away="", average_colors=True, edge_spacing=8.0)
"""Settings every image script has (see surface_image.py's docstring); select_field,
select_range and cut_away describe a selected region (selected_region)."""

SURFACE_AMBIENT = 0.45
"""Lighting of shaded surfaces: one light from the camera (a headlight, no light
kit), a face's colour is the colour map's times SURFACE_AMBIENT + (1 - SURFACE_AMBIENT)
cos(angle between its normal and the view): no face darker than 45% of its colour,
so values stay apart on every face; faces towards the camera at full colour.
Flat pieces (slices) are unlit: exactly the colour map."""


def fixed_color_range(values):
    """The color_range setting: None (each step's range, or 'first': the first
    step's, kept), or (low, high)."""
    if values.color_range in ("", "first"):
        return None
    fixed = values.list("color_range", float)
    if len(fixed) != 2 or not fixed[0] < fixed[1]:
        raise ValueError("color_range: 'low,high' with low < high, 'first' or '' (got %r)"
                         % values.color_range)
    return tuple(fixed)


def light_from_camera(view):
    """One headlight instead of ParaView's light kit (see SURFACE_AMBIENT)."""
    from paraview.simple import AddLight
    view.UseLight = 0
    light = AddLight(view=view)
    light.Coords = "Headlight"
    light.Intensity = 1.0
    return light


def shade(display, flat):
    """Colours that read: flat pieces (slices) unlit, surfaces lit by the
    headlight with an ambient term (SURFACE_AMBIENT); no specular highlight."""
    display.Specular = 0.0
    display.Interpolation = "Flat"
    display.Ambient = 1.0 if flat else SURFACE_AMBIENT
    display.Diffuse = 0.0 if flat else 1.0 - SURFACE_AMBIENT


CUT_AWAY_HELP = "'' (none), 'octant' (the octant towards the camera) or 'xmin,xmax,ymin,ymax,zmin,zmax'"


def selected_region(source, values):
    """`source` with the selected region's mask (no cell or field copied): the
    cells whose select_field lies in select_range ('low,high', inclusive), without
    the cut_away box (see CUT_AWAY_HELP); `source` itself when neither is set.
    Returns (region, cut) where cut is the cut-away filter (None without one);
    call cut_away_box(cut, ...) each step when cut_away is 'octant'."""
    from paraview import simple
    region = source
    if values.select_field or values.select_range:
        bounds = values.list("select_range", float)
        if not values.select_field or len(bounds) != 2 or not bounds[0] <= bounds[1]:
            raise ValueError("select_field=<field> and select_range=low,high (low <= high) go "
                             "together (got %r and %r)" % (values.select_field, values.select_range))
        region = simple.CanopyExtractSelection(
            Input=region, SelectionMode="Value Range", ValueArrayName=values.select_field,
            ValueComponent=0, ValueRange=bounds, PreserveTopology=1)
    cut = None
    if values.cut_away:
        box = [] if values.cut_away == "octant" else values.list("cut_away", float)
        if values.cut_away != "octant" and len(box) != 6:
            raise ValueError("cut_away: %s (got %r)" % (CUT_AWAY_HELP, values.cut_away))
        cut = simple.CanopyExtractSelection(
            Input=region, SelectionMode="Box", Box=box or [0.0] * 6, Invert=1, PreserveTopology=1)
        region = cut
    return region, cut


def octant_towards(bounds, camera_position):
    """The octant of `bounds` nearest the camera, unbounded outward (a box that
    cuts it away whatever lies beyond the domain)."""
    box = []
    for axis in range(3):
        low, high = bounds[2 * axis], bounds[2 * axis + 1]
        centre = 0.5 * (low + high)
        box += [centre, 1e300] if camera_position[axis] >= centre else [-1e300, centre]
    return box


def grid_bounds(grid):
    """The whole grid's bounds, agreed over ranks (collective)."""
    local = _local_bounds(_local_data(grid))
    low = _reduce([local[2 * axis] for axis in range(3)], "MIN_OP")
    high = _reduce([local[2 * axis + 1] for axis in range(3)], "MAX_OP")
    return [value for axis in range(3) for value in (low[axis], high[axis])]


class ImageScript:
    """The frame of an image script: settings (IMAGE_DEFAULTS), Catalyst options,
    the plugin, the simulation's grid, an off-screen view lit for colour maps, a PNG
    extractor, the colour legend and the time label; show() adds what is drawn, and
    execute() does each step's work (camera, view-following filters, colours,
    cut-away box, time). Collective calls happen in execute(), on every rank."""

    def __init__(self, values, cinema=None):
        self.settings = values
        self.fixed_range = fixed_color_range(values)
        self.options = catalyst_options(values, cinema=cinema)
        load_canopy_plugin()
        self.grid = simulation_grid(values)
        self.view = render_view(values)
        light_from_camera(self.view)
        self.region, self.cut = selected_region(self.grid, values)
        self.followers = []
        self.displays = []  # (display, the Canopy filter it shows or None)
        self.edges = []  # (Canopy filter, its edge overlay)
        self.shaded = []
        png_extractor(self.view, values)
        self.legend = color_legend(self.view, values.color_by) if values.legend else None
        self.label = time_label(self.view) if values.time_label else None

    def show(self, proxy, flat=False, follows_view=True, colored=True, edges=True):
        """Shows `proxy` in the view: flat (unlit, slices) or shaded; a filter that
        follows the view (CanopyAdaptiveSurface, CanopyAdaptiveSlice, CanopyContour
        with level of detail) gets the view's camera each step; colored by color_by
        unless colored=False; with show_edges its cells' edges unless edges=False
        (an isosurface's triangles are not the grid's cells: their edges would only
        darken it)."""
        from paraview.simple import Show
        display = Show(proxy, self.view)
        shade(display, flat)
        self.shaded.append((display, flat))
        edges = edges and self.settings.show_edges
        if edges and follows_view and self.settings.edge_spacing > 0:
            overlay, overlay_display = edge_overlay(proxy, self.view, self.settings)
            self.edges.append((proxy, display, flat, overlay, overlay_display))
        elif edges:
            display.SetRepresentationType("Surface With Edges")
            display.EdgeColor = EDGE_COLOR
        if follows_view:
            self.followers.append(proxy)
        if colored:
            self.displays.append((display, proxy if follows_view else None))
        return display

    def fields(self):
        """The fields this script reads itself: color_by and select_field."""
        return [self.settings.color_by, self.settings.select_field]

    def request_fields(self, data_description):
        request_fields(data_description, self.settings, extra=self.fields(),
                       every_field_when_empty=False)

    def region_bounds(self):
        """The bounds of what is drawn, agreed over ranks: the selected cells'
        (before any cut) with a value range, else the whole grid's."""
        values = self.region
        while values is not self.grid and values.SelectionMode != "Value Range":
            values = values.Input
        if values is self.grid:
            return grid_bounds(self.grid)
        _at_step_time(values)
        values.UpdatePropertyInformation()
        local = list(values.GetProperty("LastSelectedBounds").GetData())
        low = _reduce([local[2 * axis] for axis in range(3)], "MIN_OP")
        high = _reduce([local[2 * axis + 1] for axis in range(3)], "MAX_OP")
        if not all(low[axis] <= high[axis] for axis in range(3)):
            return grid_bounds(self.grid)  # nothing selected: show where it would be
        return [value for axis in range(3) for value in (low[axis], high[axis])]

    def execute(self, info):
        """A step's work before the image: frame what is drawn (unless the
        settings give a camera), cut the octant towards the camera, follow the
        view, colour, time label. Collective: call it on every rank."""
        bounds = self.region_bounds()
        frame_bounds(self.view, bounds, self.settings)
        # A 2D (or 1D) grid's surface is flat: unlit, exactly the colour map.
        planar = any(bounds[2 * axis + 1] <= bounds[2 * axis] for axis in range(3))
        for display, flat in self.shaded:
            shade(display, flat or planar)
        if self.cut is not None and self.settings.cut_away == "octant":
            self.cut.Box = octant_towards(bounds, list(self.view.CameraPosition))
        for proxy, display, flat, overlay, overlay_display in self.edges:
            # The overlay's coarser pieces lie on the drawn ones only when they
            # are flat (a 2D grid's surface, slices); a 3D surface at a coarser
            # threshold is elsewhere: there, the drawn cells' own edges.
            on_top = flat or planar
            overlay_display.Visibility = int(on_top)
            display.SetRepresentationType("Surface" if on_top else "Surface With Edges")
            display.EdgeColor = EDGE_COLOR
            if on_top:
                copy_pieces(proxy, overlay)
                follow_view(overlay, self.view)
                lift_toward_camera(overlay_display, self.view, bounds)
        for proxy in self.followers:
            follow_view(proxy, self.view)
        used = self.fixed_range
        for display, canopy_filter in self.displays:
            # The range is agreed over ranks once; the other displays take it.
            used = color_by(display, self.view, self.grid, self.settings.color_by, used)
            averaged = self.settings.average_colors and canopy_filter is not None
            if averaged and used is not None:
                draw_filtered_colors(canopy_filter, display, self.settings.color_by)
        if self.settings.color_range == "first" and self.fixed_range is None and used is not None:
            self.fixed_range = used
        if self.legend is not None and used is not None:
            self.legend.RangeLabelFormat = label_format(*used)
        if self.label is not None:
            self.label.Text = time_text(info.time)


def png_extractor(view, values):
    """The PNG extractor of an image script: <file_prefix>_<step>.png of the
    image size, at png_compression, on the script's trigger."""
    from paraview.simple import CreateExtractor
    image = CreateExtractor("PNG", view, registrationName=values.file_prefix + "_image")
    image.Writer.FileName = values.file_prefix + "_{timestep:06d}.png"
    image.Writer.ImageResolution = image_size(values)
    image.Writer.Format.CompressionLevel = str(values.png_compression)
    set_trigger(image, values)
    return image


SURFACE_DEFAULTS = dict(IMAGE_DEFAULTS, surface_extract=False, cinema=False)
"""The settings of SurfaceImage's scripts but file_prefix (surface_image.py's docstring)."""


class SurfaceImage(ImageScript):
    """surface_image.py's pipeline, also that of surface_image_second_view.py (the
    driver runs a script file once, so a second camera needs a second file): the
    adaptive surface of the selected region in ImageScript's frame, and with
    surface_extract that surface as .pvtp files; execute() reports the quads drawn
    as "<file_prefix> quads"."""

    def __init__(self, values):
        from paraview import simple
        ImageScript.__init__(self, values, cinema="surface.cdb" if values.cinema else None)
        self.surface = simple.CanopyAdaptiveSurface(
            Input=self.region, PixelThreshold=values.pixel_threshold, Fields=values.list("fields"),
            SkipBackFaces=int(values.skip_back_faces))
        self.show(self.surface)
        if values.surface_extract:
            data_extractor("VTP", self.surface, "surface_data",
                           values.file_prefix + "_{timestep:06d}.pvtp", values)

    def execute(self, info):
        ImageScript.execute(self, info)
        report(self.settings.file_prefix + " quads", output_cells(self.surface))


def time_label(view):
    """A text in the view's upper left corner; set its Text each step (time_text)."""
    from paraview.simple import Show, Text
    label = Text(registrationName="canopy_time_label", Text="")
    shown = Show(label, view)
    shown.WindowLocation = "Upper Left Corner"
    shown.Color = [0.1, 0.1, 0.1]
    shown.FontSize = 18
    return label


def time_text(time):
    return "t = %.6g" % time


def report(name, local_value):
    """Reports a number this step measured (e.g. the quads the surface drew): after
    the script's extracts are written, `local_value()` is called on every rank and
    the sum over ranks goes into the step's canopy::StepReport::measures under `name`
    (and the driver's step summary). Call it in catalyst_execute, on every rank, with
    the same names; each call covers one step."""
    driver = _driver()
    if driver is None:
        return  # not run by Canopy's driver (e.g. pvbatch): nobody to tell
    driver.report_measure(name, local_value)


def output_cells(proxy):
    """A function giving the number of cells the proxy's filter output on this rank
    last time it ran (the data rendered or written), for report(). Catalyst runs in a
    builtin session: the client-side object is the rank's own VTK algorithm."""
    algorithm = proxy.GetClientSideObject()
    return lambda: algorithm.GetOutputDataObject(0).GetNumberOfCells()


def _step_time():
    """The simulation time of the step being run (None outside a Catalyst run)."""
    from paraview.modules.vtkPVPythonCatalyst import vtkCPPythonScriptV2Helper
    helper = vtkCPPythonScriptV2Helper.GetActiveInstance()
    description = helper.GetDataDescription() if helper is not None else None
    return description.GetTime() if description is not None else None


def _local_data(source):
    """This rank's data object of `source`, updated at this step's time, or None.
    Catalyst runs in a builtin session: the client-side object is this rank's own
    algorithm, so bounds and ranges are read from the data itself. ParaView's data
    information (GetDataInformation) would gather much more (every array's range,
    leaf counts, memory size): 0.06 s per 1e5 leaves here, per call
    (tests/bench/canopy_bench_image_step, docs/benchmarks.md)."""
    _at_step_time(source)
    algorithm = source.GetClientSideObject()
    return algorithm.GetOutputDataObject(0) if algorithm is not None else None


def _local_bounds(data):
    """(xmin, xmax, ymin, ymax, zmin, zmax) of this rank's data; empty (min > max)
    when it has none, so that it does not count in the reduction over ranks."""
    if data is None or data.GetNumberOfCells() == 0:
        return [float("inf"), float("-inf")] * 3
    return list(data.GetBounds())


def _at_step_time(source):
    """The source, updated at this step's time. Data information alone updates
    without a time, so the request would keep the previous step's time and
    ParaView's producer would warn that it cannot produce it."""
    time = _step_time()
    if time is not None:
        source.UpdatePipeline(time)
    return source


def collective(function):
    """Decorates catalyst_execute so that an exception on some ranks is raised on
    all of them before anything collective (rendering, parallel writers) starts:
    otherwise the ranks that did not fail would wait forever for the others.
    The decorated function itself must not make collective calls (frame_grid,
    color_by, GetDataInformation, ...): a rank that raised would not be there."""
    import functools

    @functools.wraps(function)
    def guarded(*args, **kwargs):
        error = None
        try:
            function(*args, **kwargs)
        except BaseException as exception:  # noqa: B902 - sys.exit() too; re-raised below
            error = exception
        if not _any_rank(error is not None):
            return
        if error is not None:
            raise error
        raise RuntimeError("catalyst_execute failed on another rank; this rank skips the step")

    return guarded


def _any_rank(flag):
    return _reduce([1.0 if flag else 0.0], "MAX_OP")[0] != 0.0


def _reduce(values, operation):
    """Element-wise MIN_OP / MAX_OP / SUM_OP of `values` over all ranks (collective).
    In Catalyst a source's data and data information are this rank's only, so what
    a script must agree on (bounds, colour ranges, whether a rank failed) is reduced
    here. Run by Canopy's driver: _canopy.reduce, on a communicator of Canopy's that
    only these reductions use; elsewhere (pvbatch, maybe under mpirun) ParaView's
    controller, the only one there; alone, the values themselves."""
    door = _door()
    if door is not None:
        return door.reduce(values, {"MIN_OP": "min", "MAX_OP": "max", "SUM_OP": "sum"}[operation])
    from paraview.modules.vtkRemotingCore import vtkProcessModule
    from paraview.vtk.vtkParallelCore import vtkCommunicator
    from paraview.vtk import vtkDoubleArray
    controller = vtkProcessModule.GetProcessModule().GetGlobalController()
    if controller is None or controller.GetNumberOfProcesses() < 2:
        return list(values)
    local = vtkDoubleArray()
    for value in values:
        local.InsertNextValue(value)
    total = vtkDoubleArray()
    controller.AllReduce(local, total, getattr(vtkCommunicator, operation))
    return [total.GetValue(i) for i in range(total.GetNumberOfTuples())]


GRID_FORMATS = ("vtkhdf", "htg", "both")


def grid_writers(grid, values):
    """Writers of the whole grid for a script's catalyst_execute (see write_grid),
    by the 'format' setting: 'vtkhdf' (every step in <file_prefix>.vtkhdf, read by
    current VTK/ParaView), 'htg' (the series <file_prefix>.pvd that ParaView 5.11
    opens: per step a .vtm of .htg pieces) or 'both'. They write the 'fields'
    setting's fields (all when empty). Needs load_canopy_plugin first."""
    from paraview import servermanager
    form = str(values.format).lower()
    if form not in GRID_FORMATS:
        raise ValueError("format %r: expected one of %s" % (values.format, ", ".join(GRID_FORMATS)))
    base = os.path.join(values.output_directory, values.file_prefix)
    fields = values.list("fields")
    writers = []
    if form in ("vtkhdf", "both"):
        writers.append(servermanager.writers.CanopyHyperTreeGridHDFWriter(
            Input=grid, FileName=base + ".vtkhdf", CellArrays=fields))
    if form in ("htg", "both"):
        writers.append(servermanager.writers.CanopyHyperTreeGridSeriesWriter(
            Input=grid, FileName=base + ".pvd", CellArrays=fields))
    return writers


def write_grid(writers, info):
    """Writes this step with every writer of grid_writers. Collective: each writer
    agrees over ranks, so when any rank fails, every rank raises the same error,
    naming each rank's problem and the step (the driver then reports the step as
    failed on all ranks)."""
    if not writers:
        return
    driver = _driver()  # None: not run by Canopy's driver, no agreement to join
    folder = os.path.dirname(writers[0].FileName)
    if driver is not None and os.path.isdir(folder):
        # A step whose extracts would not fit is refused before any file is written
        # (the driver's own check comes after catalyst_execute, too late for these).
        # A folder that does not exist: the writers say why they cannot create it.
        data = _local_data(writers[0].Input)
        size = data.GetActualMemorySize() * 1024.0 if data is not None else 0.0
        driver.ensure_step_fits(size * len(writers), folder)
    problems = []
    for writer in writers:
        writer.TimeStep = info.timestep
        writer.TimeValue = info.time
        writer.UpdatePipeline(info.time)
        writer.UpdatePropertyInformation()
        problem = writer.GetProperty("LastError").GetData()
        if problem:
            problems.append(problem)
    if problems:
        raise RuntimeError("; ".join(problems))
