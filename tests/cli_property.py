#!/usr/bin/env python3
"""Property test (issue 33): every option of `pfill fill`, `check`, `info`
and `render`, given NaN, +-inf, 0, a negative number, 1e300 or a non-number,
ends in exit 1 or 2 with one line of under 1,000 bytes on stderr, or in a
result: a fill whose file `pfill check` measures as the fill's own summary
says (check may also exit 3, a missed threshold). Never a signal, never a
hang. The options are read from each command's --help, so new ones are
covered. Usage: cli_property.py PFILL_BINARY"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

PFILL = os.path.abspath(sys.argv[1])
VALUES = ["nan", "inf", "-inf", "0", "-1", "1e300", "abc"]
# A small, quick fill: few spheres, a short pass 1, no holes round.
FILL_BASE = {"--builtin": "sphere", "-n": "60", "--max-steps": "300", "--settle-steps": "300",
             "--hole-rounds": "0", "-o": "out.ply"}

failures = []
tried = 0
verified = 0  # fills that succeeded and whose file check measured as their summary said


def options_of(command):
    """(name, takes_value) for each option in `pfill COMMAND --help`."""
    text = subprocess.run([PFILL, command, "--help"], capture_output=True, text=True, timeout=60).stdout
    found = []
    for line in text.splitlines():
        # "  -n,--count UINT:INT    About ...": a type one space after the name takes a value;
        # a flag's description starts two or more spaces after it.
        m = re.match(r"^\s+((?:-\w,)?--[\w-]+)( [A-Z]\S*)?(?:\s|$)", line)
        if not m:
            continue
        names = m.group(1).split(",")
        name = names[-1]
        if name in ("--help", "--version"):
            continue
        found.append((name, names, m.group(2) is not None))
    return found


def run(args, cwd):
    return subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=120, errors="replace")


def judge(label, result, allowed=(0, 1, 2)):
    """The common part: no signal, an allowed status, one short line on an error."""
    if result.returncode < 0 or result.returncode >= 128:
        failures.append(f"{label}: ended by signal / status {result.returncode}: {result.stderr[-300:]}")
        return False
    if result.returncode not in allowed:
        failures.append(f"{label}: exit {result.returncode}: {result.stderr[-300:]}")
        return False
    if result.returncode == 0 and re.search(r"\b(nan|inf)\b", result.stdout + result.stderr, re.I):
        failures.append(f"{label}: exit 0 with a NaN or infinity in its output: {result.stdout[:300]!r}")
        return False
    if result.returncode in (1, 2):
        lines = [line for line in result.stderr.splitlines() if line.strip()]
        if len(lines) != 1 or len(lines[0].encode()) >= 1000:
            failures.append(f"{label}: exit {result.returncode} with {len(lines)} lines, "
                            f"{len(result.stderr.encode())} bytes on stderr: {result.stderr[:300]!r}")
            return False
    return True


def fill_agrees(label, result, cwd, output):
    """A fill that succeeded: `pfill check` on its file agrees with its summary."""
    try:
        summary = json.loads(result.stdout)["metrics"]
    except (ValueError, KeyError):
        failures.append(f"{label}: exit 0 but no JSON summary: {result.stdout[:200]!r}")
        return
    path = os.path.join(cwd, output)
    if not os.path.exists(path):
        failures.append(f"{label}: exit 0 but {output} was not written")
        return
    check = run([PFILL, "check", output, "sphere", "--json"], cwd)
    if check.returncode != 0:
        failures.append(f"{label}: check of the written file exited {check.returncode}: {check.stderr[:200]}")
        return
    global verified
    verified += 1
    measured = json.loads(check.stdout)["metrics"]
    if measured["particles"] != summary["particles"]:
        failures.append(f"{label}: the file holds {measured['particles']} spheres, the summary says {summary['particles']}")
    if abs(measured["contained_share"] - summary["contained_share"]) > 1e-9:
        failures.append(f"{label}: check finds {measured['contained_share']} inside, the summary {summary['contained_share']}")
    if abs(measured["max_overlap"] - summary["max_overlap"]) > 1e-3:
        failures.append(f"{label}: check finds overlaps up to {measured['max_overlap']}, the summary {summary['max_overlap']}")


def main():
    global tried, verified
    top = tempfile.mkdtemp(prefix="pfill-property-")
    try:
        shared = os.path.join(top, "shared")
        os.mkdir(shared)
        made = run([PFILL, "fill", "--builtin", "sphere", "-n", "60", "-q", "--hole-rounds", "0", "-o", "parts.ply"],
                   shared)
        if made.returncode != 0:
            print("FAIL: the base fill failed:", made.stderr)
            return 1
        parts = os.path.join(shared, "parts.ply")
        bases = {
            "fill": None,  # built per option below
            "check": [PFILL, "check", parts, "sphere"],
            "info": [PFILL, "info", "sphere"],
            "render": [PFILL, "render", parts, "-o", "pic.png", "--size", "48x32"],
        }
        for command in ("fill", "check", "info", "render"):
            opts = options_of(command)
            if not opts:
                failures.append(f"no options found in `pfill {command} --help`")
            for name, aliases, takes_value in opts:
                for value in (VALUES if takes_value else [None]):
                    tried += 1
                    cwd = os.path.join(top, f"run{tried}")
                    os.mkdir(cwd)
                    if command == "fill":
                        base = {k: v for k, v in FILL_BASE.items() if k not in aliases}
                        if name in ("--mesh",):
                            base.pop("--builtin", None)
                        args = [PFILL, "fill", "--json", "-q"] if name not in ("--json", "--quiet") else [PFILL, "fill", "-q"]
                        for k, v in base.items():
                            args += [k, v]
                    else:
                        args = list(bases[command])
                    args += [name] if value is None else [name, value]
                    label = " ".join(os.path.basename(a) if a == PFILL else a for a in args)
                    try:
                        result = run(args, cwd)
                    except subprocess.TimeoutExpired:
                        failures.append(f"{label}: no answer within 120 s")
                        continue
                    allowed = (0, 1, 2, 3) if command == "check" else (0, 1, 2)
                    if not judge(label, result, allowed):
                        continue
                    if command == "fill" and result.returncode == 0 and "--json" in args and name not in ("-o", "--output", "--report"):
                        fill_agrees(label, result, cwd, base.get("-o", "out.ply"))
                    shutil.rmtree(cwd, ignore_errors=True)
        # The positional arguments: paths and shape names.
        positional = [
            lambda v: [PFILL, "fill", v, "-q", "-n", "60", "--max-steps", "300", "--hole-rounds", "0", "-o", "out.ply"],
            lambda v: [PFILL, "check", v, "sphere"],
            lambda v: [PFILL, "check", parts, v],
            lambda v: [PFILL, "info", v],
            lambda v: [PFILL, "render", v, "-o", "pic.png", "--size", "48x32"],
        ]
        for make in positional:
            for value in VALUES:
                tried += 1
                cwd = os.path.join(top, f"run{tried}")
                os.mkdir(cwd)
                args = make(value)
                label = " ".join(os.path.basename(a) if a == PFILL else a for a in args)
                try:
                    judge(label, run(args, cwd), (0, 1, 2, 3) if args[1] == "check" else (0, 1, 2))
                except subprocess.TimeoutExpired:
                    failures.append(f"{label}: no answer within 120 s")
    finally:
        shutil.rmtree(top, ignore_errors=True)
    for f in failures:
        print("FAIL:", f)
    print(f"{tried} inputs tried, {len(failures)} failures; {verified} fills succeeded and pfill check agreed "
          f"with their summaries")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
