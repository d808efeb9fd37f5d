"""Triggers fire at exactly the steps a replay of the query history says.

Usage: triggers_check.py OUTPUT_DIR MODE CONDITION [--frequency N] [--same-as OTHER_DIR]
                         [--refused TEXT] -- COMMAND...

Runs COMMAND (the stand-in simulation with one marker script carrying --trigger and
--trigger-mode=MODE), then reads OUTPUT_DIR/canopy_queries.csv and replays the
trigger in Python, independently of the driver: CONDITION is a Python expression over
`q(text, k=0)` (the query column `text`, k evaluated steps ago; None before the first
step). Checks, step by step: the history's "held" column equals the replayed
condition, its "fired" column equals the mode's rule (while / rising / every:N) on the
replayed condition, the script ran (ran_<step>.txt) exactly at the fired steps its
frequency names, and willExecute said yes at those steps and never where the trigger
did not fire. --same-as: the query columns equal another
run's (another rank count) to 1e-12. --refused: the command must fail at open with
TEXT on stderr, and no step may run.
"""
import csv
import math
import os
import subprocess
import sys


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def read_history(folder):
    with open(os.path.join(folder, "canopy_queries.csv")) as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    return header, [[float(v) for v in row] for row in rows]


def main():
    split = sys.argv.index("--")
    args, command = sys.argv[1:split], sys.argv[split + 1:]
    output, mode, condition = args[0], args[1], args[2]
    frequency, same_as, refused = 1, None, None
    rest = args[3:]
    while rest:
        if rest[0] == "--frequency":
            frequency = int(rest[1])
        elif rest[0] == "--same-as":
            same_as = rest[1]
        elif rest[0] == "--refused":
            refused = rest[1]
        rest = rest[2:]
    if os.path.isdir(output):
        for name in os.listdir(output):
            path = os.path.join(output, name)
            if os.path.isfile(path):
                os.remove(path)
    run = subprocess.run(command, capture_output=True, text=True, timeout=280)
    if refused is not None:
        if run.returncode == 0:
            fail("the run was not refused:\n" + run.stdout)
        if refused not in run.stderr:
            fail("stderr does not say %r:\n%s" % (refused, run.stderr))
        if "step 0" in run.stdout:
            fail("a step ran before the refusal")
        print("refused at open: " + refused)
        return
    if run.returncode != 0:
        fail("the run failed (%d):\n%s\n%s" % (run.returncode, run.stdout, run.stderr))
    header, rows = read_history(output)
    column = {name: i for i, name in enumerate(header)}
    held_column, fired_column = len(header) - 2, len(header) - 1  # the trigger's two columns
    steps = [int(row[0]) for row in rows]
    if steps != list(range(len(rows))):
        fail("one row per evaluated step expected, steps %s" % steps)

    def value_at(s):
        def q(text, k=0):
            if s - k < 0:
                return None
            return rows[s - k][column[text]]
        return q

    held_before = False
    last_fired = None
    fired_steps = []
    for s in range(len(rows)):
        try:
            held = bool(eval(condition, {"math": math}, {"q": value_at(s)}))
        except TypeError:  # a value before the first step: NaN compares false
            held = False
        if mode == "while":
            fires = held
        elif mode == "rising":
            fires = held and not held_before
        else:
            every = int(mode.split(":")[1])
            fires = held and (last_fired is None or s - last_fired >= every)
        held_before = held
        if fires:
            last_fired = s
            fired_steps.append(s)
        if bool(rows[s][held_column]) != held:
            fail("step %d: the history says the condition %s, the replay %s"
                 % (s, "held" if rows[s][held_column] else "did not hold", held))
        if bool(rows[s][fired_column]) != fires:
            fail("step %d: the history says the trigger %s, the replay %s"
                 % (s, "fired" if rows[s][fired_column] else "did not fire", fires))
    ran = sorted(int(name[4:10]) for name in os.listdir(output) if name.startswith("ran_"))
    expected_runs = [s for s in fired_steps if s % frequency == 0]
    if ran != expected_runs:
        fail("the script ran at steps %s, the replay says %s" % (ran, expected_runs))
    will = [int(line.split()[1]) for line in run.stdout.splitlines()
            if line.startswith("step ") and line.endswith("will execute 1")]
    # willExecute may say yes where the frequency alone cannot tell before the script's
    # import (ParaView's scripts are due before their first run), never where the
    # trigger does not fire, and always where the script runs.
    if not set(expected_runs) <= set(will) <= set(fired_steps):
        fail("willExecute said yes at steps %s: the script ran at %s, the trigger fired at %s"
             % (will, expected_runs, fired_steps))
    # What the script read with canopy_catalyst.query_values(), where it recorded it:
    # the history's row, on every rank.
    for name in sorted(os.listdir(output)):
        if not (name.startswith("queries_") and name.endswith(".json")):
            continue
        import json
        step = int(name.split("_")[1])
        seen = json.load(open(os.path.join(output, name)))
        for text, value in seen.items():
            if text in column and rows[step][column[text]] != value:
                fail("%s: the script read %s = %r, the history has %r"
                     % (name, text, value, rows[step][column[text]]))
        missing = [text for text in header[2:-2] if text not in seen]
        if missing:
            fail("%s: the script did not get %s" % (name, missing))
        print("%s: the script read the history's %d values" % (name, len(seen)))
    if not fired_steps or len(fired_steps) == len(rows):
        fail("a test that fires never or always proves little: fired at %s" % fired_steps)
    if same_as:
        other_header, other_rows = read_history(same_as)
        if other_header != header or len(other_rows) != len(rows):
            fail("the history differs in shape from %s" % same_as)
        for s, (mine, theirs) in enumerate(zip(rows, other_rows)):
            for name, a, b in zip(header, mine, theirs):
                if abs(a - b) > 1e-12 * max(1.0, abs(a)):
                    fail("step %d, %s: %r here, %r in %s" % (s, name, a, b, same_as))
    # The history's plot, written at close by rank 0: a PNG beside the CSV.
    png = os.path.join(output, "canopy_queries.png")
    if not os.path.isfile(png):
        fail("no plot of the history (canopy_queries.png)")
    with open(png, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        fail("canopy_queries.png is not a PNG")
    width, height = int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")
    if width < 400 or height < 150:
        fail("canopy_queries.png is %dx%d: too small to show %d columns" % (width, height, len(header)))
    print("%d steps, fired at %s, ran at %s; plot %dx%d" % (len(rows), fired_steps, ran, width, height))


main()
