"""Tests tests/support/with_xvfb.sh, the private X server every rendering test uses.

Usage: python3 with_xvfb_test.py <with_xvfb.sh>

Checks that the command gets a working display of the requested size, that the
server admits only clients with the run's cookie, survives a client closing its
last connection and reopening at once (what made xvfb-run's tests flaky: its
server resets then and refuses connections meanwhile), that concurrent runs get
distinct displays, that the command's status comes back, and that the server is
gone afterwards: after success, failure, SIGTERM, and when it cannot start.
"""
import ctypes
import os
import signal
import subprocess
import sys
import tempfile
import time

WRAPPER = os.path.abspath(sys.argv[1])
FAILURES = []


def expect(condition, message):
    print(("ok:     " if condition else "FAILED: ") + message, flush=True)
    if not condition:
        FAILURES.append(message)


def run(args, **kwargs):
    return subprocess.run([WRAPPER] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True, timeout=300, **kwargs)


def gone(pid, display, wait=5.0):
    """The server process has exited and its display socket is removed."""
    deadline = time.time() + wait
    while time.time() < deadline:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return not os.path.exists("/tmp/.X11-unix/X%s" % display)
        time.sleep(0.05)
    return False


def reopen_displays(count):
    """Opens and closes the display `count` times in a row; returns the failures."""
    x11 = ctypes.CDLL("libX11.so.6")
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
    failures = 0
    for _ in range(count):
        display = x11.XOpenDisplay(None)
        if not display:
            failures += 1
            continue
        x11.XCloseDisplay(display)
    return failures


if len(sys.argv) > 2 and sys.argv[2] == "--reopen":
    # Run inside the wrapper (below): the client side of the reset check.
    print("reopen failures: %d" % reopen_displays(int(sys.argv[3])))
    sys.exit(0)

# 1. A working display of the requested size; the status comes back; the server is gone.
probe = ("echo display=$DISPLAY; echo pid=$CANOPY_XVFB_PID; "
         "xdpyinfo | grep dimensions; "
         "XAUTHORITY=/dev/null xdpyinfo >/dev/null 2>&1 && echo stranger=admitted; "
         "exit 7")
result = run(["--screen", "640x480x24", "sh", "-c", probe])
values = dict(line.split("=", 1) for line in result.stdout.splitlines() if "=" in line)
expect(result.returncode == 7, "the command's exit status comes back (7, got %d)" % result.returncode)
expect(values.get("display", "").startswith(":"), "the command runs with DISPLAY set (%r)"
       % values.get("display"))
expect("640x480 pixels" in result.stdout, "the screen has the requested size")
expect("stranger" not in values, "a client without the run's cookie is refused")
if "pid" in values and "display" in values:
    expect(gone(int(values["pid"]), values["display"][1:]),
           "the server and its socket are gone when the command has ended")

# 2. Closing the last connection and reopening at once never fails (no server reset).
result = run(["--", sys.executable, __file__, WRAPPER, "--reopen", "300"])
expect(result.returncode == 0 and "reopen failures: 0" in result.stdout,
       "300 close-then-reopen cycles in one process all connect (%s)"
       % (result.stdout.strip() or result.stderr.strip()))

# 3. Concurrent runs each get their own display and all succeed.
runs = [subprocess.Popen([WRAPPER, "sh", "-c", "xdpyinfo >/dev/null && echo $DISPLAY"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for _ in range(6)]
outputs = [r.communicate(timeout=300) for r in runs]
displays = [out.strip() for out, _ in outputs]
expect(all(r.returncode == 0 for r in runs),
       "6 concurrent runs all succeed (%s)" % [err.strip() for _, err in outputs if err.strip()])
expect(len(set(displays)) == 6, "6 concurrent runs get 6 distinct displays (%s)" % displays)

# 4. A server that cannot start: a clear message, status 125, the command never runs.
with tempfile.TemporaryDirectory() as scratch:
    marker = os.path.join(scratch, "ran")
    result = run(["--screen", "not-a-screen", "touch", marker])
    expect(result.returncode == 125, "no server: exit status 125 (got %d)" % result.returncode)
    expect("with_xvfb: Xvfb" in result.stderr,
           "no server: the message says Xvfb did not start (%r)" % result.stderr[:300])
    expect(not os.path.exists(marker), "no server: the command is not run")

# 5. SIGTERM to the wrapper stops the command and the server.
wrapper = subprocess.Popen([WRAPPER, "sh", "-c", "echo $CANOPY_XVFB_PID $DISPLAY; exec sleep 60"],
                           stdout=subprocess.PIPE, text=True)
pid, display = wrapper.stdout.readline().split()
wrapper.send_signal(signal.SIGTERM)
status = wrapper.wait(timeout=30)
expect(status == 143, "SIGTERM: the wrapper exits with 143 (got %d)" % status)
expect(gone(int(pid), display[1:]), "SIGTERM: the server and its socket are gone")

print("%d check(s) failed" % len(FAILURES) if FAILURES else "all checks passed")
sys.exit(1 if FAILURES else 0)
