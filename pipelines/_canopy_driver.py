"""The in-situ driver's side of Python (not for pipeline scripts).

ParaView 5.11 calls a V2 script through functions of
``paraview.catalyst.v2_internals`` (import, catalyst_initialize,
RequestDataDescription, catalyst_execute, catalyst_finalize). ``guard_catalyst_calls``
wraps them so that

* ``sys.exit()`` in a script is an error like any other: a SystemExit reaching
  ParaView's C++ ends the process (its PyErr_Print exits on SystemExit);
* the driver can read what went wrong (``take_failure``): the one-line summary
  and the traceback, which ranks above 0 cannot print (ParaView silences them).

``StepTimeLimitExceeded`` is what the driver's watchdog raises in a script that
runs past the step time limit.
"""
import functools
import traceback

_failure = None  # (summary, traceback) of the last failed call, until taken


class ScriptExit(RuntimeError):
    """A script called sys.exit(); raised instead, so the simulation goes on."""


class StepTimeLimitExceeded(TimeoutError):
    """Raised by the driver's watchdog where a script is when the step time limit
    passes (InSituOptions::stepTimeLimitSeconds)."""


def _summary(error):
    if isinstance(error, (ScriptExit, StepTimeLimitExceeded)):
        return str(error)
    return "raised an error: " + "".join(
        traceback.format_exception_only(type(error), error)).strip().replace("\n", " ")


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
    from paraview.catalyst import v2_internals
    for name in ("import_and_validate", "do_catalyst_initialize", "do_request_data_description",
                 "do_catalyst_execute", "do_catalyst_finalize"):
        call = getattr(v2_internals, name)
        if not getattr(call, "_canopy_guarded", False):
            setattr(v2_internals, name, _guarded(call))


def take_failure():
    """(summary, traceback) of the last failed script call, or None; forgets it."""
    global _failure
    failure, _failure = _failure, None
    return failure


def install_interrupt(number, interrupt_wanted):
    """Handles signal `number` on the main thread: when the driver's watchdog
    wants the running script call stopped (interrupt_wanted() gives the message),
    raises StepTimeLimitExceeded where the script is. Not installed (False) if
    the simulation handles that signal itself."""
    import signal
    if signal.getsignal(number) not in (signal.SIG_DFL, signal.SIG_IGN):
        return False

    def on_signal(signal_number, frame):
        message = interrupt_wanted()
        if message:
            raise StepTimeLimitExceeded(message)

    signal.signal(number, on_signal)
    return True
