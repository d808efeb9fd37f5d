"""Helpers shared by Canopy's Catalyst pipeline scripts (ParaView 5.9+ format).

Canopy's in-situ driver puts this folder on the Python path before it imports
any script, so a script starts with ``import canopy_catalyst``. A script reads
its settings with ``settings(...)``: defaults given by the script, overridden by
environment variables (``CANOPY_FREQUENCY=5``), overridden by the arguments the
simulation gave this script (``--frequency=5``). Names use underscores in Python
and in variables, dashes or underscores in arguments.
"""
import os

# Filled by the driver at open: script path -> its arguments.
_arguments = {}

COMMON_DEFAULTS = {
    "output_directory": "canopy-output",
    "channel": "grid",
    "frequency": 1,
    "fields": "",
}


def _register_arguments(path, arguments):
    _arguments[os.path.abspath(path)] = list(arguments)


def _script_arguments():
    from paraview import catalyst
    name = catalyst.get_script_filename()
    return _arguments.get(os.path.abspath(name), []) if name else []


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


def _converted(text, default):
    if isinstance(default, bool):
        return str(text).lower() in ("1", "true", "yes", "on")
    if isinstance(default, int):
        return int(text)
    if isinstance(default, float):
        return float(text)
    return str(text)


def settings(**defaults):
    """The script's settings: COMMON_DEFAULTS and `defaults`, then CANOPY_<NAME>
    environment variables, then the script's --name=value arguments. An argument
    naming no known setting is an error (a typo must not go unnoticed)."""
    merged = dict(COMMON_DEFAULTS)
    merged.update(defaults)
    values = Settings(merged)
    for name, default in merged.items():
        text = os.environ.get("CANOPY_" + name.upper())
        if text is not None:
            values[name] = _converted(text, default)
    for argument in _script_arguments():
        if not argument.startswith("--") or "=" not in argument:
            raise ValueError("script argument %r is not of the form --name=value" % argument)
        name, text = argument[2:].split("=", 1)
        name = name.replace("-", "_")
        if name not in merged:
            raise ValueError("script argument %r: no setting named %r (known: %s)"
                             % (argument, name, ", ".join(sorted(merged))))
        values[name] = _converted(text, merged[name])
    return values


def catalyst_options(values, cinema=None):
    """Catalyst options for a script: where extracts go and how often the script runs.
    With `cinema` (a folder name ending in .cdb), the script's extracts go into that
    Cinema database inside the output directory, indexed by data.csv at the end."""
    from paraview import catalyst
    options = catalyst.Options()
    options.ExtractsOutputDirectory = values.output_directory
    options.GlobalTrigger.Frequency = int(values.frequency)
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
    simple.LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False)
    if namespace is not None:
        for name in dir(simple):
            if name.startswith("Canopy"):
                namespace[name] = getattr(simple, name)


def simulation_grid(values):
    """The hypertree grid the simulation passes to Catalyst this step."""
    from paraview.simple import TrivialProducer
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


def data_extractor(writer, source, name, file_name, values):
    """A data extractor ('VTU', 'VTP', 'HTG') writing `file_name` (a parallel
    file: .pvtu/.pvtp/.phtg listing one piece per rank in a folder of the same
    name) every `frequency` steps. Pieces are written inline (base64): VTK 9.2's
    appended mode writes files its own reader rejects."""
    from paraview.simple import CreateExtractor
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
    position = values.list("camera_position", float) if values.get("camera_position") else []
    if position:
        view.CameraPosition = position
        view.CameraFocalPoint = values.list("camera_focal_point", float)
        view.CameraViewUp = values.list("camera_view_up", float) or [0, 1, 0]
        if values.get("parallel_scale", 0.0) > 0.0:
            view.CameraParallelProjection = 1
            view.CameraParallelScale = values.parallel_scale
        return
    local = _local_bounds(_local_data(grid))
    low = _reduce([local[2 * axis] for axis in range(3)], "MIN_OP")
    high = _reduce([local[2 * axis + 1] for axis in range(3)], "MAX_OP")
    bounds = [value for axis in range(3) for value in (low[axis], high[axis])]
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
        data = _local_data(grid)
        array = data.GetCellData().GetArray(field) if data is not None else None
        local = (array.GetRange(-1 if array.GetNumberOfComponents() > 1 else 0)
                 if array is not None and array.GetNumberOfTuples() > 0
                 else (float("inf"), float("-inf")))
        # Each rank has its own part: agree on the range, or each rank would color
        # with its own.
        low = _reduce([local[0]], "MIN_OP")[0]
        high = _reduce([local[1]], "MAX_OP")[0]
    if not low <= high:
        return None
    high = high if high > low else low + 1
    GetColorTransferFunction(field).RescaleTransferFunction(low, high)
    return (low, high)


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
    try:
        import _canopy_driver
    except ImportError:
        return  # not run by Canopy's driver (e.g. pvbatch): nobody to tell
    _canopy_driver.report_measure(name, local_value)


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
    """Element-wise MIN_OP / MAX_OP / SUM_OP of `values` over all ranks."""
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
    try:
        import _canopy_driver
    except ImportError:
        _canopy_driver = None  # not run by Canopy's driver: no agreement to join
    folder = os.path.dirname(writers[0].FileName)
    if _canopy_driver is not None and os.path.isdir(folder):
        # A step whose extracts would not fit is refused before any file is written
        # (the driver's own check comes after catalyst_execute, too late for these).
        # A folder that does not exist: the writers say why they cannot create it.
        data = _local_data(writers[0].Input)
        size = data.GetActualMemorySize() * 1024.0 if data is not None else 0.0
        _canopy_driver.ensure_step_fits(_canopy_driver.DATA_FACTOR * size * len(writers), folder)
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
