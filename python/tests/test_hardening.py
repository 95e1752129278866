"""Issue 33 in Python: every keyword of pfill.fill, given NaN, +-inf, 0, a
negative number, 1e300 or a non-number, raises an exception with one line of
under 1,000 bytes, or returns a fill that pfill.check measures as its own
metrics say; it never kills the interpreter. Each keyword runs in a child
interpreter, so an abort shows as that keyword's failure, not as a lost run.
"""
import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import pfill

VALUES = ["float('nan')", "float('inf')", "float('-inf')", "0", "-1", "1e300", "'abc'"]
BASE = dict(count=40, hole_rounds=0)  # a small fill of the built-in sphere

CHILD = r"""
import json, math, sys, warnings
import numpy as np
import pfill
warnings.simplefilter("ignore")
keyword, values, base = sys.argv[1], json.loads(sys.argv[2]), json.loads(sys.argv[3])
for text in values:
    kwargs = dict(base)
    kwargs.pop("radius" if keyword == "count" else "count" if keyword == "radius" else None, None)
    kwargs[keyword] = eval(text)
    try:
        r = pfill.fill("sphere", **kwargs)
    except Exception as e:
        print(json.dumps({"value": text, "error": type(e).__name__, "message": str(e)}), flush=True)
        continue
    m = pfill.check(r.positions, r.radii, "sphere")
    print(json.dumps({"value": text, "particles": [len(r), m["particles"]],
                      "inside": [r.metrics["contained_share"], m["contained_share"]],
                      "overlap": [r.metrics["max_overlap"], m["max_overlap"]]}), flush=True)
"""


def keywords():
    """The settings pfill.fill's docstring lists (one a line under 'Settings')."""
    doc = pfill.fill.__doc__
    lines = doc[doc.index("Settings (default in brackets):"):].splitlines()[1:]
    return [line.split()[0] for line in lines if line.startswith("  ")]


def test_keywords_are_found():
    assert {"count", "radius", "birth", "exponents", "rest_distance"} <= set(keywords())


@pytest.mark.parametrize("keyword", keywords())
def test_hostile_values_raise_one_line_or_fill_what_check_measures(keyword):
    child = subprocess.run([sys.executable, "-c", CHILD, keyword, json.dumps(VALUES), json.dumps(BASE)],
                           capture_output=True, text=True, timeout=600)
    assert child.returncode == 0, f"{keyword}: the interpreter ended with {child.returncode}: {child.stderr[-500:]}"
    answers = [json.loads(line) for line in child.stdout.splitlines() if line.startswith("{")]
    assert len(answers) == len(VALUES), child.stdout + child.stderr
    for a in answers:
        if "error" in a:
            assert "\n" not in a["message"] and len(a["message"].encode()) < 1000, a
            assert a["message"], a
        else:
            assert a["particles"][0] == a["particles"][1], (keyword, a)
            assert a["inside"][0] == pytest.approx(a["inside"][1], abs=1e-9), (keyword, a)
            assert a["overlap"][0] == pytest.approx(a["overlap"][1], abs=1e-6), (keyword, a)


def test_count_and_radius_together_are_refused():
    with pytest.raises(Exception, match="not both"):
        pfill.fill("sphere", count=300, radius=0.05)


def test_a_path_with_a_nul_is_refused():
    with pytest.raises(Exception, match="NUL"):
        pfill.fill("sphere\0.obj", count=40)


def test_float_triangle_indices_are_refused():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=float) + 0.7
    with pytest.raises(Exception, match="integer"):
        pfill.fill((v, t), count=40)


def test_radius_1e300_and_a_nan_birth_point_raise():
    with pytest.raises(Exception, match="no particle of radius"):
        pfill.fill("sphere", radius=1e300)
    with pytest.raises(Exception, match="birth"):
        pfill.fill("sphere", count=40, birth=(math.nan, 0, 0))
    with pytest.raises(Exception, match="birth"):
        pfill.fill("sphere", count=40, birth=(1e19, 0, 0))
