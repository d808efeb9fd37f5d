"""The in-situ driver's side of Python (not for pipeline scripts).

Canopy's driver and Python talk through one door, the driver's built-in module
``_canopy`` (adaptor/insitu/CanopyModule.h lists every call, both ways). Python
calls its functions: the run's settings, each script's arguments, reductions
over ranks, the agreement before extracts. The driver calls the methods of one
object, ``DriverSide``, which importing this module registers with
``_canopy.connect``; the driver imports it when it opens. Outside the driver's
process ``_canopy`` does not exist and importing this module fails.

ParaView 5.11 calls a V2 script through functions of
``paraview.catalyst.v2_internals`` (import, catalyst_initialize,
RequestDataDescription, catalyst_execute, catalyst_finalize). Importing this
module wraps them (``guard_catalyst_calls``) so that

* ``sys.exit()`` in a script is an error like any other: a SystemExit reaching
  ParaView's C++ ends the process (its PyErr_Print exits on SystemExit);
* the driver can read what went wrong (``DriverSide.take_failure``): the one-line
  summary and the traceback, which ranks above 0 cannot print (ParaView silences
  them);
* between a script's catalyst_execute and its extracts (which ParaView writes
  right after), every rank agrees (``_canopy.agree_before_extracts``): if
  catalyst_execute failed on any rank, or the extracts due at this step would not
  fit on the disk, no rank writes any (VTK 9.2's polydata and unstructured
  writers crash on a full disk, and the others leave partial files).
  ``DriverSide.discard_outputs`` removes what a failed step of a script wrote.

canopy_catalyst imports this module, never the reverse.

``StepTimeLimitExceeded`` (``_canopy``'s) is what the driver's watchdog raises in a
script that runs past the step time limit.
"""
import functools
import os
import shutil
import time
import traceback

import _canopy

_failure = None  # (summary, traceback) of the last failed call, until taken
_in_script = False  # the script's own code is running: the time limit may interrupt it
_extractors = {}  # script path -> the extractors its import created
_outputs = {}  # script path -> (start of its last run, the files that run was to write)
_measures = {}  # name -> this rank's value of what the running script measured (report_measure)

StepTimeLimitExceeded = _canopy.StepTimeLimitExceeded

# Disk space the extracts of one rank may need at most: the data in memory
# times 4/3 for base64 (compression only shrinks it) and a margin (an image:
# its raw pixels and a margin), and per extract 16 KiB for the XML around the
# data, the summary file and the filesystem's blocks. Python checks once, for
# every extract (_refuse_unless_fits); the VTKHDF writer checks its own file again
# in C++ (adaptor/io/VtkHdfWriter.cxx, freeSpaceProblem), from its exact size.
DATA_FACTOR = 1.5
IMAGE_FACTOR = 1.1
PER_EXTRACT_BYTES = 16 * 1024


class ScriptExit(RuntimeError):
    """A script called sys.exit(); raised instead, so the simulation goes on."""


class NotEnoughDiskSpace(OSError):
    """The extracts due at a step would not fit on the disk: none is written."""


def _summary(error):
    if isinstance(error, (ScriptExit, StepTimeLimitExceeded, NotEnoughDiskSpace)):
        return str(error)
    return "raised an error: " + "".join(
        traceback.format_exception_only(type(error), error)).strip().replace("\n", " ")


def _script_code(call):
    """Marks the call as the script's own code: only there does the step time
    limit interrupt (an exception in the driver's agreements would leave the
    other ranks waiting)."""
    @functools.wraps(call)
    def script_code(*args):
        global _in_script
        _in_script = True
        try:
            return call(*args)
        finally:
            _in_script = False

    return script_code


def _guarded(call):
    @functools.wraps(call)
    def guarded(*args):
        global _failure
        try:
            return call(*args)
        except SystemExit as exit:
            error = ScriptExit("called sys.exit(%r)" % (exit.code,))
            _failure = (_summary(error), traceback.format_exc())
            raise error from exit
        except BaseException as error:
            _failure = (_summary(error), traceback.format_exc())
            raise

    guarded._canopy_guarded = True
    return guarded


def guard_catalyst_calls():
    from paraview.catalyst import detail, v2_internals
    if getattr(v2_internals.do_catalyst_execute, "_canopy_guarded", False):
        return
    for name in ("import_and_validate", "do_catalyst_initialize", "do_request_data_description",
                 "do_catalyst_finalize"):
        setattr(v2_internals, name, _guarded(_script_code(getattr(v2_internals, name))))
    v2_internals.do_catalyst_execute = _guarded(_before_extracts(
        _script_code(v2_internals.do_catalyst_execute)))
    detail.RegisterExtractor = _recording_extractors(detail.RegisterExtractor)


def _active_step():
    """(script path, step, time) of the script ParaView is running."""
    from paraview.modules.vtkPVPythonCatalyst import vtkCPPythonScriptV2Helper
    helper = vtkCPPythonScriptV2Helper.GetActiveInstance()
    description = helper.GetDataDescription()
    return (os.path.abspath(helper.GetScriptFileName()), description.GetTimeStep(),
            description.GetTime())


