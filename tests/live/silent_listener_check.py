"""A Catalyst Live address where something accepts connections and never
answers (a hung viewer, or another service on the port): ParaView 5.11's link
would wait in its handshake forever, holding the simulation.

  silent_listener_check.py PORT OUTPUT SIMULATION_COMMAND...

Listens on PORT without ever answering, runs the simulation with
--live localhost:PORT --live-stall-limit 2, and checks that it ends with 0, no
failed pipeline and an image for every step, having waited once, for the stall
limit (one warning naming the address, the next attempt a minute later), not at
every step.
"""
import glob
import os
import re
import shutil
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import expect, finish  # noqa: E402

port, output = int(sys.argv[1]), sys.argv[2]
shutil.rmtree(output, ignore_errors=True)
os.makedirs(output)
listener = socket.socket()
listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
listener.bind(("127.0.0.1", port))
listener.listen(16)  # connections complete in the kernel; nobody reads them

start = time.time()
run = subprocess.run(sys.argv[3:] + ["--live", "localhost:%d" % port, "--live-stall-limit", "2",
                                     "--output", output],
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
took = time.time() - start
log = run.stdout
open(os.path.join(output, "simulation.log"), "w").write(log)

expect(run.returncode == 0, "the simulation exits with 0 (got %d)" % run.returncode)
expect(re.search(r" 0 pipeline failure\(s\)", log) is not None,
       "the simulation reports no failed pipeline")
steps = re.findall(r"^step +(\d+) ", log, re.M)
images = glob.glob(os.path.join(output, "surface_*.png"))
expect(len(steps) > 1 and len(images) == len(steps),
       "an image for every step (%d images, %d steps)" % (len(images), len(steps)))
waits = re.findall(r"WARN\|.*Catalyst Live: something at localhost:%d accepted the connection "
                   r"but did not answer for 2 s.*next attempt is in 60 s" % port, log)
expect(len(waits) == 1, "one warning for the silent listener (%d)" % len(waits))
# One warning: the wait happened once (each attempt that waits warns), not at
# every step; a wait without the guard would never end (the timeout above).
expect(not re.search(r"ERR\|", log), "no error in the simulation's log")
print("took %.1f s" % took)
finish()
