"""The contact network in Python: FillResult.contacts / .coordination and
pfill.contacts(), against a brute-force search and the command line."""
import json
import os
import subprocess

import numpy as np
import pytest

import pfill

CLI = os.environ.get("PFILL_CLI", "pfill")


def brute_force(positions, radii, gap):
    d = np.sqrt(((positions[:, None, :] - positions[None, :, :]) ** 2).sum(-1))
    touching = d - radii[:, None] - radii[None, :] <= gap * np.minimum(radii[:, None], radii[None, :])
    i, j = np.nonzero(np.triu(touching, 1))
    return set(zip(i.tolist(), j.tolist()))


@pytest.fixture(scope="module")
def cube_fill():
    return pfill.fill("cube", count=200, seed=2)


def test_fill_result_contacts_equal_a_brute_force_search(cube_fill):
    pairs = cube_fill.contacts
    assert pairs.dtype == np.int64 and pairs.ndim == 2 and pairs.shape[1] == 2
    assert (pairs[:, 0] < pairs[:, 1]).all()
    assert set(map(tuple, pairs.tolist())) == brute_force(cube_fill.positions, cube_fill.radii, 0.02)
    c = cube_fill.coordination
    assert c.shape == (len(cube_fill),)
    assert c.sum() == 2 * len(pairs)
    assert c.mean() == pytest.approx(cube_fill.metrics["mean_coordination"], abs=0.1)


def test_contacts_with_a_gap_and_the_wall(cube_fill):
    net = pfill.contacts(cube_fill.positions, cube_fill.radii, gap=0.1, mesh="cube")
    assert set(map(tuple, net["pairs"].tolist())) == brute_force(cube_fill.positions, cube_fill.radii, 0.1)
    assert net["gaps"].shape == (len(net["pairs"]),)
    assert len(net["wall_particles"]) > 0
    # Wall contacts of the cube: the normal is an axis, the point on a face, the sphere within the gap of it.
    n = net["wall_normals"]
    assert np.allclose(np.abs(n).max(axis=1), 1)
    assert np.allclose(np.abs(net["wall_points"]).max(axis=1), 1)
    r = cube_fill.radii[net["wall_particles"]]
    assert (net["wall_gaps"] <= 0.1 * r + 1e-12).all()
    assert net["report"]["wall_contacts"] == len(net["wall_particles"])
    with pytest.raises(pfill.Error, match="contact gap"):
        pfill.contacts(cube_fill.positions, cube_fill.radii, gap=-1)


def test_the_command_line_writes_the_same_pairs(tmp_path):
    r = pfill.fill("cube", count=150, seed=4)
    subprocess.run([CLI, "fill", "cube", "-n", "150", "--seed", "4", "-q", "--contacts", "-o", str(tmp_path / "c.csv"),
                    "--pairs", str(tmp_path / "pairs.csv"), "--report", str(tmp_path / "c.json")],
                   check=True, stdout=subprocess.DEVNULL)
    report = json.loads((tmp_path / "c.json").read_text())
    assert report["contacts"]["pairs"] == len(r.contacts)
    rows = np.loadtxt(tmp_path / "pairs.csv", delimiter=",", skiprows=1)
    pair_rows = rows[rows[:, 1] > 0]
    index_of = {int(i): k for k, i in enumerate(r.ids)}
    cli_pairs = {tuple(sorted((index_of[int(a)], index_of[int(b)]))) for a, b in pair_rows[:, :2]}
    assert cli_pairs == set(map(tuple, r.contacts.tolist()))
    particles = np.loadtxt(tmp_path / "c.csv", delimiter=",", skiprows=1)
    assert particles[:, -1].sum() == 2 * len(r.contacts)  # the coordination column


def test_surface_particles_are_even_and_cover_the_surface():
    s = pfill.surface("sphere", count=500)
    n = len(s["positions"])
    assert 480 <= n <= 520
    assert s["normals"].shape == (n, 3) and s["areas"].shape == (n,)
    assert s["areas"].sum() == pytest.approx(s["surface_area"])
    assert np.allclose(np.linalg.norm(s["normals"], axis=1), 1)
    assert (np.einsum("ij,ij->i", s["normals"], s["positions"]) > 0).all()  # out of the sphere
    shell = s["shell"]
    assert shell["share_within_15_percent"] >= 0.95
    assert shell["closer_than_0.8_spacing"] == 0
    assert shell["coverage_over_r"] <= 1.5
    with pytest.raises(pfill.Error, match="radius"):
        pfill.surface("sphere")


def test_fill_shell_output_reads_back_with_the_kinds_apart(tmp_path):
    subprocess.run([CLI, "fill", "cube", "-n", "150", "-q", "--shell", "-o", str(tmp_path / "f.csv")], check=True,
                   stdout=subprocess.DEVNULL)
    table = np.genfromtxt(tmp_path / "f.csv", delimiter=",", names=True)
    inner, shell = table[table["kind"] == 0], table[table["kind"] == 1]
    assert len(inner) > 50 and len(shell) > 50
    assert (inner["area"] == 0).all() and (shell["area"] > 0).all()
    # Inner spheres clear of every shell particle (to the 0.1% bound) and inside the cube.
    p_in = np.c_[inner["x"], inner["y"], inner["z"]]
    p_sh = np.c_[shell["x"], shell["y"], shell["z"]]
    d = np.sqrt(((p_in[:, None] - p_sh[None]) ** 2).sum(-1))
    assert (d >= (inner["radius"][:, None] + shell["radius"][None]) - 0.001 * inner["radius"][:, None] - 1e-9).all()
    assert (np.abs(p_in).max(axis=1) + inner["radius"] <= 1 + 1e-9).all()


@pytest.mark.parametrize("ext", ["ply", "csv", "vtp", "glb", "xyzr"])
def test_read_particles_gives_a_shells_kinds_apart(tmp_path, ext):
    path = tmp_path / f"f.{ext}"
    subprocess.run([CLI, "fill", "cube", "-n", "150", "-q", "--shell", "-o", str(path)], check=True,
                   stdout=subprocess.DEVNULL)
    table = np.genfromtxt(tmp_path / "f.csv", delimiter=",", names=True) if ext == "csv" else None
    p = pfill.read_particles(str(path))
    kinds = p["kinds"]
    assert kinds is not None and kinds.dtype == np.uint8 and len(kinds) == len(p["positions"])
    inner, shell = kinds == 0, kinds == 1
    assert inner.sum() > 50 and shell.sum() > 50 and (inner | shell).all()
    assert (p["areas"][inner] == 0).all() and (p["areas"][shell] > 0).all()
    assert np.allclose(np.linalg.norm(p["normals"][shell], axis=1), 1, atol=1e-5)
    if table is not None:
        assert (kinds == table["kind"]).all()
    # A file without a shell: no kinds.
    subprocess.run([CLI, "fill", "cube", "-n", "50", "-q", "-o", str(tmp_path / f"g.{ext}")], check=True,
                   stdout=subprocess.DEVNULL)
    plain = pfill.read_particles(str(tmp_path / f"g.{ext}"))
    assert plain["kinds"] is None and plain["normals"] is None and plain["areas"] is None
    assert len(plain["radii"]) == len(plain["positions"])