def _recording_extractors(register):
    """Keeps, per script, the extractors it creates (ParaView keeps them hidden)."""
    @functools.wraps(register)
    def register_extractor(extractor):
        register(extractor)
        _extractors.setdefault(_active_step()[0], []).append(extractor)

    return register_extractor


def _due_outputs(script, directory, step, step_time):
    """The files the script's extractors will write at this step, and the disk
    space they may need on this rank (an upper bound)."""
    from paraview.modules.vtkRemotingServerManager import vtkSMExtractsController
    controller = vtkSMExtractsController()
    controller.SetTimeStep(step)
    controller.SetTime(step_time)
    paths, needed = [], 0.0
    for extractor in _extractors.get(script, []):
        if not controller.IsTriggerActivated(extractor.SMProxy):
            continue
        writer = extractor.Writer
        pattern = str(writer.FileName)
        try:
            name = pattern.format(timestep=step, time=step_time)
            paths.append(name if os.path.isabs(name) else os.path.join(directory, name))
        except (KeyError, IndexError, ValueError):
            pass  # a pattern Canopy cannot predict: not removed if the step fails
        if "ImageResolution" in writer.ListProperties():
            width, height = (int(n) for n in writer.ImageResolution)
            needed += IMAGE_FACTOR * 4 * width * height + PER_EXTRACT_BYTES
        elif "Input" in writer.ListProperties() and writer.Input is not None:
            source = writer.Input
            source.UpdatePipeline(step_time)  # as the writer will (the result is kept)
            kib = source.GetDataInformation().GetMemorySize()
            needed += _written_bytes(1024 * kib) + PER_EXTRACT_BYTES
    return paths, needed


def _written_bytes(memory_bytes):
    """The disk space data of `memory_bytes` in memory may take once written."""
    return DATA_FACTOR * memory_bytes


def _free_bytes(directory):
    while directory and not os.path.isdir(directory):
        directory = os.path.dirname(directory)
    disk = os.statvfs(directory or ".")
    return float(disk.f_bavail * disk.f_frsize)


def _size(count):
    for unit in ("bytes", "KiB", "MiB", "GiB"):
        if count < 1024 or unit == "GiB":
            return "%.0f %s" % (count, unit) if unit == "bytes" else "%.1f %s" % (count, unit)
        count /= 1024.0


def _before_extracts(execute):
    """do_catalyst_execute, then the agreement before ParaView writes the extracts
    (_canopy.agree_before_extracts, on the driver's agreement communicator)."""

    @functools.wraps(execute)
    def execute_then_agree(module):
        script, step, step_time = _active_step()
        directory = module.options.ExtractsOutputDirectory
        _outputs[script] = (time.time(), [])
        error, result, needed = None, None, 0.0
        try:
            result = execute(module)
            paths, needed = _due_outputs(script, directory, step, step_time)
            _outputs[script] = (_outputs[script][0], paths)
        except BaseException as exception:  # noqa: B902 - re-raised below, after agreeing
            error = exception
        # Every rank comes here, also where the script failed.
        outcome = _summary(error) if error is not None else ""
        failed, total_needed, free = _canopy.agree_before_extracts(outcome, needed,
                                                                   _free_bytes(directory))
        if error is not None:
            raise error
        if failed:
            raise RuntimeError("catalyst_execute failed on another rank; no rank writes the "
                               "step's extracts")
        _refuse_unless_fits(directory, total_needed, free)
        return result

    return execute_then_agree


def ensure_step_fits(own_data_bytes, directory):
    """For a script that writes files itself in catalyst_execute (data_extracts.py's
    grid writers), before it writes them: agrees over ranks that those (data of
    `own_data_bytes` in memory on this rank) and the step's extracts fit on the
    disk; raises NotEnoughDiskSpace on every rank otherwise, with nothing written.
    Collective: every rank calls it (the agreement after catalyst_execute follows
    as usual)."""
    script, step, step_time = _active_step()
    _, needed = _due_outputs(script, directory, step, step_time)
    needed += _written_bytes(own_data_bytes)
    failed, total_needed, free = _canopy.agree_before_extracts("", needed, _free_bytes(directory))
    _refuse_unless_fits(directory, total_needed, free)


def _refuse_unless_fits(directory, total_needed, free):
    """Raises NotEnoughDiskSpace when what all ranks need exceeds the least free
    space (both agreed over ranks: every rank decides alike)."""
    if total_needed > free:
        raise NotEnoughDiskSpace(
            "could not write its extracts: not enough free disk space in '%s' (up to %s "
            "needed by all ranks, %s free); nothing written"
            % (directory, _size(total_needed), _size(free)))


def report_measure(name, local_value):
    """Records a number the running script measured at this step (canopy_catalyst.report);
    `local_value`, a function, is called after the script's extracts were written."""
    _measures[str(name)] = local_value


def _remove(remove, path):
    try:
        remove(path)
    except OSError:
        pass  # another rank removed it first


