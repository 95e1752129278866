"""The Python module against the command line and known answers.

Run by ctest (python.pfill) with PYTHONPATH naming build/python and
PFILL_CLI naming the `pfill` program. Fills are small (a few hundred
particles of a built-in shape), so no file outside the repository is needed.
"""
import json
import math
import os
import signal
import subprocess
import threading

import numpy as np
import pytest

import pfill

CLI = os.environ.get("PFILL_CLI", "pfill")
OPTIONS = dict(count=250, seed=3)  # one small fill, shared by the tests below


@pytest.fixture(scope="module")
def sphere_fill():
    return pfill.fill("sphere", **OPTIONS)


@pytest.fixture(scope="module")
def cli_fill(tmp_path_factory):
    """The same fill by `pfill fill`: its report and its particles (CSV)."""
    work = tmp_path_factory.mktemp("cli")
    subprocess.run([CLI, "fill", "--builtin", "sphere", "-n", str(OPTIONS["count"]), "--seed", str(OPTIONS["seed"]),
                    "-q", "-o", str(work / "s.csv"), "--report", str(work / "s.json")],
                   check=True, stdout=subprocess.DEVNULL)
    report = json.loads((work / "s.json").read_text())
    particles = np.loadtxt(work / "s.csv", delimiter=",", skiprows=1)
    return report, particles


def test_fill_arrays_have_the_documented_shapes_and_types(sphere_fill):
    r = sphere_fill
    n = len(r)
    assert 150 < n < 400
    assert r.positions.shape == (n, 3) and r.positions.dtype == np.float64
    assert r.radii.shape == (n,) and r.radii.dtype == np.float64
    assert np.allclose(r.radii, r.radius)
    assert r.colours is None  # the built-in sphere has no colours
    assert r.velocities.shape == (n, 3)
    assert r.ids.shape == (n,) and len(set(r.ids.tolist())) == n  # distinct ids
    assert r.metrics["particles"] == n
    assert np.all(np.linalg.norm(r.positions, axis=1) + r.radii <= 1.0 + 0.011 * r.radius)


def test_fill_matches_the_command_line_with_the_same_options_and_seed(sphere_fill, cli_fill):
    report, particles = cli_fill
    r = sphere_fill
    assert list(r.report.keys()) == list(report.keys())
    assert list(r.metrics.keys()) == list(report["metrics"].keys())
    assert r.metrics["particles"] == report["metrics"]["particles"]
    assert r.metrics["packing_fraction"] == pytest.approx(report["metrics"]["packing_fraction"], rel=1e-12)
    assert r.report["stop_signal"] == report["stop_signal"]
    assert r.report["seed"] == report["seed"] == OPTIONS["seed"]
    assert np.allclose(r.positions, particles[:, :3], rtol=0, atol=1e-6)
    assert np.allclose(r.radii, particles[:, 3], rtol=1e-6)


SHARED = os.environ.get("PFILL_SHARED_MESHES", "")


@pytest.mark.skipif(not os.path.exists(os.path.join(SHARED, "spot_textured.glb")),
                    reason="../shared/meshes is absent")
def test_a_textured_mesh_gives_the_command_lines_colours(tmp_path):
    mesh = os.path.join(SHARED, "spot_textured.glb")
    subprocess.run([CLI, "fill", mesh, "-n", "200", "--seed", "1", "-q", "-o", str(tmp_path / "t.csv")],
                   check=True, stdout=subprocess.DEVNULL)
    cli = np.loadtxt(tmp_path / "t.csv", delimiter=",", skiprows=1)
    r = pfill.fill(mesh, count=200, seed=1)
    assert r.colours is not None and r.colours.dtype == np.uint8
    assert len(r) == len(cli)
    assert np.array_equal(r.colours, cli[:, 4:7].astype(np.uint8))
    assert len(np.unique(r.colours, axis=0)) > 10  # the texture's colours, not one
    assert np.allclose(r.positions, cli[:, :3], rtol=0, atol=1e-6)


def test_fill_of_arrays_equals_the_fill_of_the_shape(sphere_fill):
    vertices, triangles = pfill.load_mesh("sphere")
    r = pfill.fill((vertices, triangles.astype(np.int32)), **OPTIONS)
    assert len(r) == len(sphere_fill)
    assert np.array_equal(r.positions, sphere_fill.positions)
    assert r.report["mesh"] == "(vertices, triangles)"


def test_an_open_mesh_warns_and_a_colour_option_colours_every_particle():
    vertices, triangles = pfill.load_mesh("cube")
    top = np.all(vertices[triangles][:, :, 2] == 1.0, axis=1)
    with pytest.warns(UserWarning, match="the mesh is open"):
        r = pfill.fill((vertices, triangles[~top]), count=60, seed=2, colour="#ff8000")
    assert r.colours.shape == (len(r), 3) and r.colours.dtype == np.uint8
    assert np.all(r.colours == [255, 128, 0])
    assert any("open" in w for w in r.report["warnings"])


def test_load_mesh_reads_a_file_into_arrays(tmp_path):
    path = tmp_path / "tetra.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    vertices, triangles = pfill.load_mesh(path)
    assert vertices.shape == (4, 3) and vertices.dtype == np.float64
    assert triangles.shape == (4, 3) and np.issubdtype(triangles.dtype, np.integer)
    assert sorted(map(tuple, vertices.tolist())) == [(0, 0, 0), (0, 0, 1), (0, 1, 0), (1, 0, 0)]
    assert triangles.min() == 0 and triangles.max() == 3
    cube_vertices, cube_triangles = pfill.load_mesh("cube")
    assert cube_triangles.shape[1] == 3 and np.abs(cube_vertices).max() == pytest.approx(1.0)


def test_errors_are_pfill_errors_with_the_command_lines_messages(tmp_path):
    with pytest.raises(pfill.Error, match="missing.obj"):
        pfill.fill(str(tmp_path / "missing.obj"), count=50)
    with pytest.raises(RuntimeError, match="no particle of radius"):
        pfill.fill("sphere", radius=5)
    with pytest.raises(pfill.Error, match="blocked, ke or collisions"):
        pfill.fill("sphere", count=50, stop="never")
    with pytest.raises(pfill.Error, match="outside the mesh"):
        pfill.fill("sphere", count=50, birth=(5, 0, 0))
    with pytest.raises(pfill.Error, match="three numbers"):
        pfill.fill("sphere", count=50, birth=(5, 0))
    with pytest.raises(pfill.Error, match="exponents must be"):
        pfill.fill("sphere", count=50, exponents=(6, 12))
    with pytest.raises(pfill.Error, match="names vertex 7"):
        pfill.fill((np.zeros((3, 3)), [[0, 1, 7]]), count=50)
    with pytest.raises(pfill.Error, match=r"\(N, 3\)"):
        pfill.check(np.zeros((4, 2)), 0.1, "sphere")
    with pytest.raises(pfill.Error, match="one per particle"):
        pfill.check(np.zeros((4, 3)), [0.1, 0.1], "sphere")
    with pytest.raises(pfill.Error, match="file path"):
        pfill.fill(42)


def test_a_cancel_hook_stops_the_fill_cleanly():
    polls = []

    def cancelled():
        polls.append(1)
        return len(polls) >= 3

    with pytest.raises(pfill.Cancelled):
        pfill.fill("sphere", count=5000, cancelled=cancelled)
    assert len(polls) == 3
    # The module is still usable after a cancelled fill.
    assert len(pfill.fill("cube", count=60, seed=2)) > 30


def test_progress_is_reported_and_its_exceptions_stop_the_fill():
    phases = []

    def progress(p):
        phases.append(p["phase"])
        if p["phase"] == "pass 1" and p["particles"] > 20:
            raise ValueError("enough")

    with pytest.raises(ValueError, match="enough"):
        pfill.fill("sphere", count=5000, progress=progress)
    assert phases[0] == "field" and "pass 1" in phases


def test_other_threads_run_while_a_fill_runs():
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.005)

    thread = threading.Thread(target=tick)
    thread.start()
    try:
        before = len(ticks)
        pfill.fill("cube", count=60, seed=2)
        during = len(ticks) - before
    finally:
        done.set()
        thread.join()
    # A fill of a second or more: a thread that waits 5 ms a tick ticks
    # many times, where a held GIL would let it tick only at the polls.
    assert during >= 20


def test_ctrl_c_interrupts_a_fill():
    # SIGINT from another thread, as a terminal's Ctrl-C: the fill polls
    # Python's signal handlers while it runs without the GIL.
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            pfill.fill("sphere", count=5000)
    finally:
        timer.cancel()