class DriverSide:
    """What the C++ driver calls in Python (PythonSide in adaptor/insitu/CanopyModule.h):
    registered with _canopy.connect when this module is imported."""

    def take_failure(self):
        """(summary, traceback) of the last failed script call, or None; forgets it."""
        global _failure
        failure, _failure = _failure, None
        return failure

    def take_measures(self, evaluate):
        """What the script that just ran reported, summed over ranks: {name: total}, in
        the StepReport. Collective when `evaluate` (every rank's script ran; every rank
        reported the same names); otherwise forgets them (the step failed somewhere)."""
        global _measures
        measures, _measures = _measures, {}
        if not evaluate:
            return {}
        names = sorted(measures)
        local = []
        for name in names:
            try:
                local.append(float(measures[name]()))
            except Exception:  # a measure is never worth a deadlock: report NaN
                local.append(float("nan"))
        # First the most values any rank has, so that every rank reduces as many
        # even if a script reported different names on some ranks: a measure is
        # never worth a deadlock (the misreported sums are then wrong).
        most = int(_canopy.reduce([float(len(local))], "max")[0])
        padded = local + [float("nan")] * (most - len(local))
        return dict(zip(names, _canopy.reduce(padded, "sum")))

    def discard_outputs(self, script):
        """Removes what the last run of `script` wrote (its extracts failed on some
        rank): each file due at that step, and the folder of its pieces, if they
        were written since that run started."""
        start, paths = _outputs.pop(os.path.abspath(script), (None, []))
        for path in paths:
            stem = os.path.splitext(path)[0]
            for candidate in (path, stem):
                try:
                    if os.lstat(candidate).st_mtime < start - 1.0:  # coarse filesystem clocks
                        continue
                except OSError:
                    continue
                if candidate == path and os.path.isfile(candidate):
                    _remove(os.remove, candidate)
                elif candidate == stem and os.path.isdir(candidate) and path != stem:
                    _remove(shutil.rmtree, candidate)

    def install_interrupt(self, number):
        """Handles signal `number` on the main thread: when the driver's watchdog
        wants the running script call stopped (_canopy.interrupt_wanted() gives the
        message), raises StepTimeLimitExceeded where the script is. Not installed
        (False) if the simulation handles that signal itself."""
        import signal
        if signal.getsignal(number) not in (signal.SIG_DFL, signal.SIG_IGN):
            return False

        def on_signal(signal_number, frame):
            message = _canopy.interrupt_wanted() if _in_script else None
            if message:
                raise StepTimeLimitExceeded(message)

        signal.signal(number, on_signal)
        return True


    def plot_history(self, csv_path, png_path):
        """Plots the query history at close (docs/queries.md): each query or expression
        column against time, one panel each, every trigger's firings as vertical lines.
        Returns '' when written, else why not (no matplotlib, no rows)."""
        import csv
        try:
            import matplotlib
            matplotlib.use("Agg")
            from matplotlib import pyplot
        except ImportError as error:
            return "no plot of the query history: %s" % error
        with open(csv_path) as f:
            rows = list(csv.reader(f))
        if len(rows) < 2:
            return "no plot of the query history: no step was evaluated"
        header, rows = rows[0], rows[1:]
        times = [float(row[1]) for row in rows]
        fired = [i for i, name in enumerate(header) if name.endswith(": fired")]
        held = [i - 1 for i in fired]
        values = [i for i in range(2, len(header)) if i not in fired and i not in held]
        figure, axes = pyplot.subplots(max(1, len(values)), 1, sharex=True, squeeze=False,
                                       figsize=(8, 1.8 * max(1, len(values)) + 0.8))
        colours = pyplot.rcParams["axes.prop_cycle"].by_key()["color"]
        for panel, column in zip(axes[:, 0], values):
            series = [float(row[column]) for row in rows]
            panel.plot(times, series, marker=".")
            panel.set_ylabel(header[column], fontsize=8)
            # A conserved quantity moves by rounding only: drawn flat around its value,
            # not as noise under an offset like "1e-14+4.5e-2".
            finite = [v for v in series if v == v and abs(v) != float("inf")]
            if finite:
                low, high = min(finite), max(finite)
                if high - low <= 1e-9 * max(abs(low), abs(high)):
                    margin = max(abs(high) * 1e-3, 1e-12)
                    panel.set_ylim(low - margin, high + margin)
            panel.ticklabel_format(axis="y", useOffset=False, style="plain")
            for n, trigger in enumerate(fired):
                label = header[trigger][:-len(": fired")]
                for row, time in zip(rows, times):
                    if float(row[trigger]):
                        panel.axvline(time, color=colours[(n + 1) % len(colours)],
                                      linestyle="--", linewidth=1, label=label)
                        label = None
        axes[-1, 0].set_xlabel("time")
        if fired:
            axes[0, 0].legend(fontsize=7, title="trigger fired", title_fontsize=7)
        figure.tight_layout()
        figure.savefig(png_path, dpi=100)
        pyplot.close(figure)
        return ""


guard_catalyst_calls()
_canopy.connect(DriverSide())