def test_check_measures_a_known_set():
    # Eight spheres of radius 0.5 on a 2x2x2 lattice fill the cube [-1, 1]^3
    # touching each other and the walls: packing pi/6, 3 contacts each.
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    m = pfill.check(corners, 0.5, "cube")
    assert m["particles"] == 8
    assert m["packing_fraction"] == pytest.approx(math.pi / 6, rel=1e-9)
    assert m["contained_share"] == 1.0
    assert m["overlapping_pairs"] == 0
    assert m["mean_coordination"] == pytest.approx(3.0)
    # One more, its centre outside, overlapping a corner sphere by 0.3.
    more = np.vstack([corners, [[1.2, 0.5, 0.5]]])
    m = pfill.check(more, np.full(9, 0.5), "cube")
    assert m["contained_share"] == pytest.approx(8 / 9)
    assert m["centres_outside"] == 1
    assert m["overlapping_pairs"] == 1 and m["max_overlap"] == pytest.approx(0.6)


def test_check_agrees_with_the_fill_metrics(sphere_fill):
    m = pfill.check(sphere_fill.positions, sphere_fill.radii, "sphere")
    assert m["packing_fraction"] == pytest.approx(sphere_fill.metrics["packing_fraction"], rel=1e-12)
    assert m["contained_share"] == sphere_fill.metrics["contained_share"]


def test_devices_lists_one_default():
    devices = pfill.devices()
    assert devices and sum(d["default"] for d in devices) == 1
    assert all(d["name"] and d["compute_units"] >= 1 for d in devices)


def _help_all_flags():
    """The settings' flags `pfill fill --help-all` lists (the output options aside)."""
    out = subprocess.run([CLI, "fill", "--help-all"], capture_output=True, text=True, check=True).stdout
    flags = set()
    for line in out.splitlines():
        for word in line.split():
            for part in word.split(","):
                if part.startswith("--"):
                    flags.add(part)
    return flags


def _doc_settings():
    """The settings pfill.fill's docstring lists, one a line under 'Settings'."""
    doc = pfill.fill.__doc__
    lines = doc[doc.index("Settings (default in brackets):"):].splitlines()[1:]
    return [line.split()[0] for line in lines if line.startswith("  ")]


def test_one_name_per_setting_in_the_cli_python_and_the_docs():
    names = _doc_settings()
    assert len(names) > 30 and len(set(names)) == len(names)
    flags = _help_all_flags()
    for name in names:
        assert "--" + name.replace("_", "-") in flags, name
    # Every keyword is accepted by that name: None leaves each at its default,
    # and the bad count last fails on its value, not on an unknown keyword.
    settings = {name: None for name in names}
    settings["count"] = -5
    with pytest.raises(pfill.Error, match="count '-5' is out of range"):
        pfill.fill("sphere", **settings)
    with pytest.raises(pfill.Error, match="unknown keyword 'void_rounds'"):
        pfill.fill("sphere", count=50, void_rounds=2)


def test_the_short_help_lists_the_users_options_only():
    out = subprocess.run([CLI, "fill", "--help"], capture_output=True, text=True, check=True).stdout
    options = [line for line in out.splitlines() if line.lstrip().startswith("-")]
    assert len(options) <= 26  # 25, and --radii (--radii-by is in --help-all)
    assert "--max-overlap" in out and "--patience" not in out


@pytest.mark.parametrize("settings, words", [
    (dict(count=300, radius=0.05), "not both"),
    (dict(count=300, birth=(math.nan, 0, 0)), "birth"),
    (dict(radius=math.inf), "radius"),
    (dict(count=True), "not True or False"),
    (dict(count=300, exponents=(12, "x")), "exponents"),
])
def test_bad_settings_are_refused_before_the_fill(settings, words):
    with pytest.raises(pfill.Error, match=words):
        pfill.fill("sphere", **settings)


def test_unequal_spheres_follow_the_distribution_asked_for():
    """radii= takes the command line's SPEC: two sizes 1:2, half the number each."""
    r = pfill.fill("sphere", count=300, radii="discrete:1:0.5,2:0.5", seed=2)
    sizes = np.unique(np.round(r.radii, 9))
    assert len(sizes) == 2 and sizes[1] == pytest.approx(2 * sizes[0])
    report = r.report["radii"]
    assert report["spec"] == "discrete:1:0.5,2:0.5"
    small_share = float(np.mean(np.isclose(r.radii, sizes[0])))
    assert report["classes"][0]["number_share"] == pytest.approx(small_share)
    assert abs(small_share - 0.5) <= 0.03
    # overlaps are of the smaller radius, the same by pfill.check
    m = pfill.check(r.positions, r.radii, "sphere")
    assert m["max_overlap"] <= 0.001 + 1e-9
    assert m["max_overlap"] == pytest.approx(r.metrics["max_overlap"], abs=1e-9)
